//! Group 2, huge and close lights: a sphere light almost touching, touching and enclosing the
//! shading point, and a quad light 2e4 across at height 1.

use crate::harness::{Case, Check, Col, Reference, run_group};
use crate::scenes::{Setup, lambert_out, lambertian, origin_hit, sphere_e, view, wo_default};
use picomis::{Shape, Technique, Vec3};
use picomis_tests::{DVec3, d3, lambert_polygon_irradiance, quad_corners, shading_hit};

pub fn almost_touching() -> Case {
    let mut s = Setup::floor(lambertian());
    let c = Vec3::new(0.0, 1.001, 0.0);
    s.sphere_light(c, 1.0, 1.0);
    let hit = origin_hit();
    let exact = lambert_out(sphere_e(&hit, c, 1.0, 1.0));
    Case::new(
        "sphere light 1e-3 above the shading point (r = 1)",
        s.scene,
        hit,
        wo_default(),
        Reference::Exact(exact),
    )
    .except(
        Col::LightArea,
        Check::FiniteOnly,
        "uniform area sampling of a sphere at gap g from the receiver: the points under the shading point \
             carry ~1/g^2, relative variance ~4/g^2 = 4e6",
    )
}

pub fn touching() -> Case {
    let mut s = Setup::floor(lambertian());
    // Tangent to the floor at the origin, seen from 0.1 away: the sphere touches the horizon.
    let c = Vec3::Y;
    s.sphere_light(c, 1.0, 1.0);
    let hit = shading_hit(picomis::ShapeId::new(0), Vec3::new(0.1, 0.0, 0.0), Vec3::Y);
    let exact = lambert_out(sphere_e(&hit, c, 1.0, 1.0));
    Case::new(
        "sphere light touching the floor, 0.1 from the contact",
        s.scene,
        hit,
        wo_default(),
        Reference::Exact(exact),
    )
    .except(
        Col::LightArea,
        Check::FiniteOnly,
        "0.1 from the contact the sphere is only g = 0.1^2 / 2 = 5e-3 above the shading point: area \
         sampling's relative variance ~4/g^2 = 1.6e5",
    )
}

pub fn inside() -> Case {
    let mut s = Setup::floor(lambertian());
    // The floor cuts through the sphere; the shading point is inside it. Emission is one-sided
    // (outward): no light reaches the inside.
    s.sphere_light(Vec3::new(0.0, 0.5, 0.0), 1.0, 10.0);
    let (hit, wo) = view(&s.scene, Vec3::new(0.2, 0.6, 0.1), Vec3::new(0.05, 0.0, -0.02), 0);
    Case::new("shading point inside a sphere light", s.scene, hit, wo, Reference::Zero)
}

pub fn huge_quad() -> Case {
    let mut s = Setup::floor(lambertian());
    let h = 1.0e4;
    let corners =
        quad_corners(Vec3::new(-h, 1.0, -h), Vec3::new(2.0 * h, 0.0, 0.0), Vec3::new(0.0, 0.0, 2.0 * h));
    assert!(Shape::quad(corners).unwrap().normal_at(corners[0]).y < 0.0);
    s.quad_light(corners, 1.0);
    let hit = origin_hit();
    let exact = lambert_out(lambert_polygon_irradiance(DVec3::ZERO, DVec3::Y, &corners.map(d3), 1.0));
    let light_fails = "uniform area sampling of a 2e4 x 2e4 quad at height 1: relative variance ~area / (3 pi h^2) \
                       = 4e7 (the cone option changes nothing for quads)";
    Case::new("quad light 2e4 x 2e4 at height 1", s.scene, hit, wo_default(), Reference::Exact(exact))
        .except(Col::LightArea, Check::FiniteOnly, light_fails)
        .except(Col::LightCone, Check::FiniteOnly, light_fails)
        .except(
            Col::Average,
            Check::Part(Technique::Bsdf, 0.5),
            "the light half of the average is as unreachable as light sampling; the BSDF half (0.5 ref) is asserted",
        )
}

/// Group 2's cases.
pub fn huge_and_close_cases() -> Vec<Case> {
    vec![almost_touching(), touching(), inside(), huge_quad()]
}

#[test]
fn huge_and_close_lights() {
    run_group(2, huge_and_close_cases());
}
