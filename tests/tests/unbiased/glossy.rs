//! (f) A GGX conductor under a sphere light, against an adaptive quadrature of the kernel's
//! `Material::eval` over the light's cone (no closed form for GGX); (g) the same GGX floor under
//! three sphere lights, one near the mirror direction, with every light selection (contribution
//! weighs the lights by the BSDF).

use crate::harness::{N, add, assert_estimates, check_methods, check_wo, methods, settings};
use crate::lambertian::{SPHERE_L, SphereScene};
use picomis::{Film, LightSelection, Material, Rgb, SamplerKind, Scene, Shape, SphereSampling, Vec3};
use picomis_host::HostScene;
use picomis_tests::{
    Cap, DVec3, camera, d3, direct_run, f3, floor_corners, integrate_adaptive, rgb64, shading_hit,
};

/// A GGX floor (object 0) under a sphere light 40 degrees off the normal.
pub fn glossy_scene(alpha: f32) -> (SphereScene, Vec3, f32) {
    let mut s: SphereScene = Scene::new(camera(), Film::new(8, 8).unwrap()).unwrap();
    let metal = s.add_material(Material::ggx_conductor(alpha, Rgb::new(0.9, 0.7, 0.5)).unwrap()).unwrap();
    let black = s.add_material(Material::lambertian(Rgb::ZERO).unwrap()).unwrap();
    s.add_shape(Shape::quad(floor_corners(50.0)).unwrap(), metal).unwrap();
    let t = 40f32.to_radians();
    let (c, r) = (Vec3::new(3.0 * t.sin(), 3.0 * t.cos(), 0.0), 1.0);
    let bulb = s.add_shape(Shape::sphere(c, r).unwrap(), black).unwrap();
    s.add_area_light(bulb, SPHERE_L).unwrap();
    (s, c, r)
}

/// The reflected radiance L_r = integral over the light's cone of L f cos dwi, by adaptive
/// Gauss-Legendre quadrature of the kernel's `Material::eval` (f cos) in f64: no closed form
/// exists for GGX, but the integral is known far more precisely than the estimates.
pub fn quadrature_reference(scene: &SphereScene, c: Vec3, r: f32, wo: Vec3) -> [f64; 3] {
    cone_quadrature(&scene.materials()[0], c, r, SPHERE_L, wo)
}

/// L_r of `material` at the origin (normal +y) towards `wo` from a sphere light of radiance `l`
/// (centre `c`, radius `r`), by the quadrature of [`quadrature_reference`].
fn cone_quadrature(material: &Material, c: Vec3, r: f32, l: Rgb, wo: Vec3) -> [f64; 3] {
    cone_quadrature_at(material, Vec3::ZERO, Vec3::Y, c, r, l, wo)
}

/// [`cone_quadrature`] at the point `x` with unit normal `n` (the light in full view of `x`).
pub fn cone_quadrature_at(
    material: &Material,
    x: Vec3,
    n: Vec3,
    c: Vec3,
    r: f32,
    l: Rgb,
    wo: Vec3,
) -> [f64; 3] {
    let frame = picomis::num::Frame::from_normal(n);
    let wo_local = frame.to_local(wo);
    let axis = d3(c) - d3(x);
    let cap = Cap::new(axis, (f64::from(r) / axis.length()).asin());
    let mut out = [0.0; 3];
    for (k, l) in rgb64(l).into_iter().enumerate() {
        let f = |w: DVec3| {
            let e = material.eval(wo_local, frame.to_local(f3(w)));
            l * f64::from([e.x, e.y, e.z][k])
        };
        let density = cap.density(f);
        let (na, nb) = (16, 32);
        for i in 0..na {
            for j in 0..nb {
                let a = [i as f64 / na as f64, (i + 1) as f64 / na as f64];
                let b = [j as f64 / nb as f64, (j + 1) as f64 / nb as f64];
                out[k] += integrate_adaptive(&density, a, b, 1e-10, 6);
            }
        }
    }
    out
}

#[test]
fn f_glossy_receiver() {
    // The light sits near the specular direction of wo.
    let wo = Vec3::new(-0.5, 0.75, 0.1).normalize();
    for (k, alpha) in [0.1f32, 0.4].into_iter().enumerate() {
        let (scene, c, r) = glossy_scene(alpha);
        let exact = quadrature_reference(&scene, c, r, wo);
        let hit = shading_hit(picomis::ShapeId::new(0), Vec3::ZERO, Vec3::Y);
        for (j, spheres) in [SphereSampling::Area, SphereSampling::Cone].into_iter().enumerate() {
            for kind in SamplerKind::ALL {
                for (i, (name, method)) in methods().into_iter().enumerate() {
                    let s = settings(method, 1, 1).with_sphere_sampling(spheres).with_sampler(kind);
                    let stream = 9100 + 100 * (2 * k + j) as u32 + i as u32;
                    let run = direct_run(&scene, &s, &hit, wo, stream, N);
                    let label = format!("(f) GGX alpha {alpha}, {name}, {spheres:?}, {}", kind.name());
                    assert_estimates(&label, &run.totals(), exact);
                }
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// (g) a glossy receiver under several lights: selection by contribution weighs the BSDF

type GlossyMany = HostScene;

/// A GGX floor (object 0) under three sphere lights: one near (not at) the mirror direction of
/// [`check_wo`], two far from it (one small and bright); their cones of directions apart.
fn glossy_many(alpha: f32) -> (GlossyMany, Vec<(Vec3, f32, Rgb)>) {
    let mut s: GlossyMany = Scene::new(camera(), Film::new(8, 8).unwrap()).unwrap();
    let metal = s.add_material(Material::ggx_conductor(alpha, Rgb::new(0.9, 0.7, 0.5)).unwrap()).unwrap();
    let black = s.add_material(Material::lambertian(Rgb::ZERO).unwrap()).unwrap();
    s.add_shape(Shape::quad(floor_corners(50.0)).unwrap(), metal).unwrap();
    let lights = vec![
        (Vec3::new(-1.1, 2.8, 0.4), 0.6, SPHERE_L),
        (Vec3::new(2.0, 2.0, 1.5), 0.5, Rgb::new(2.0, 3.0, 1.0)),
        (Vec3::new(0.5, 2.5, -2.0), 0.3, Rgb::new(12.0, 9.0, 15.0)),
    ];
    let cones: Vec<(DVec3, f64)> = lights
        .iter()
        .map(|(c, r, _)| (d3(*c).normalize(), (f64::from(*r) / d3(*c).length()).asin()))
        .collect();
    for (i, (a, ta)) in cones.iter().enumerate() {
        assert!(a.y > ta.sin(), "light {i} dips below the horizon");
        for (b, tb) in &cones[i + 1..] {
            assert!(a.dot(*b).acos() > ta + tb + 0.05);
        }
    }
    for (c, r, l) in &lights {
        let bulb = s.add_shape(Shape::sphere(*c, *r).unwrap(), black).unwrap();
        s.add_area_light(bulb, *l).unwrap();
    }
    (s, lights)
}

#[test]
fn g_glossy_receiver_under_several_lights() {
    let wo = check_wo();
    for (k, alpha) in [0.05f32, 0.3].into_iter().enumerate() {
        let (scene, lights) = glossy_many(alpha);
        let material = scene.materials()[0];
        let exact =
            lights.iter().map(|(c, r, l)| cone_quadrature(&material, *c, *r, *l, wo)).fold([0.0; 3], add);
        for (j, selection) in LightSelection::ALL.into_iter().enumerate() {
            let label = format!("(g) GGX alpha {alpha}, three lights");
            let stream = 9700 + 100 * (3 * k + j) as u32;
            let cone = SphereSampling::Cone;
            check_methods(&label, &scene, &methods(), (1, 1), cone, selection, exact, stream);
        }
    }
}
