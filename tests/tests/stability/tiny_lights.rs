//! Group 1, tiny sphere lights: a Lambertian floor under sphere lights of r/d = 1e-2 down to
//! 1e-6, which BSDF sampling cannot find.

use crate::harness::{Case, Check, Col, Reference, run_group};
use crate::scenes::{Setup, lambert_out, lambertian, origin_hit, sphere_e, tilt, wo_default};
use picomis::{Technique, Vec3};

pub const BSDF_MISSES_TINY: &str = "a cosine-sampled direction hits a light of angular radius r/d with probability \
~(r/d)^2 cos(theta): at most a few hits in N";
pub const AVERAGE_LIGHT_HALF: &str = "the average gives each technique half of f; the BSDF half is as unreachable as \
BSDF sampling, the light half (0.5 ref) is asserted";

/// A Lambertian floor at the origin under a sphere light of angular radius `k` whose centre is
/// at distance 2 along `dir`, radiance 1/k^2 (closed form). BSDF sampling cannot find a light
/// this small, and the average heuristic keeps only its light half.
pub fn small_light_case(label: String, dir: Vec3, k: f32) -> Case {
    let mut s = Setup::floor(lambertian());
    let d = 2.0;
    let c = dir * d;
    let (r, radiance) = (k * d, 1.0 / (k * k));
    s.sphere_light(c, r, radiance);
    let hit = origin_hit();
    let exact = lambert_out(sphere_e(&hit, c, r, radiance));
    Case::new(label, s.scene, hit, wo_default(), Reference::Exact(exact))
        .except(Col::Bsdf, Check::FiniteOnly, BSDF_MISSES_TINY)
        .except(Col::Average, Check::Part(Technique::Light, 0.5), AVERAGE_LIGHT_HALF)
}

/// A sphere light of r/d = `k`, 30 degrees off the normal (irradiance pi cos(30 deg) for every k).
pub fn tiny_light(k: f32) -> Case {
    small_light_case(format!("tiny sphere light, r/d = {k:.0e}"), tilt(30.0), k)
}

/// Group 1's cases.
pub fn tiny_sphere_light_cases() -> Vec<Case> {
    [1e-2, 1e-3, 1e-4, 1e-5, 1e-6].into_iter().map(tiny_light).collect()
}

#[test]
fn tiny_sphere_lights() {
    run_group(1, tiny_sphere_light_cases());
}
