//! Warps of the unit square onto disks, hemispheres, spheres, cones and parallelograms, and
//! the linear and bilinear warps, each with its pdf.

use crate::num::{
    INV_PI, PI, Vec2, Vec3, clamp, magnitude_bits, max0, safe_sqrt, sin_cos_eighths, sin_cos_turns, sqrt,
};

/// Concentric map of the unit square to the unit disk (Shirley and Chiu 1997).
#[inline]
pub fn sample_concentric_disk(u: Vec2) -> Vec2 {
    let o = u * 2.0 - Vec2::ONE;
    // The comparisons of magnitudes on the bits (the same answers for values that are not NaN;
    // on a soft-float core no comparison routine).
    let (mx, my) = (magnitude_bits(o.x), magnitude_bits(o.y));
    if mx == 0 && my == 0 {
        return Vec2::ZERO;
    }
    // theta = pi/4 (y/x) in the left and right wedges, pi/2 - pi/4 (x/y) in the others:
    // only sines and cosines of |angle| <= pi/4 are needed.
    let (r, s, c) = if mx > my {
        let (s, c) = sin_cos_eighths(o.y / o.x);
        (o.x, s, c)
    } else {
        let (s, c) = sin_cos_eighths(o.x / o.y);
        (o.y, c, s)
    };
    Vec2::new(c, s) * r
}

/// Cosine-weighted direction on the upper hemisphere (Malley's method).
#[inline]
pub fn sample_cosine_hemisphere(u: Vec2) -> Vec3 {
    let d = sample_concentric_disk(u);
    Vec3::new(d.x, d.y, safe_sqrt(1.0 - d.x * d.x - d.y * d.y))
}

/// Pdf of [`sample_cosine_hemisphere`]: cos(theta) / pi on the upper hemisphere, else 0.
#[inline]
pub fn cosine_hemisphere_pdf(cos_theta: f32) -> f32 {
    if cos_theta > 0.0 { cos_theta * INV_PI } else { 0.0 }
}

/// Uniform direction on the unit sphere (also: a uniform point on a sphere of any radius).
#[inline]
pub fn sample_uniform_sphere(u: Vec2) -> Vec3 {
    let z = 1.0 - 2.0 * u.x;
    let r = safe_sqrt(1.0 - z * z);
    let (s, c) = sin_cos_turns(u.y);
    Vec3::new(r * c, r * s, z)
}

/// Pdf of [`sample_uniform_sphere`] per unit solid angle: 1 / (4 pi).
#[inline]
pub fn uniform_sphere_pdf() -> f32 {
    0.25 * INV_PI
}

/// `1 - cos(theta_max)` of the cone that a sphere subtends, from `sin^2(theta_max) = r^2 / d^2`,
/// computed as `sin^2 / (1 + cos)`: exact to f32 precision down to r/d = 1e-6, where the naive
/// `1 - sqrt(1 - sin^2)` rounds to zero. Sampling and pdf both call this one routine.
#[inline]
pub fn cone_one_minus_cos(sin2_theta_max: f32) -> f32 {
    let sin2 = if sin2_theta_max < 1.0 { max0(sin2_theta_max) } else { 1.0 };
    sin2 / (1.0 + safe_sqrt(1.0 - sin2))
}

/// Uniform direction inside the cone around local `z` with the given `1 - cos(theta_max)`,
/// through the concentric disk (the low-distortion map Mitsuba 3 uses too): a uniform point `p`
/// on the unit disk has `|p|^2` uniform in [0, 1], so `1 - cos(theta) = |p|^2 (1 - cos(theta_max))`
/// and the azimuth is `p`'s. Neighbouring `u` stay neighbouring directions, so a stratified `u`
/// stays stratified on the cone (the polar map squeezes one row of strata into the axis).
#[inline]
pub fn sample_uniform_cone(u: Vec2, one_minus_cos_max: f32) -> Vec3 {
    let p = sample_concentric_disk(u);
    // 1 - cos(theta), kept in that form for precision.
    let one_minus_cos = (p.x * p.x + p.y * p.y) * one_minus_cos_max;
    // sin(theta) / |p| = sqrt((1 - cos_max) (2 - (1 - cos))).
    let k = safe_sqrt(one_minus_cos_max * (2.0 - one_minus_cos));
    Vec3::new(p.x * k, p.y * k, 1.0 - one_minus_cos)
}

/// Pdf of [`sample_uniform_cone`] per unit solid angle: 1 / (2 pi (1 - cos theta_max)).
#[inline]
pub fn uniform_cone_pdf(one_minus_cos_max: f32) -> f32 {
    if one_minus_cos_max > 0.0 { 1.0 / (2.0 * PI * one_minus_cos_max) } else { 0.0 }
}

/// Uniform point on the parallelogram `p0 + s e1 + t e2`, as its (s, t) coordinates.
#[inline]
pub fn sample_parallelogram(u: Vec2) -> Vec2 {
    u
}

/// Pdf of [`sample_parallelogram`] per unit area: 1 / area.
#[inline]
pub fn parallelogram_pdf(area: f32) -> f32 {
    if area > 0.0 { 1.0 / area } else { 0.0 }
}

/// The largest f32 below 1: samples on [0, 1) stay below it.
pub const ONE_MINUS_EPSILON: f32 = 1.0 - f32::EPSILON / 2.0;

/// A point of [0, 1) with density proportional to (1 - x) a + x b (`a`, `b` finite and
/// non-negative; uniform when both are 0), by inverting its cdf:
/// x = u (a + b) / (a + sqrt((1 - u) a^2 + u b^2)) (pbrt-v4's `SampleLinear`).
#[inline]
pub fn sample_linear(u: f32, a: f32, b: f32) -> f32 {
    let sum = a + b;
    if !(sum > 0.0) {
        return clamp(u, 0.0, ONE_MINUS_EPSILON);
    }
    let denominator = a + sqrt((1.0 - u) * (a * a) + u * (b * b));
    let x = if denominator > 0.0 { u * sum / denominator } else { 0.0 };
    clamp(x, 0.0, ONE_MINUS_EPSILON)
}

/// Pdf of [`sample_linear`]: 2 ((1 - x) a + x b) / (a + b) on [0, 1] (1 when a + b = 0), else 0.
#[inline]
pub fn linear_pdf(x: f32, a: f32, b: f32) -> f32 {
    let sum = a + b;
    if !(0.0..=1.0).contains(&x) {
        0.0
    } else if !(sum > 0.0) {
        1.0
    } else {
        2.0 * ((1.0 - x) * a + x * b) / sum
    }
}

/// A point of [0, 1)^2 with density proportional to the bilinear interpolation of the corner
/// values `w` at (0, 0), (1, 0), (0, 1) and (1, 1) (finite, non-negative): y from its marginal,
/// then x given y, each by [`sample_linear`] (pbrt-v4's `SampleBilinear`).
#[inline]
pub fn sample_bilinear(u: Vec2, w: [f32; 4]) -> Vec2 {
    let [w00, w10, w01, w11] = w;
    let y = sample_linear(u.y, w00 + w10, w01 + w11);
    let x = sample_linear(u.x, (1.0 - y) * w00 + y * w01, (1.0 - y) * w10 + y * w11);
    Vec2::new(x, y)
}

/// Pdf of [`sample_bilinear`] on the unit square: 4 bilerp(w; p) / (w00 + w10 + w01 + w11)
/// (1 when every weight is 0), 0 outside it.
#[inline]
pub fn bilinear_pdf(p: Vec2, w: [f32; 4]) -> f32 {
    let [w00, w10, w01, w11] = w;
    let (x, y) = (p.x, p.y);
    let sum = (w00 + w10) + (w01 + w11);
    if !((0.0..=1.0).contains(&x) && (0.0..=1.0).contains(&y)) {
        0.0
    } else if !(sum > 0.0) {
        1.0
    } else {
        let bilerp = (1.0 - y) * ((1.0 - x) * w00 + x * w10) + y * ((1.0 - x) * w01 + x * w11);
        4.0 * bilerp / sum
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cone_measure_is_exact_for_tiny_spheres() {
        // r/d = 1e-6: 1 - cos = 5e-13 (the naive form gives 0).
        let r_over_d = 1e-6f32;
        let v = cone_one_minus_cos(r_over_d * r_over_d);
        assert!((v / 5e-13 - 1.0).abs() < 1e-5, "{v}");
        assert!(uniform_cone_pdf(v).is_finite());
        // Full hemisphere when the sphere touches the point.
        assert_eq!(cone_one_minus_cos(1.0), 1.0);
    }

    #[test]
    fn cone_samples_stay_inside_the_cone() {
        let omc = cone_one_minus_cos(0.25);
        for i in 0..64 {
            for j in 0..64 {
                let u = Vec2::new(i as f32 / 64.0, j as f32 / 64.0);
                let w = sample_uniform_cone(u, omc);
                assert!(w.z >= 1.0 - omc - 1e-6);
                assert!((w.length() - 1.0).abs() < 1e-5);
            }
        }
    }

    #[test]
    fn bilinear_samples_follow_their_pdf() {
        // The pdf integrates to one, and the samples of a 64 x 64 grid of u land with the pdf's
        // mass per quadrant (to the grid's resolution).
        for w in [[0.01, 1.0, 0.5, 0.2], [1.0, 1.0, 1.0, 1.0], [0.0, 0.0, 0.0, 3.0], [0.0; 4]] {
            let n = 200;
            let mut integral = 0.0;
            for i in 0..n {
                for j in 0..n {
                    let p = Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
                    integral += bilinear_pdf(p, w) / (n * n) as f32;
                }
            }
            assert!((integral - 1.0).abs() < 1e-3, "{w:?}: {integral}");
            let mut left = 0.0;
            for i in 0..64 {
                for j in 0..64 {
                    let p = sample_bilinear(Vec2::new((i as f32 + 0.5) / 64.0, (j as f32 + 0.5) / 64.0), w);
                    assert!((0.0..1.0).contains(&p.x) && (0.0..1.0).contains(&p.y), "{w:?}: {p}");
                    left += f32::from(p.x < 0.5) / 4096.0;
                }
            }
            let sum: f32 = w.iter().sum();
            let expected = if sum > 0.0 { (0.75 * (w[0] + w[2]) + 0.25 * (w[1] + w[3])) / sum } else { 0.5 };
            assert!((left - expected).abs() < 0.02, "{w:?}: {left} vs {expected}");
        }
        assert_eq!(bilinear_pdf(Vec2::new(1.5, 0.5), [1.0; 4]), 0.0);
        assert_eq!(sample_linear(0.0, 0.0, 1.0), 0.0);
        assert!(sample_linear(0.999_999_94, 1.0, 0.0) < 1.0);
    }
}
