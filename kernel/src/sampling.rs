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

/// How many equally likely values a random number from
/// [`Sampler::next_f32`](crate::rng::Sampler::next_f32) takes: its 24 bits, 2^24.
pub const GRID: u32 = 1 << 24;

/// A discrete distribution on the grid of the random number it is sampled with: entry `i` owns
/// a run of the 2^24 equally likely values of `u`, so the probability [`GridDistribution::pmf`]
/// reports is exactly the one [`GridDistribution::sample`] realises. Every positive weight gets
/// at least one value: a share rounded to none would never be drawn while its pmf still lowered
/// the other technique's MIS weights (a bias).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct GridDistribution<const N: usize> {
    /// Where each entry's run of grid values ends (cumulative); empty when no weight is positive.
    ends: heapless::Vec<u32, N>,
}

impl<const N: usize> GridDistribution<N> {
    /// The distribution proportional to `weights` (at most `N` are read); entries whose weight is
    /// not positive get no value. Empty (it samples nothing) when the weights do not have a
    /// positive, finite sum.
    pub fn new(weights: &[f32]) -> Self {
        let mut ends = heapless::Vec::new();
        let weights = weights.get(..N).unwrap_or(weights);
        let total: f32 = weights.iter().filter(|w| **w > 0.0).sum();
        if !(total > 0.0 && total.is_finite()) {
            return Self { ends };
        }
        // Each share rounded to the grid, at least one value if positive; the rounding difference
        // (at most N values either way) goes to the largest entry, which has at least GRID / N.
        let scale = GRID as f32 / total;
        let cells = |w: f32| if w > 0.0 { ((w * scale + 0.5) as u32).clamp(1, GRID) } else { 0 };
        let mut sum = 0u32;
        let mut largest = (0, 0);
        for (i, &w) in weights.iter().enumerate() {
            let c = cells(w);
            sum += c;
            if c > largest.1 {
                largest = (i, c);
            }
        }
        let mut end = 0u32;
        for (i, &w) in weights.iter().enumerate() {
            let c = if i == largest.0 { (largest.1 + GRID).saturating_sub(sum) } else { cells(w) };
            end += c;
            // `weights` has at most N entries.
            let _ = ends.push(end);
        }
        Self { ends }
    }

    /// True when nothing can be sampled (no positive weight).
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.ends.last().is_none_or(|&end| end == 0)
    }

    /// The entry owning the grid value of `u` in [0, 1), and its probability.
    #[inline]
    pub fn sample(&self, u: f32) -> Option<(usize, f32)> {
        // u = k / 2^24 exactly for the sampler's numbers; others are clamped into the grid.
        let k = ((u * GRID as f32) as u32).min(GRID - 1);
        let i = self.ends.iter().position(|&end| k < end)?;
        Some((i, self.pmf(i)))
    }

    /// The probability of entry `i` under [`GridDistribution::sample`]: its share of the grid.
    #[inline]
    pub fn pmf(&self, i: usize) -> f32 {
        let start = match i.checked_sub(1) {
            Some(j) => self.ends.get(j).copied().unwrap_or(0),
            None => 0,
        };
        match self.ends.get(i) {
            Some(&end) => (end - start) as f32 * (1.0 / GRID as f32),
            None => 0.0,
        }
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
    fn grid_distributions_realise_their_pmf_exactly() {
        // Shares from 1 down to 1e-14: each positive weight gets at least one grid value.
        let w = [0.0, 1e5, 1e-9, 3.0, 0.0, 1e-3];
        let d = GridDistribution::<6>::new(&w);
        let mut counts = [0u32; 6];
        for k in 0..GRID {
            let (i, p) = d.sample(k as f32 / GRID as f32).unwrap();
            assert_eq!(p, d.pmf(i));
            counts[i] += 1;
        }
        for (i, c) in counts.iter().enumerate() {
            assert_eq!(*c as f32 / GRID as f32, d.pmf(i), "entry {i}");
            assert_eq!(*c > 0, w[i] > 0.0, "entry {i}");
        }
        assert_eq!(counts.iter().sum::<u32>(), GRID);
        assert!(GridDistribution::<2>::new(&[0.0, -1.0]).is_empty());
        assert!(GridDistribution::<2>::new(&[f32::INFINITY, 1.0]).is_empty());
        assert_eq!(GridDistribution::<2>::new(&[0.0]).sample(0.5), None);
        assert_eq!(d.pmf(9), 0.0);
    }
}
