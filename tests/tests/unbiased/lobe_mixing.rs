//! (h) The rim of a light's reflection in a near-mirror, (i) the glow of a quad's: light samples
//! mixed with the lobe's (`LobeMixing::On`) stay unbiased, and light sampling's noise falls.

use crate::glossy::{glossy_scene, quadrature_reference};
use crate::harness::{MAX_REL_STDERR, N, assert_estimates, methods, settings, z_max};
use crate::lambertian::SPHERE_L;
use picomis::{
    Film, Heuristic, LobeMixing, Material, Method, QuadSampling, RenderSettings, Rgb, SamplerKind, Scene,
    Shape, Vec3,
};
use picomis_host::HostScene;
use picomis_tests::{camera, direct_run, direct_stats, floor_corners, shading_hit};

/// The view direction of [`glossy_scene`] whose mirror direction lies `outside` degrees beyond
/// the edge of the light's cone (negative: inside), in the plane of the normal and the light.
fn rim_wo(outside: f32) -> Vec3 {
    let edge = 40.0 + (1.0f32 / 3.0).asin().to_degrees();
    let t = (edge + outside).to_radians();
    Vec3::new(-t.sin(), t.cos(), 0.0)
}

/// Settings of `method` (1 light + 1 BSDF sample) with lobe mixing.
fn with_lobe(method: Method) -> RenderSettings {
    settings(method, 1, 1).with_lobe_mixing(LobeMixing::On)
}

#[test]
fn h_rim_of_a_reflection() {
    // GGX alpha well below the cone's sin(theta_max) = 1/3, so the lobe's part applies; the
    // mirror direction just outside, on and just inside the cone's edge.
    let hit = shading_hit(picomis::ShapeId::new(0), Vec3::ZERO, Vec3::Y);
    for (k, alpha) in [0.02f32, 0.05].into_iter().enumerate() {
        let (scene, c, r) = glossy_scene(alpha);
        for (j, outside) in [2.0f32, 0.0, -1.0].into_iter().enumerate() {
            let wo = rim_wo(outside);
            let exact = quadrature_reference(&scene, c, r, wo);
            for kind in SamplerKind::ALL {
                for (i, (name, method)) in methods().into_iter().enumerate() {
                    let s = with_lobe(method).with_sampler(kind);
                    let stream = 9900 + 100 * (3 * k + j) as u32 + i as u32;
                    let run = direct_run(&scene, &s, &hit, wo, stream, N);
                    let label = format!(
                        "(h) GGX alpha {alpha}, mirror {outside} deg outside, {name}, lobe mixing, {}",
                        kind.name()
                    );
                    assert_estimates(&label, &run.totals(), exact);
                }
            }
        }
    }
}

/// The lobe's share is what makes light sampling work at the rim: its standard error there is
/// far below the cone's alone (at equal sample counts).
#[test]
fn h_the_lobe_lowers_light_sampling_noise_at_the_rim() {
    let hit = shading_hit(picomis::ShapeId::new(0), Vec3::ZERO, Vec3::Y);
    let (scene, _, _) = glossy_scene(0.02);
    let wo = rim_wo(1.0);
    let stderr = |lobe| {
        let s =
            settings(Method::LightOnly, 1, 1).with_lobe_mixing(lobe).with_sampler(SamplerKind::Independent);
        direct_stats(&scene, &s, &hit, wo, 9990, N).total.0[0].stderr()
    };
    let (cone, lobe) = (stderr(LobeMixing::Off), stderr(LobeMixing::On));
    println!("light sampling alone at the rim: stderr cone {cone:.3e}, with the lobe {lobe:.3e}");
    assert!(lobe < 0.25 * cone, "with the lobe {lobe:e} against the cone alone {cone:e}");
}

/// A near-mirror (GGX alpha 0.01, about 0.6 degrees) under a large quad light, seen in the glow
/// below the quad's reflection (mirror direction 3 degrees below the quad's lower edge), at the
/// rim (0.3 degrees below) and just inside it (0.3 degrees above), with every quad strategy:
/// with lobe mixing, every method agrees with the power heuristic without it (z-test on the
/// difference of the two means, with both standard errors), and light sampling's standard error
/// falls at least fourfold.
#[test]
fn i_glow_of_a_quad_in_a_near_mirror() {
    type QuadScene = HostScene;
    let mut s: QuadScene = Scene::new(camera(), Film::new(8, 8).unwrap()).unwrap();
    let metal = s.add_material(Material::ggx_conductor(0.01, Rgb::new(0.9, 0.7, 0.5)).unwrap()).unwrap();
    let black = s.add_material(Material::lambertian(Rgb::ZERO).unwrap()).unwrap();
    s.add_shape(Shape::quad(floor_corners(50.0)).unwrap(), metal).unwrap();
    // A 2 x 2 wall facing -x at x = 3, from y = 1 to 3: its lower edge atan(1/3) above the
    // horizon seen from the origin.
    let wall = [
        Vec3::new(3.0, 1.0, -1.0),
        Vec3::new(3.0, 1.0, 1.0),
        Vec3::new(3.0, 3.0, 1.0),
        Vec3::new(3.0, 3.0, -1.0),
    ];
    let light = s.add_shape(Shape::quad(wall).unwrap(), black).unwrap();
    s.add_area_light(light, SPHERE_L).unwrap();
    let hit = shading_hit(picomis::ShapeId::new(0), Vec3::ZERO, Vec3::Y);
    for (k, below) in [3.0f32, 0.3, -0.3].into_iter().enumerate() {
        let t = (1.0f32 / 3.0).atan() - below.to_radians();
        let wo = Vec3::new(-t.cos(), t.sin(), 0.0);
        for (j, quads) in QuadSampling::ALL.into_iter().enumerate() {
            glow_of_a_quad(&s, &hit, wo, below, quads, 10_500 + 100 * (3 * k + j) as u32);
        }
    }
}

/// One case of [`i_glow_of_a_quad_in_a_near_mirror`]: the mirror direction `below` degrees
/// below the quad's lower edge.
fn glow_of_a_quad(s: &HostScene, hit: &picomis::Hit, wo: Vec3, below: f32, quads: QuadSampling, stream: u32) {
    let alone = settings(Method::LightOnly, 1, 1).with_quad_sampling(quads);
    let power = settings(Method::Mis(Heuristic::Power { beta: 2.0 }), 1, 1).with_quad_sampling(quads);
    let reference = direct_stats(s, &power, hit, wo, stream, 4 * N).total;
    for (i, (name, method)) in methods().into_iter().enumerate() {
        let st =
            direct_stats(s, &with_lobe(method).with_quad_sampling(quads), hit, wo, stream + 1 + i as u32, N);
        for c in 0..3 {
            let (a, b) = (&st.total.0[c], &reference.0[c]);
            let z = (a.mean() - b.mean()) / (a.stderr().powi(2) + b.stderr().powi(2)).sqrt();
            let label =
                format!("(i) quad glow {below} deg below, {name}, quads {quads}, lobe mixing [channel {c}]");
            println!(
                "{label}: mean {:.5e} ({:.2e}), without {:.5e} ({:.2e}), z {z:+.2}",
                a.mean(),
                a.stderr(),
                b.mean(),
                b.stderr()
            );
            assert!(z.abs() < z_max() && a.stderr() < MAX_REL_STDERR * b.mean(), "{label}: z {z}");
        }
    }
    let light_only = with_lobe(Method::LightOnly).with_quad_sampling(quads);
    let with = direct_stats(s, &light_only, hit, wo, stream + 99, N).total.0[0].stderr();
    let without = direct_stats(s, &alone, hit, wo, stream + 98, N).total.0[0].stderr();
    println!(
        "(i) {below} deg below, quads {quads}: light sampling's stderr {without:.3e}, with the lobe {with:.3e}"
    );
    assert!(with < 0.25 * without, "{below} deg, quads {quads}: {with:e} against {without:e}");
}
