//! Group 6, quad strategies and the control variate: cases of the other groups again with quads
//! sampled by solid angle, by solid angle x cosine and by `auto`, and with the analytic control variate;
//! and a quad light cut in half by the horizon.

use crate::glossy::below_horizon;
use crate::harness::{Case, Reference, run_group};
use crate::huge_lights::huge_quad;
use crate::occlusion::{lit_quad, lit_sphere};
use crate::scenes::{Setup, lambert_out, lambertian, origin_hit, wo_default};
use picomis::{Shape, Vec3};
use picomis_tests::{DVec3, d3, lambert_polygon_irradiance, quad_corners};

/// Group 6's cases.
pub fn quad_strategy_cases() -> Vec<Case> {
    vec![
        huge_quad().solid_angle(),
        lit_quad().solid_angle(),
        lit_quad().control_variate(),
        lit_sphere().control_variate(),
        below_horizon().control_variate(),
        huge_quad().control_variate(),
        huge_quad().solid_angle_cosine(),
        lit_quad().solid_angle_cosine(),
        horizon_quad(),
        horizon_quad().solid_angle(),
        horizon_quad().solid_angle_cosine(),
        huge_quad().auto_quads(),
        lit_quad().auto_quads(),
        horizon_quad().auto_quads(),
    ]
}

#[test]
fn quads_by_solid_angle_cosine_and_control_variate() {
    run_group(6, quad_strategy_cases());
}

/// A Lambertian floor at the origin and a 1 x 1 quad light standing upright 1 away, facing it,
/// whose lower half is below the floor's horizon: the cosine is 0.41 at its top corners and 0
/// from its middle down, so the cosine warp's corner weights are 0.41 and the floor 0.01.
pub fn horizon_quad() -> Case {
    let mut s = Setup::floor(lambertian());
    let corners =
        quad_corners(Vec3::new(-0.5, -0.5, -1.0), Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 1.0, 0.0));
    assert!(Shape::quad(corners).unwrap().normal_at(corners[0]).z > 0.0);
    s.quad_light(corners, 2.0);
    let hit = origin_hit();
    // Only the half above the horizon lights the floor.
    let above = quad_corners(Vec3::new(-0.5, 0.0, -1.0), Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 0.5, 0.0));
    let exact = lambert_out(lambert_polygon_irradiance(DVec3::ZERO, DVec3::Y, &above.map(d3), 2.0));
    Case::new("quad light cut in half by the horizon", s.scene, hit, wo_default(), Reference::Exact(exact))
}
