//! Closed forms to test the estimators against: irradiance from spheres and polygons, solid
//! angles, the mean of a colour's channels.

use std::f64::consts::PI;

use glam::DVec3;
use picomis::Rgb;

/// Solid angle 2 pi (1 - cos theta_max) of the cone a sphere of radius r subtends at distance d,
/// computed as 2 pi s^2 / (1 + sqrt(1 - s^2)) with s = r/d (accurate for tiny r/d).
pub fn cone_measure(r_over_d: f64) -> f64 {
    let s2 = r_over_d * r_over_d;
    2.0 * PI * s2 / (1.0 + (1.0 - s2).sqrt())
}

/// Irradiance from a sphere of radiance `radiance` and radius `r`, centre at distance `d`,
/// whose centre is `theta` off the receiver's normal and fully above its horizon:
/// E = pi L (r/d)^2 cos(theta).
pub fn sphere_irradiance(radiance: f64, r: f64, d: f64, cos_theta: f64) -> f64 {
    assert!(cos_theta >= r / d - 1e-12, "sphere not fully above the horizon");
    PI * radiance * (r / d) * (r / d) * cos_theta
}

/// Irradiance at `x` (unit normal `n`) from a sphere light of radiance `radiance`, centre `c`
/// and radius `r`, fully above the horizon of `x` ([`sphere_irradiance`] in any position).
pub fn sphere_irradiance_at(x: DVec3, n: DVec3, c: DVec3, r: f64, radiance: f64) -> f64 {
    let v = c - x;
    let d = v.length();
    sphere_irradiance(radiance, r, d, n.dot(v) / d)
}

/// Irradiance at `x` (unit normal `n`) from a convex polygon of constant `radiance` entirely
/// above the horizon, by Lambert's formula E = (L/2) |sum_k acos(v_k . v_k+1) n . normalize(v_k x
/// v_k+1)| with v_k the unit vectors to the vertices (either winding).
pub fn lambert_polygon_irradiance(x: DVec3, n: DVec3, verts: &[DVec3], radiance: f64) -> f64 {
    let k = verts.len();
    let mut sum = 0.0f64;
    for i in 0..k {
        let a = (verts[i] - x).normalize();
        let b = (verts[(i + 1) % k] - x).normalize();
        let angle = a.dot(b).clamp(-1.0, 1.0).acos();
        sum += angle * n.dot(a.cross(b).normalize());
    }
    0.5 * radiance * sum.abs()
}

/// Solid angle of a convex planar polygon seen from `x`: a fan of triangles, each by Van
/// Oosterom and Strackee's formula tan(Omega/2) = |a.(b x c)| / (abc + (a.b)c + (a.c)b + (b.c)a).
pub fn polygon_solid_angle(x: DVec3, verts: &[DVec3]) -> f64 {
    let tri = |a: DVec3, b: DVec3, c: DVec3| {
        let (la, lb, lc) = (a.length(), b.length(), c.length());
        let num = a.dot(b.cross(c)).abs();
        let den = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
        2.0 * num.atan2(den)
    };
    (1..verts.len() - 1).map(|i| tri(verts[0] - x, verts[i] - x, verts[i + 1] - x)).sum()
}

/// The mean of a colour's channels in f64 (the kernel's light selection weighs colours by it).
pub fn channel_mean(c: Rgb) -> f64 {
    (f64::from(c.x) + f64::from(c.y) + f64::from(c.z)) / 3.0
}

/// The three channels of a colour in f64.
pub fn rgb64(c: Rgb) -> [f64; 3] {
    [f64::from(c.x), f64::from(c.y), f64::from(c.z)]
}

/// f cos(theta_i) of a GGX conductor of reflectance `r` (Fresnel one) whose normal is +y, in f64
/// (free of f32's rounding): R D(m) G1(wo) G1(wi) / (4 cos_o), GGX's D and Smith's G1 of the
/// roughness `alpha`, for unit `wo` and `wi`; 0 where either is below the surface or the half
/// vector is.
pub fn ggx_f_cos(wo: DVec3, wi: DVec3, alpha: f64, r: f64) -> f64 {
    let m = (wo + wi).normalize();
    if m.y <= 0.0 || wi.y <= 0.0 || wo.y <= 0.0 {
        return 0.0;
    }
    let a2 = alpha * alpha;
    let g1 = |c: f64| 2.0 * c / (c + (a2 + (1.0 - a2) * c * c).sqrt());
    let t = (m.x * m.x + m.z * m.z) / a2 + m.y * m.y;
    r / (PI * a2 * t * t) * g1(wo.y) * g1(wi.y) / (4.0 * wo.y)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::histogram::integrate_cell;

    /// The f64 GGX model is the kernel's `Material::eval` without f32's rounding, and zero
    /// below the surface.
    #[test]
    fn ggx_f_cos_is_the_kernels_eval() {
        for alpha in [0.01f32, 0.1, 0.5] {
            let m = picomis::Material::ggx_conductor(alpha, Rgb::splat(0.9)).unwrap();
            for (wo, wi) in [
                (DVec3::new(0.3, 0.9, -0.2), DVec3::new(-0.28, 0.92, 0.21)),
                (DVec3::new(0.6, 0.5, 0.1), DVec3::new(-0.5, 0.6, -0.2)),
                (DVec3::new(0.0, 1.0, 0.0), DVec3::new(0.1, 0.99, 0.0)),
            ] {
                let (wo, wi) = (wo.normalize(), wi.normalize());
                let model = ggx_f_cos(wo, wi, f64::from(alpha), 0.9);
                // The kernel's local frame: normal +z.
                let local = |v: DVec3| picomis::Vec3::new(v.x as f32, v.z as f32, v.y as f32);
                let kernel = f64::from(m.eval(local(wo), local(wi)).x);
                assert!(model > 0.0 && (kernel / model - 1.0).abs() < 1e-4, "{alpha}: {kernel} vs {model}");
            }
            let below = DVec3::new(0.2, -0.5, 0.1).normalize();
            assert_eq!(ggx_f_cos(DVec3::Y, below, f64::from(alpha), 0.9), 0.0);
        }
    }

    /// Irradiance from a parallelogram by brute-force quadrature over its area, in f64:
    /// E = L integral cos_x cos_y / r^2 dA.
    fn quad_irradiance_by_quadrature(x: DVec3, n: DVec3, p0: DVec3, e1: DVec3, e2: DVec3, l: f64) -> f64 {
        let ny = e1.cross(e2).normalize();
        let area = e1.cross(e2).length();
        let f = |s: f64, t: f64| {
            let y = p0 + e1 * s + e2 * t;
            let v = y - x;
            let d2 = v.length_squared();
            let d = d2.sqrt();
            l * n.dot(v).max(0.0) / d * ny.dot(-v).abs() / d / d2
        };
        let mut sum = 0.0;
        let k = 16;
        for i in 0..k {
            for j in 0..k {
                let a = [i as f64 / k as f64, (i + 1) as f64 / k as f64];
                let b = [j as f64 / k as f64, (j + 1) as f64 / k as f64];
                sum += integrate_cell(&f, a, b, 2);
            }
        }
        sum * area
    }

    #[test]
    fn lambert_formula_matches_quadrature() {
        let x = DVec3::new(0.1, 0.0, -0.2);
        let n = DVec3::Y;
        for (p0, e1, e2) in [
            (DVec3::new(-0.5, 1.0, -0.5), DVec3::X, DVec3::Z),
            (DVec3::new(0.3, 2.0, 0.1), DVec3::new(1.5, 0.4, 0.0), DVec3::new(0.0, 0.3, -1.0)),
            (DVec3::new(-3.0, 0.5, -3.0), DVec3::new(6.0, 0.0, 0.0), DVec3::new(0.0, 0.0, 6.0)),
        ] {
            let verts = [p0, p0 + e1, p0 + e1 + e2, p0 + e2];
            let lambert = lambert_polygon_irradiance(x, n, &verts, 2.0);
            let mut rev = verts;
            rev.reverse();
            assert!((lambert_polygon_irradiance(x, n, &rev, 2.0) - lambert).abs() < 1e-12);
            let quad = quad_irradiance_by_quadrature(x, n, p0, e1, e2, 2.0);
            assert!((lambert / quad - 1.0).abs() < 1e-6, "{lambert} vs {quad}");
        }
        // A huge square close above: E -> pi L.
        let big = [
            DVec3::new(-1e4, 1.0, -1e4),
            DVec3::new(1e4, 1.0, -1e4),
            DVec3::new(1e4, 1.0, 1e4),
            DVec3::new(-1e4, 1.0, 1e4),
        ];
        assert!((lambert_polygon_irradiance(DVec3::ZERO, n, &big, 1.0) / PI - 1.0).abs() < 1e-3);
    }

    #[test]
    fn solid_angle_formula_matches_quadrature() {
        let x = DVec3::new(0.2, -0.1, 0.0);
        let (p0, e1, e2) =
            (DVec3::new(-0.4, 1.0, -0.3), DVec3::new(1.2, 0.2, 0.0), DVec3::new(0.1, 0.0, 0.9));
        let ny = e1.cross(e2).normalize();
        let area = e1.cross(e2).length();
        let f = |s: f64, t: f64| {
            let v = p0 + e1 * s + e2 * t - x;
            ny.dot(v).abs() / v.length().powi(3)
        };
        let quad = integrate_cell(&f, [0.0, 1.0], [0.0, 1.0], 32) * area;
        let formula = polygon_solid_angle(x, &[p0, p0 + e1, p0 + e1 + e2, p0 + e2]);
        assert!((formula / quad - 1.0).abs() < 1e-9, "{formula} vs {quad}");
        // A whole hemisphere: a huge square just above.
        let big = [
            DVec3::new(-1e5, 1e-3, -1e5),
            DVec3::new(1e5, 1e-3, -1e5),
            DVec3::new(1e5, 1e-3, 1e5),
            DVec3::new(-1e5, 1e-3, 1e5),
        ];
        assert!((polygon_solid_angle(DVec3::ZERO, &big) / (2.0 * PI) - 1.0).abs() < 1e-6);
    }

    #[test]
    fn cone_measure_is_accurate() {
        let r = 0.5f64;
        let naive = 2.0 * PI * (1.0 - (1.0 - r * r).sqrt());
        assert!((cone_measure(r) / naive - 1.0).abs() < 1e-14);
        assert!((cone_measure(1e-6) / (PI * 1e-12) - 1.0).abs() < 1e-11);
    }
}
