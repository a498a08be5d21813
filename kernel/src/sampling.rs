//! Every sampling routine with its pdf, as `sample_x` / `x_pdf` pairs. Random numbers come in as
//! `u`; directions are in a local frame whose `z` axis is the normal (or the cone axis).
//! Pdfs are per unit solid angle for directions and per unit area for points.

use crate::math::{
    INV_PI, PI, Vec2, Vec3, max0, normalize_or, safe_sqrt, sin_cos_quarter, sin_cos_turns, sqrt,
};

/// Concentric map of the unit square to the unit disk (Shirley and Chiu 1997).
#[inline]
pub fn sample_concentric_disk(u: Vec2) -> Vec2 {
    let o = u * 2.0 - Vec2::ONE;
    if o.x == 0.0 && o.y == 0.0 {
        return Vec2::ZERO;
    }
    // theta = pi/4 (y/x) in the left and right wedges, pi/2 - pi/4 (x/y) in the others:
    // only sines and cosines of |angle| <= pi/4 are needed.
    let (r, s, c) = if o.x.abs() > o.y.abs() {
        let (s, c) = sin_cos_quarter((PI / 4.0) * (o.y / o.x));
        (o.x, s, c)
    } else {
        let (s, c) = sin_cos_quarter((PI / 4.0) * (o.x / o.y));
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

/// Uniform direction inside the cone around local `z` with the given `1 - cos(theta_max)`.
#[inline]
pub fn sample_uniform_cone(u: Vec2, one_minus_cos_max: f32) -> Vec3 {
    // 1 - cos(theta) is uniform in [0, 1 - cos(theta_max)]; keep it in that form for precision.
    let one_minus_cos = u.x * one_minus_cos_max;
    let cos_theta = 1.0 - one_minus_cos;
    let sin_theta = safe_sqrt(one_minus_cos * (2.0 - one_minus_cos));
    let (s, c) = sin_cos_turns(u.y);
    Vec3::new(sin_theta * c, sin_theta * s, cos_theta)
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

/// GGX normal distribution D(m) for isotropic `alpha`, `m` in the local frame.
/// Written as 1 / (pi a^2 (m_z^2 + (m_x^2 + m_y^2)/a^2)^2), which neither overflows nor loses
/// precision for alpha down to 1e-4.
#[inline]
pub fn ggx_d(m: Vec3, alpha: f32) -> f32 {
    if m.z <= 0.0 {
        return 0.0;
    }
    let a2 = alpha * alpha;
    let t = (m.x * m.x + m.y * m.y) / a2 + m.z * m.z;
    1.0 / (PI * a2 * t * t)
}

/// Smith masking G1(v) for GGX: 2 / (1 + sqrt(1 + a^2 tan^2 theta_v)), 0 below the horizon.
#[inline]
pub fn ggx_g1(v: Vec3, alpha: f32) -> f32 {
    if v.z <= 0.0 {
        return 0.0;
    }
    let tan2 = (v.x * v.x + v.y * v.y) / (v.z * v.z);
    2.0 / (1.0 + safe_sqrt(1.0 + alpha * alpha * tan2))
}

/// Microfacet normal from the GGX distribution of normals visible from `wo` (Heitz 2018).
/// `wo` must be in the upper hemisphere.
#[inline]
pub fn sample_ggx_vndf(wo: Vec3, alpha: f32, u: Vec2) -> Vec3 {
    // Stretch the view direction to the hemisphere configuration.
    let vh = normalize_or(Vec3::new(alpha * wo.x, alpha * wo.y, wo.z), Vec3::Z);
    let lensq = vh.x * vh.x + vh.y * vh.y;
    let t1 = if lensq > 0.0 { Vec3::new(-vh.y, vh.x, 0.0) * (1.0 / sqrt(lensq)) } else { Vec3::X };
    let t2 = vh.cross(t1);
    // Uniform point on the disk, warped to the visible half.
    let r = sqrt(u.x);
    let (s, c) = sin_cos_turns(u.y);
    let p1 = r * c;
    let s_mix = 0.5 * (1.0 + vh.z);
    let p2 = (1.0 - s_mix) * safe_sqrt(1.0 - p1 * p1) + s_mix * (r * s);
    let nh = t1 * p1 + t2 * p2 + vh * safe_sqrt(1.0 - p1 * p1 - p2 * p2);
    // Unstretch.
    normalize_or(Vec3::new(alpha * nh.x, alpha * nh.y, max0(nh.z)), Vec3::Z)
}

/// Pdf of [`sample_ggx_vndf`] per unit solid angle of microfacet normals:
/// D_wo(m) = G1(wo) max(0, wo.m) D(m) / cos(theta_o).
#[inline]
pub fn ggx_vndf_pdf(wo: Vec3, m: Vec3, alpha: f32) -> f32 {
    if wo.z <= 0.0 {
        return 0.0;
    }
    ggx_g1(wo, alpha) * max0(wo.dot(m)) * ggx_d(m, alpha) / wo.z
}

/// The largest f32 below one: remapped numbers are clamped to it, so they stay in [0, 1).
pub const ONE_MINUS_EPSILON: f32 = 1.0 - f32::EPSILON / 2.0;

/// A chosen index, its probability, and the random number that chose it rescaled to [0, 1)
/// within the index's interval, so it can be used again (a 2-D sample then stays stratified
/// across the choice and the rest of the sample).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DiscreteSample {
    /// The index.
    pub index: usize,
    /// Its probability.
    pub prob: f32,
    /// `(u - cdf(index - 1)) / prob`, in [0, 1).
    pub u_remapped: f32,
}

/// Picks index `i` with probability `weights[i] / total` by a linear scan (small light lists).
/// `None` when no weight is positive.
#[inline]
pub fn sample_discrete(weights: &[f32], total: f32, u: f32) -> Option<DiscreteSample> {
    if !(total > 0.0) || !total.is_finite() {
        return None;
    }
    let target = u * total;
    let mut acc = 0.0;
    let mut last = None;
    for (i, &w) in weights.iter().enumerate() {
        if w > 0.0 {
            let below = acc;
            acc += w;
            let u_remapped = ((target - below) / w).clamp(0.0, ONE_MINUS_EPSILON);
            last = Some(DiscreteSample { index: i, prob: w / total, u_remapped });
            if target < acc {
                return last;
            }
        }
    }
    // Rounding can leave `target` just above the last partial sum: take the last positive entry.
    last
}

/// Picks one of `n` indices uniformly; `None` when `n` is 0.
#[inline]
pub fn sample_uniform_index(n: usize, u: f32) -> Option<DiscreteSample> {
    if n == 0 {
        return None;
    }
    let scaled = u * n as f32;
    let index = (scaled as usize).min(n - 1);
    let u_remapped = (scaled - index as f32).clamp(0.0, ONE_MINUS_EPSILON);
    Some(DiscreteSample { index, prob: 1.0 / n as f32, u_remapped })
}

/// Probability of index `i` under [`sample_discrete`].
#[inline]
pub fn discrete_pdf(weights: &[f32], total: f32, i: usize) -> f32 {
    match weights.get(i) {
        Some(&w) if w > 0.0 && total > 0.0 && total.is_finite() => w / total,
        _ => 0.0,
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
    fn ggx_is_finite_at_tiny_alpha_and_grazing_angles() {
        let wo = Vec3::new(1.0, 0.0, 1e-6).normalize();
        for alpha in [1e-4f32, 1e-2, 1.0] {
            let m = sample_ggx_vndf(wo, alpha, Vec2::new(0.3, 0.7));
            assert!(m.is_finite() && m.z >= 0.0);
            assert!(ggx_d(m, alpha).is_finite());
            assert!(ggx_vndf_pdf(wo, m, alpha).is_finite());
            assert!(ggx_d(Vec3::Z, alpha).is_finite());
        }
    }

    #[test]
    fn discrete_sampling_returns_positive_entries_only() {
        let w = [0.0, 2.0, 0.0, 1.0];
        let pick = |u| sample_discrete(&w, 3.0, u).map(|d| (d.index, d.prob, d.u_remapped));
        assert_eq!(pick(0.0), Some((1, 2.0 / 3.0, 0.0)));
        assert_eq!(pick(0.5), Some((1, 2.0 / 3.0, 0.75)));
        assert_eq!(pick(0.9), Some((3, 1.0 / 3.0, 0.6999998)));
        assert_eq!(pick(0.999_999_9), Some((3, 1.0 / 3.0, 0.9999995)));
        let uniform = |u| sample_uniform_index(4, u).map(|d| (d.index, d.prob, d.u_remapped));
        assert_eq!(uniform(0.0), Some((0, 0.25, 0.0)));
        assert_eq!(uniform(0.625), Some((2, 0.25, 0.5)));
        assert_eq!(uniform(ONE_MINUS_EPSILON), Some((3, 0.25, 0.99999976)));
        assert_eq!(sample_uniform_index(0, 0.5), None);
        assert_eq!(sample_discrete(&[0.0], 0.0, 0.5), None);
        assert_eq!(discrete_pdf(&w, 3.0, 0), 0.0);
        assert_eq!(discrete_pdf(&w, 3.0, 9), 0.0);
    }
}
