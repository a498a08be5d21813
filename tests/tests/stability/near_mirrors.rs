//! Group 7, near mirrors with lobe mixing: the rim and the glow of a sphere light's and of a quad
//! light's reflection in a near-mirror, without and with lobe mixing.

use crate::glossy::LIGHT_MISSES_LOBE;
use crate::harness::{Case, Check, Col, Reference, run_group};
use crate::scenes::{Setup, ggx, origin_hit, tilt};
use crate::tiny_lights::AVERAGE_LIGHT_HALF;
use picomis::{Technique, Vec3};
use picomis_tests::quad_corners;

/// A GGX floor (alpha `alpha`) seen 40 degrees off the normal, with a sphere light of angular
/// radius asin(k) at distance 3 whose edge passes `outside` radians beyond the mirror direction
/// (negative: inside): the rim of the light's reflection, where the lobe straddles the light's
/// edge, or its glow.
pub fn rim_case(alpha: f32, k: f32, outside: f32) -> Case {
    let mut s = Setup::floor(ggx(alpha));
    let wo = tilt(-40.0);
    let t = (40.0f32).to_radians() + k.asin() + outside;
    s.sphere_light(Vec3::new(t.sin(), t.cos(), 0.0) * 3.0, 3.0 * k, 1.0);
    let label =
        format!("GGX alpha {alpha:.0e}, light r/d = {k:.0e}, mirror direction {outside:+.0e} rad outside");
    Case::new(label, s.scene, origin_hit(), wo, Reference::Agreement)
}

pub const BSDF_MISSES_GLOW: &str = "a GGX direction reaches a light 40 alphas beyond the mirror direction with \
probability ~(alpha / 40 alpha)^2";
pub const AVERAGE_RIM: &str = "the average gives each technique half of f: here both halves are as noisy as \
their techniques";

/// The rim of a reflection in a near-mirror: light sampling spreads over the light and misses the
/// lobe, BSDF sampling spreads over the lobe and misses the light half the time.
pub fn rim() -> Case {
    rim_case(1e-3, 0.1, 2e-3)
}

/// The glow beyond the rim: the lobe's tail reaches the light 40 alphas away.
pub fn glow() -> Case {
    rim_case(1e-3, 0.1, 4e-2).except(Col::Bsdf, Check::FiniteOnly, BSDF_MISSES_GLOW)
}

/// A GGX floor (`alpha`) at the origin seen from 40 degrees off the normal under a 2 x 2 quad light
/// (a wall at x = 3 facing the receiver, radiance 1), whose upper edge lies `outside` radians
/// beyond the mirror direction.
pub fn quad_rim_case(alpha: f32, outside: f32) -> Case {
    let mut s = Setup::floor(ggx(alpha));
    let wo = tilt(-40.0);
    let top = 3.0 / ((40.0f32).to_radians() + outside).tan();
    let corners =
        quad_corners(Vec3::new(3.0, top - 2.0, -1.0), Vec3::new(0.0, 0.0, 2.0), Vec3::new(0.0, 2.0, 0.0));
    s.quad_light(corners, 1.0);
    let label = format!(
        "GGX alpha {alpha:.0e}, 2 x 2 quad light, mirror direction {outside:+.0e} rad above its edge"
    );
    Case::new(label, s.scene, origin_hit(), wo, Reference::Agreement)
}

/// Group 7's cases: the rim and the glow of a sphere light's reflection in a near-mirror, then
/// of a quad light's, without and with lobe mixing. With it, light sampling reaches the
/// expectation at both and the heuristics' variance falls 12- to 19-fold for the sphere; BSDF
/// sampling is unchanged.
pub fn lobe_mixing_cases() -> Vec<Case> {
    [without_and_with_lobe(rim, glow), without_and_with_lobe(quad_rim, quad_glow)]
        .into_iter()
        .flatten()
        .collect()
}

/// A light's `rim` and `glow` cases without lobe mixing (light sampling cannot land in the lobe)
/// and with it (BSDF sampling still misses the glow; the average's light half is asserted there).
pub fn without_and_with_lobe(rim: fn() -> Case, glow: fn() -> Case) -> [Case; 4] {
    let light_fails = |c: Case| {
        c.except(Col::LightArea, Check::FiniteOnly, LIGHT_MISSES_LOBE)
            .except(Col::LightCone, Check::FiniteOnly, LIGHT_MISSES_LOBE)
            .except(Col::Average, Check::FiniteOnly, AVERAGE_RIM)
    };
    [
        light_fails(rim()),
        rim().lobe_mixing(),
        light_fails(glow()),
        glow().lobe_mixing().except(Col::Bsdf, Check::FiniteOnly, BSDF_MISSES_GLOW).except(
            Col::Average,
            Check::Part(Technique::Light, 0.5),
            AVERAGE_LIGHT_HALF,
        ),
    ]
}

/// The rim of a quad light's reflection in a near-mirror (`stress`'s mirror floor).
pub fn quad_rim() -> Case {
    quad_rim_case(1e-3, 2e-3)
}

/// The glow beyond the rim of a quad light's reflection.
pub fn quad_glow() -> Case {
    quad_rim_case(1e-3, 4e-2).except(Col::Bsdf, Check::FiniteOnly, BSDF_MISSES_GLOW)
}

#[test]
fn near_mirrors_with_lobe_mixing() {
    run_group(7, lobe_mixing_cases());
}
