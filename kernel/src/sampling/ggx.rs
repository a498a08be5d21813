//! The GGX microfacet distribution: D, G1 and its visible normals.

use crate::num::{PI, Vec2, Vec3, max0, normalize_or, safe_sqrt, sin_cos_turns, sqrt};

/// An isotropic GGX roughness with the powers of alpha that [`GgxAlpha::d`] and
/// [`GgxAlpha::g1`] use, computed once (a shading point evaluates D and G1 several times).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GgxAlpha {
    /// alpha.
    pub alpha: f32,
    /// alpha^2.
    a2: f32,
    /// 1 - alpha^2.
    one_minus_a2: f32,
    /// pi alpha^2.
    pi_a2: f32,
}

impl GgxAlpha {
    /// The roughness `alpha`.
    #[inline]
    pub fn new(alpha: f32) -> Self {
        let a2 = alpha * alpha;
        Self { alpha, a2, one_minus_a2: 1.0 - a2, pi_a2: PI * a2 }
    }

    /// The normal distribution D(m), `m` in the local frame. Written as
    /// 1 / (pi a^2 (m_z^2 + (m_x^2 + m_y^2)/a^2)^2), which neither overflows nor loses precision
    /// for alpha down to 1e-4.
    #[inline]
    pub fn d(&self, m: Vec3) -> f32 {
        if m.z <= 0.0 {
            return 0.0;
        }
        let t = (m.x * m.x + m.y * m.y) / self.a2 + m.z * m.z;
        1.0 / (self.pi_a2 * t * t)
    }

    /// Smith masking G1(v): 2 / (1 + sqrt(1 + a^2 tan^2 theta_v)), 0 below the horizon; for
    /// the unit `v`, with tan^2 = (1 - cos^2) / cos^2, as 2 cos / (cos + sqrt(a^2 + (1 - a^2)
    /// cos^2)): no cancellation (a sum of positive terms under the root), one division.
    #[inline]
    pub fn g1(&self, v: Vec3) -> f32 {
        if v.z <= 0.0 {
            return 0.0;
        }
        (v.z + v.z) / (v.z + sqrt(self.a2 + self.one_minus_a2 * (v.z * v.z)))
    }
}

/// GGX normal distribution D(m) for isotropic `alpha`, `m` in the local frame ([`GgxAlpha::d`]).
#[inline]
pub fn ggx_d(m: Vec3, alpha: f32) -> f32 {
    GgxAlpha::new(alpha).d(m)
}

/// Smith masking G1(v) for GGX ([`GgxAlpha::g1`]), 0 below the horizon.
#[inline]
pub fn ggx_g1(v: Vec3, alpha: f32) -> f32 {
    GgxAlpha::new(alpha).g1(v)
}

/// Microfacet normal from the GGX distribution of normals visible from `wo`, by spherical caps
/// (Dupuy and Benyoub 2023, "Sampling Visible GGX Normals with Spherical Caps"): in the
/// stretched configuration, where the roughness is one, the visible normals are the directions
/// `c + v` for `c` uniform on the cap of the unit sphere with `z > -v.z` (`v` the stretched
/// `wo`); unstretching gives the sample. The same distribution as Heitz's (2018) construction
/// with a tangent frame, in about half the operations. `wo` must be in the upper hemisphere.
#[inline]
pub fn sample_ggx_vndf(wo: Vec3, alpha: f32, u: Vec2) -> Vec3 {
    // Stretch the view direction to the hemisphere configuration.
    let v = normalize_or(Vec3::new(alpha * wo.x, alpha * wo.y, wo.z), Vec3::Z);
    // A uniform direction c on the spherical cap z in (-v.z, 1]: z uniform, azimuth uniform.
    let z = (1.0 - u.x) * (1.0 + v.z) - v.z;
    let sin_theta = safe_sqrt(1.0 - z * z);
    let (s, c) = sin_cos_turns(u.y);
    let h = Vec3::new(sin_theta * c + v.x, sin_theta * s + v.y, z + v.z);
    // Unstretch.
    normalize_or(Vec3::new(alpha * h.x, alpha * h.y, max0(h.z)), Vec3::Z)
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

#[cfg(test)]
mod tests {
    use super::*;

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
}
