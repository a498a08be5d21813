//! The sample streams under randomised quasi-Monte Carlo: every stream's pixel estimates are
//! unbiased, and the stratified one (sobol) has a lower variance than independent numbers.
//!
//! An estimate here is the mean of `SPP` camera samples of one "pixel" (samples 0..SPP of one
//! stream, as a render takes them); `REPLICAS` pixels give independent randomisations, so the
//! standard error of their mean is exact for any stream, however its samples are correlated
//! within a pixel. Scene: a Lambertian floor under a sphere light and a quad light (closed forms),
//! so light selection, the reuse of its number for the point on the light, and both techniques
//! all take part. Checks: |mean - exact| < 4 standard errors (with standard errors below 2 % of
//! the value, so the check can fail), and for sobol a replica variance below half of the
//! independent stream's at the same spp.

use picomis::{
    Film, Heuristic, LightSelection, Material, Method, RenderSettings, Rgb, Sampler, SamplerKind, Scene,
    Shape, Vec3,
};
use picomis_host::{HostScene, renderer};
use picomis_tests::{
    DVec3, Stats, assert_unbiased, camera, d3, floor_corners, lambert_polygon_irradiance, quad_corners,
    shading_hit, sphere_irradiance_at,
};
use std::f64::consts::PI;

const SPP: u32 = 256;
const REPLICAS: u32 = 256;
const ALBEDO: f32 = 0.8;

fn scene() -> (HostScene, f64) {
    let mut s: HostScene = Scene::new(camera(), Film::new(8, 8).unwrap()).unwrap();
    let white = s.add_material(Material::lambertian(Rgb::splat(ALBEDO)).unwrap()).unwrap();
    let black = s.add_material(Material::lambertian(Rgb::ZERO).unwrap()).unwrap();
    s.add_shape(Shape::quad(floor_corners(50.0)).unwrap(), white).unwrap();
    let c = Vec3::new(1.5, 2.0, 0.3);
    let bulb = s.add_shape(Shape::sphere(c, 0.5).unwrap(), black).unwrap();
    s.add_area_light(bulb, Rgb::splat(4.0)).unwrap();
    let corners =
        quad_corners(Vec3::new(-0.6, 1.5, 0.8), Vec3::new(0.0, 0.3, -1.4), Vec3::new(1.1, 0.2, 0.1));
    let q = s.add_shape(Shape::quad(corners).unwrap(), black).unwrap();
    s.add_area_light(q, Rgb::splat(1.0)).unwrap();
    let e_sphere = sphere_irradiance_at(DVec3::ZERO, DVec3::Y, d3(c), 0.5, 4.0);
    let e_quad = lambert_polygon_irradiance(DVec3::ZERO, DVec3::Y, &corners.map(d3), 1.0);
    (s, f64::from(ALBEDO) / PI * (e_sphere + e_quad))
}

/// Statistics of `REPLICAS` pixel estimates of `SPP` samples each (channel 0).
fn replicas(scene: &HostScene, settings: &RenderSettings) -> Stats {
    let it = renderer(scene, settings).unwrap();
    let hit = shading_hit(picomis::ShapeId::new(0), Vec3::ZERO, Vec3::Y);
    let wo = Vec3::new(0.3, 0.9, -0.2).normalize();
    let mut st = Stats::new();
    for pixel in 0..REPLICAS {
        let mut sum = 0.0f64;
        for i in 0..SPP {
            let mut sampler = Sampler::with_kind(settings.sampler(), settings.seed(), pixel, i);
            let (l, b) = it.estimate_direct(&hit, wo, &mut sampler);
            sum += f64::from(l.contribution.x + b.contribution.x);
        }
        st.push(sum / f64::from(SPP));
    }
    st
}

#[test]
fn pixel_estimates_are_unbiased_with_every_stream_and_sobol_is_stratified() {
    let (scene, exact) = scene();
    let methods = [
        Method::LightOnly,
        Method::BsdfOnly,
        Method::Mis(Heuristic::Balance),
        Method::Mis(Heuristic::Power { beta: 2.0 }),
    ];
    for method in methods {
        for selection in LightSelection::ALL {
            let mut variance = Vec::new();
            for kind in SamplerKind::ALL {
                let settings = RenderSettings::new(method, 1, 1, SPP, 77)
                    .unwrap()
                    .with_light_selection(selection)
                    .with_sampler(kind);
                let st = replicas(&scene, &settings);
                let label = format!("{method:?}, {selection:?}, {}", kind.name());
                println!(
                    "{label}: mean {:.5e} exact {:.5e} stderr {:.3}% z {:+.2}",
                    st.mean(),
                    exact,
                    100.0 * st.stderr() / exact,
                    (st.mean() - exact) / st.stderr()
                );
                assert_unbiased(&label, &st, exact, 0.02);
                variance.push((kind, st.variance()));
            }
            let of = |k| variance.iter().find(|(kind, _)| *kind == k).map(|v| v.1).unwrap();
            let gain = of(SamplerKind::Independent) / of(SamplerKind::Sobol);
            println!("{method:?}, {selection:?}: sobol variance {gain:.1}x lower than independent");
            assert!(gain > 2.0, "{method:?}, {selection:?}: sobol only {gain:.2}x better");
        }
    }
}
