//! Group 4, point lights, lights of very different power, lights of zero radiance.

use crate::harness::{COLS, Case, Check, Col, Reference, run_group};
use crate::scenes::{Setup, lambert_out, lambertian, origin_hit, sphere_e, tilt, wo_default};
use picomis::{LightSelection, Rgb, Vec3};
use picomis_tests::{DVec3, d3, lambert_polygon_irradiance, quad_corners};

/// Reflected radiance at the origin of the floor from a point light.
pub fn point_out(p: Vec3, intensity: f32) -> f64 {
    let v = d3(p);
    lambert_out(f64::from(intensity) * v.y / v.length() / v.length_squared())
}

pub const BSDF_NO_POINTS: &str =
    "BSDF sampling cannot find a delta light: it converges to the area lights' part only";

pub fn point_only() -> Case {
    let mut s = Setup::floor(lambertian());
    let p = Vec3::new(1.0, 2.0, 0.5);
    s.scene.add_point_light(p, Rgb::splat(5.0)).unwrap();
    let exact = point_out(p, 5.0);
    let mut case =
        Case::new("point light only", s.scene, origin_hit(), wo_default(), Reference::Exact(exact)).except(
            Col::Bsdf,
            Check::Value(0.0),
            BSDF_NO_POINTS,
        );
    // One point light: every light sample gives the same value, with weight 1 under every
    // heuristic (a delta light cannot be produced by BSDF sampling).
    for col in COLS.into_iter().skip(1) {
        case =
            case.except(col, Check::ZeroVariance, "a lone point light: every light sample is the same value");
    }
    case
}

pub fn point_and_sphere() -> Case {
    let mut s = Setup::floor(lambertian());
    let c = tilt(30.0) * 3.0;
    s.sphere_light(c, 0.8, 4.0);
    let p = Vec3::new(-1.0, 2.0, 1.5);
    s.scene.add_point_light(p, Rgb::splat(3.0)).unwrap();
    let hit = origin_hit();
    let sphere = lambert_out(sphere_e(&hit, c, 0.8, 4.0));
    Case::new(
        "point light + sphere light",
        s.scene,
        hit,
        wo_default(),
        Reference::Exact(sphere + point_out(p, 3.0)),
    )
    .except(Col::Bsdf, Check::Value(sphere), BSDF_NO_POINTS)
}

/// Lights whose contributions span 7 orders of magnitude: a bright sphere, a dim sphere, a point
/// light and a quad, none hiding another from the origin.
pub fn mixed_powers(selection: LightSelection) -> Case {
    let mut s = Setup::floor(lambertian());
    let hit = origin_hit();
    let spheres = [(Vec3::new(2.0, 3.0, 0.0), 1.0, 2.5e3), (Vec3::new(-2.0, 3.0, 1.0), 0.5, 1e-2)];
    let mut area = 0.0;
    for (c, r, l) in spheres {
        s.sphere_light(c, r, l);
        area += lambert_out(sphere_e(&hit, c, r, l));
    }
    let corners =
        quad_corners(Vec3::new(-0.5, 2.0, -2.5), Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 0.0, 1.0));
    s.quad_light(corners, 1.0);
    area += lambert_out(lambert_polygon_irradiance(DVec3::ZERO, DVec3::Y, &corners.map(d3), 1.0));
    let p = Vec3::new(0.0, 4.0, 2.0);
    s.scene.add_point_light(p, Rgb::splat(1e3)).unwrap();
    let total = area + point_out(p, 1e3);
    Case::new(
        format!("4 lights, powers 1e-2 to 1e5, {selection:?} selection"),
        s.scene,
        hit,
        wo_default(),
        Reference::Exact(total),
    )
    .selection(selection)
    .except(Col::Bsdf, Check::Value(area), BSDF_NO_POINTS)
}

pub fn zero_radiance(all_zero: bool) -> Case {
    let mut s = Setup::floor(lambertian());
    s.sphere_light(Vec3::new(-2.0, 2.5, 0.0), 0.7, 0.0);
    s.scene.add_point_light(Vec3::new(1.0, 2.0, 1.0), Rgb::ZERO).unwrap();
    if all_zero {
        // Power selection with a total power of 0 falls back to uniform selection.
        return Case::new(
            "only lights of zero radiance (power selection)",
            s.scene,
            origin_hit(),
            wo_default(),
            Reference::Zero,
        )
        .selection(LightSelection::Power);
    }
    let c = Vec3::new(1.5, 2.5, -1.0);
    s.sphere_light(c, 0.8, 3.0);
    let hit = origin_hit();
    let exact = lambert_out(sphere_e(&hit, c, 0.8, 3.0));
    Case::new(
        "two lights of zero radiance + a sphere light",
        s.scene,
        hit,
        wo_default(),
        Reference::Exact(exact),
    )
}

/// Group 4's cases.
pub fn point_and_mixed_light_cases() -> Vec<Case> {
    vec![
        point_only(),
        point_and_sphere(),
        mixed_powers(LightSelection::Uniform),
        mixed_powers(LightSelection::Power),
        zero_radiance(false),
        zero_radiance(true),
    ]
}

#[test]
fn point_and_mixed_lights() {
    run_group(4, point_and_mixed_light_cases());
}
