//! (e) Several lights of different power (three sphere lights and a quad light), with every light
//! selection.

use crate::harness::{ALBEDO, add, check_methods, lambert_out, methods, scaled, sphere_e};
use picomis::{Film, LightSelection, Material, Rgb, Scene, Shape, SphereSampling, Vec3};
use picomis_host::HostScene;
use picomis_tests::{DVec3, camera, d3, floor_corners, lambert_polygon_irradiance, quad_corners};

type ManyScene = HostScene;

/// Three sphere lights of different size and radiance and a quad light, all fully above the
/// horizon of the origin and not hiding one another; returns the exact reflected radiance.
pub fn many_lights() -> (ManyScene, [f64; 3]) {
    let mut s: ManyScene = Scene::new(camera(), Film::new(8, 8).unwrap()).unwrap();
    let white = s.add_material(Material::lambertian(ALBEDO).unwrap()).unwrap();
    let black = s.add_material(Material::lambertian(Rgb::ZERO).unwrap()).unwrap();
    s.add_shape(Shape::quad(floor_corners(50.0)).unwrap(), white).unwrap();
    let spheres = [
        (Vec3::new(2.0, 2.5, 0.0), 0.9, Rgb::new(1.0, 1.5, 2.0)),
        (Vec3::new(-1.5, 2.0, 1.0), 0.3, Rgb::new(30.0, 20.0, 10.0)),
        (Vec3::new(-0.5, 3.0, -2.0), 0.5, Rgb::new(2.0, 2.0, 2.0)),
    ];
    let mut e = [0.0; 3];
    let mut axes: Vec<(DVec3, f64)> = Vec::new();
    for (c, r, l) in spheres {
        let id = s.add_shape(Shape::sphere(c, r).unwrap(), black).unwrap();
        s.add_area_light(id, l).unwrap();
        e = add(e, scaled(l, sphere_e(c, r)));
        axes.push((d3(c).normalize(), (f64::from(r) / d3(c).length()).asin()));
    }
    let corners = quad_corners(Vec3::new(0.5, 2.0, 1.0), Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 0.0, 1.0));
    let q = Shape::quad(corners).unwrap();
    assert!(q.normal_at(corners[0]).y < 0.0);
    let id = s.add_shape(q, black).unwrap();
    let ql = Rgb::new(0.5, 0.3, 0.8);
    s.add_area_light(id, ql).unwrap();
    e = add(e, scaled(ql, lambert_polygon_irradiance(DVec3::ZERO, DVec3::Y, &corners.map(d3), 1.0)));
    // No sphere hides another sphere or the quad (cones of directions apart).
    for (i, (a, ta)) in axes.iter().enumerate() {
        for (b, tb) in &axes[i + 1..] {
            assert!(a.dot(*b).acos() > ta + tb + 0.05);
        }
        for v in corners {
            assert!(a.dot(d3(v).normalize()).acos() > ta + 0.05);
        }
    }
    (s, lambert_out(e))
}

fn check_many(selection: LightSelection, stream: u32) {
    let (scene, exact) = many_lights();
    for (k, spheres) in [SphereSampling::Area, SphereSampling::Cone].into_iter().enumerate() {
        let stream = stream + 100 * k as u32;
        check_methods("(e) four lights", &scene, &methods(), (1, 1), spheres, selection, exact, stream);
    }
}

#[test]
fn e_several_lights_uniform_selection() {
    check_many(LightSelection::Uniform, 6000);
}

#[test]
fn e_several_lights_power_selection() {
    // Streams 7000.. (they were moved to 7050 after stream 7007, the independent stream, area
    // sampling, the maximum heuristic, gave z = -4.59 in channel 0; moved back, issue 37 item 11).
    // Chance, not bias: the same check on streams 7000 to 7999 has z of mean +0.01 ± 0.03 and
    // spread 1.005 with one |z| > 4 (7007 itself), and stream 7007 continued to 3.2 million
    // estimates has z = -0.46 (tests/examples/four_lights_streams.rs). The suite's 3,159 checks at
    // |z| < 4 each would fail by chance on about a fifth of redraws; at the family-wise threshold
    // (harness.rs, `z_max`: 5.1) on 1 in 1,000.
    check_many(LightSelection::Power, 7000);
}

#[test]
fn e_several_lights_contribution_selection() {
    check_many(LightSelection::Contribution, 7500);
}
