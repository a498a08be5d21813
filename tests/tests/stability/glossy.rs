//! Group 3, near-mirror GGX, grazing angles, a light below the horizon.

use crate::harness::{Case, Check, Col, Reference, run_group};
use crate::scenes::{R_GGX, Setup, ggx, lambert_out, lambertian, origin_hit, sphere_e, tilt, wo_default};
use crate::tiny_lights::small_light_case;
use picomis::{Technique, Vec3};

pub const LIGHT_MISSES_LOBE: &str = "light sampling must land in a GGX lobe ~2 alpha wide inside the light's cone: \
probability ~(2 alpha / angular radius)^2";
pub const AVERAGE_BSDF_HALF: &str = "the light half of the average is as unreachable as light sampling; the BSDF \
half (0.5 ref) is asserted";

/// A GGX floor seen from `wo`, with a sphere light of angular radius `k` centred on the mirror
/// direction of `wo`, at distance 3.
pub fn mirror_case(alpha: f32, k: f32) -> Case {
    let mut s = Setup::floor(ggx(alpha));
    let wo = Vec3::new(-0.5, 0.75, 0.1).normalize();
    let mirror = Vec3::new(-wo.x, wo.y, -wo.z);
    let (d, radiance) = (3.0, 1.0);
    s.sphere_light(mirror * d, k * d, radiance);
    Case::new(
        format!("GGX alpha {alpha:.0e}, light r/d = {k:.0e} on the mirror direction"),
        s.scene,
        origin_hit(),
        wo,
        Reference::Agreement,
    )
}

pub fn near_mirror(k: f32) -> Case {
    // With alpha = 1e-4 the lobe (~2e-4 rad) lies inside the light: L_r = R L (1 - m) E[G1(wi)]
    // with 1 - G1 ~ alpha^2 tan^2 ~ 1e-8 and m the lobe's mass outside the light. The light's
    // cone (radius k) maps to an ellipse of half-vector slopes with semi-axes k/2 and
    // k/(2 cos(theta_o)); GGX puts alpha^2/s^2 of its mass beyond slope s, so
    // m ~ alpha^2 mean(1/s^2) = 2 alpha^2 (1 + cos^2(theta_o)) / k^2 (3e-4 for k = 1e-2).
    let alpha = 1e-4f64;
    let cos_o = f64::from(Vec3::new(-0.5, 0.75, 0.1).normalize().y);
    let m = 2.0 * alpha * alpha * (1.0 + cos_o * cos_o) / f64::from(k * k);
    mirror_case(alpha as f32, k)
        .anchor(f64::from(R_GGX) * (1.0 - m), 3e-5, "near-mirror limit R L (1 - lobe mass outside the light)")
        .except(Col::LightArea, Check::FiniteOnly, LIGHT_MISSES_LOBE)
        .except(Col::LightCone, Check::FiniteOnly, LIGHT_MISSES_LOBE)
        .except(Col::Average, Check::Part(Technique::Bsdf, 0.5), AVERAGE_BSDF_HALF)
}

pub fn grazing_view_lambert() -> Case {
    let mut s = Setup::floor(lambertian());
    let c = tilt(-40.0) * 3.0;
    s.sphere_light(c, 1.0, 1.0);
    let hit = origin_hit();
    let exact = lambert_out(sphere_e(&hit, c, 1.0, 1.0));
    let wo = Vec3::new(1.0, 1e-6, 0.0);
    Case::new("Lambertian, grazing view (cos 1e-6)", s.scene, hit, wo, Reference::Exact(exact))
}

pub fn grazing_view_ggx() -> Case {
    let mut s = Setup::floor(ggx(0.2));
    // The light near the (grazing) mirror direction, still fully above the horizon.
    s.sphere_light(tilt(-70.0) * 3.0, 1.0, 1.0);
    let wo = Vec3::new(1.0, 1e-6, 0.0);
    Case::new("GGX alpha 0.2, grazing view (cos 1e-6)", s.scene, origin_hit(), wo, Reference::Agreement)
}

/// A sphere light of angular radius `k` whose centre is at cos(theta) = 2k (just above the
/// horizon), radiance 1/k^2.
pub fn grazing_light(k: f32) -> Case {
    let cos = 2.0 * k;
    let dir = Vec3::new((1.0 - cos * cos).sqrt(), cos, 0.0);
    small_light_case(format!("Lambertian, grazing light (cos {cos:.0e}, r/d = {k:.0e})"), dir, k)
}

pub fn below_horizon() -> Case {
    let mut s = Setup::floor(lambertian());
    // Centre 80 degrees off the normal at d = 2 with r = 1: a third of the sphere is under the
    // floor (no closed form: agreement).
    s.sphere_light(tilt(80.0) * 2.0, 1.0, 1.0);
    Case::new(
        "sphere light partly below the horizon",
        s.scene,
        origin_hit(),
        wo_default(),
        Reference::Agreement,
    )
}

/// Group 3's cases.
pub fn glossy_and_grazing_cases() -> Vec<Case> {
    vec![
        near_mirror(1.0 / 3.0),
        near_mirror(1e-2),
        mirror_case(1e-2, 1e-2),
        grazing_view_lambert(),
        grazing_view_ggx(),
        grazing_light(5e-4),
        grazing_light(5e-7),
        below_horizon(),
    ]
}

#[test]
fn glossy_and_grazing() {
    run_group(3, glossy_and_grazing_cases());
}
