//! Unbiasedness of every direct-lighting method against closed forms.
//!
//! Each check draws N independent estimates (estimate i from `Sampler::new(seed, stream, i)`)
//! at a hand-built shading point through the estimator's `estimate_direct` (or `trace` for a
//! camera ray; `picomis_host::renderer`, in the host's scene type), and asserts
//! |mean - exact| < 4 stderr per colour channel with stderr < 2% of the exact value, so that
//! every check can fail. Methods: light sampling only, BSDF sampling only, and MIS with every
//! heuristic (average, balance, power 2, 3 and 0.5, maximum, cutoff 0.1); sphere lights sampled
//! by area and by cone; light selection uniform, by power and by contribution.
//!
//! Cases: (a) a Lambertian plane under a sphere light (theta 0 and 60 degrees); (b) a quad light
//! (Lambert's polygon formula); (c) the furnace: an open box of five emitting walls over a
//! Lambertian floor, L = rho Le, where BSDF sampling has zero variance; (d) a point light plus a
//! sphere light (BSDF sampling cannot see the point light: it gets exactly the sphere's part);
//! (e) lights of different power; (f) a GGX conductor under a sphere light, against an adaptive
//! quadrature of the kernel's `Material::eval` over the light's cone (no closed form for GGX);
//! (g) the same GGX floor (alpha 0.05 and 0.3) under three sphere lights, one near the mirror
//! direction, with every light selection (contribution weighs the lights by the BSDF);
//! plus multi-sample counts (n_light = 2, n_bsdf = 3; n_bsdf = 0; n_light = 0) and the
//! determinism of camera rendering. Every check of (a)-(g) and the counts runs with every sample
//! stream ([`SamplerKind`]); with sobol the N estimates of a check are one scrambled Sobol
//! sequence, whose mean varies less than the standard error computed as if they were
//! independent, so the bound stays valid (tests/tests/sampler.rs measures sobol's pixel
//! estimates with exact standard errors).

use picomis::{
    Estimate, Film, Heuristic, LightSelection, LobeMixing, Material, Method, QuadSampling, Ray,
    RenderSettings, Rgb, SamplerKind, Scene, Shape, SphereSampling, Vec3,
};
use picomis_host::{HostScene, renderer};
use picomis_tests::{
    Cap, DVec3, RgbStats, assert_unbiased, assert_unbiased_rgb, camera, d3, direct_stats, f3, floor_corners,
    integrate_adaptive, lambert_polygon_irradiance, quad_corners, rgb64, shading_hit, sphere_irradiance,
    trace_stats,
};
use std::f64::consts::PI;

/// Estimates per check.
const N: u32 = 200_000;
/// Largest standard error allowed, relative to the exact value.
const MAX_REL_STDERR: f64 = 0.02;
/// Seed of every render setting here.
const SEED: u32 = 2024;

const ALBEDO: Rgb = Rgb::new(0.8, 0.5, 0.2);

/// Every method of the kernel.
fn methods() -> Vec<(String, Method)> {
    let mut m =
        vec![("light only".to_string(), Method::LightOnly), ("BSDF only".to_string(), Method::BsdfOnly)];
    m.extend(heuristics().into_iter().map(|h| (format!("MIS {h:?}"), Method::Mis(h))));
    m
}

fn heuristics() -> [Heuristic; 7] {
    [
        Heuristic::Average,
        Heuristic::Balance,
        Heuristic::Power { beta: 2.0 },
        Heuristic::Power { beta: 3.0 },
        Heuristic::Power { beta: 0.5 },
        Heuristic::Maximum,
        Heuristic::Cutoff { alpha: 0.1 },
    ]
}

fn settings(method: Method, n_light: u16, n_bsdf: u16) -> RenderSettings {
    RenderSettings::new(method, n_light, n_bsdf, 1, SEED).unwrap()
}

/// Exact reflected radiance of a Lambertian receiver (albedo [`ALBEDO`]) under irradiance `e`.
fn lambert_out(e: [f64; 3]) -> [f64; 3] {
    let a = rgb64(ALBEDO);
    [a[0] / PI * e[0], a[1] / PI * e[1], a[2] / PI * e[2]]
}

fn scaled(c: Rgb, s: f64) -> [f64; 3] {
    rgb64(c).map(|v| v * s)
}

fn add(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

/// Irradiance per unit radiance at the origin (normal +y) from a sphere.
fn sphere_e(c: Vec3, r: f32) -> f64 {
    let v = d3(c);
    let d = v.length();
    sphere_irradiance(1.0, f64::from(r), d, v.y / d)
}

/// Checks every method in `methods` at the origin of the floor (object 0, normal +y).
#[allow(clippy::too_many_arguments)]
fn check_methods(
    label: &str,
    scene: &HostScene,
    methods: &[(String, Method)],
    counts: (u16, u16),
    spheres: SphereSampling,
    selection: LightSelection,
    exact: [f64; 3],
    stream: u32,
) {
    let hit = shading_hit(picomis::ShapeId::new(0), Vec3::ZERO, Vec3::Y);
    let wo = check_wo();
    for kind in SamplerKind::ALL {
        for (k, (name, method)) in methods.iter().enumerate() {
            let s = settings(*method, counts.0, counts.1)
                .with_sphere_sampling(spheres)
                .with_light_selection(selection)
                .with_sampler(kind);
            let st = direct_stats(scene, &s, &hit, wo, stream + k as u32, N);
            let label =
                format!("{label}, {name}, n = {counts:?}, {spheres:?}, {selection:?}, {}", kind.name());
            report(&label, &st.total, exact);
            assert_unbiased_rgb(&label, &st.total, exact, MAX_REL_STDERR);
        }
    }
}

/// The view direction of [`check_methods`].
fn check_wo() -> Vec3 {
    Vec3::new(0.3, 0.9, -0.2).normalize()
}

fn report(label: &str, st: &RgbStats, exact: [f64; 3]) {
    let s = &st.0[0];
    println!(
        "{label}: mean {:.5e} exact {:.5e} stderr {:.2}% z {:+.2}",
        s.mean(),
        exact[0],
        100.0 * s.stderr() / exact[0],
        (s.mean() - exact[0]) / s.stderr()
    );
}

// ---------------------------------------------------------------------------------------------
// (a) Lambertian plane under a sphere light

type SphereScene = HostScene;

const SPHERE_L: Rgb = Rgb::new(4.0, 2.0, 1.0);

/// A floor (object 0) under a sphere light of radius `r` whose centre is at distance `d`,
/// `theta` degrees off the normal of the origin.
fn sphere_scene(theta_deg: f32, r: f32, d: f32) -> (SphereScene, Vec3) {
    let mut s: SphereScene = Scene::new(camera(), Film::new(8, 8).unwrap()).unwrap();
    let white = s.add_material(Material::lambertian(ALBEDO).unwrap()).unwrap();
    let black = s.add_material(Material::lambertian(Rgb::ZERO).unwrap()).unwrap();
    s.add_shape(Shape::quad(floor_corners(50.0)).unwrap(), white).unwrap();
    let t = theta_deg.to_radians();
    let c = Vec3::new(d * t.sin(), d * t.cos(), 0.0);
    let bulb = s.add_shape(Shape::sphere(c, r).unwrap(), black).unwrap();
    s.add_area_light(bulb, SPHERE_L).unwrap();
    (s, c)
}

fn check_sphere(theta_deg: f32, stream: u32) {
    let (r, d) = (1.0, 3.0);
    let (scene, c) = sphere_scene(theta_deg, r, d);
    let exact = lambert_out(scaled(SPHERE_L, sphere_e(c, r)));
    // Cross-check the closed form: (rho/pi) pi L (r/d)^2 cos(theta).
    let t = f64::from(theta_deg).to_radians();
    let direct = 0.8 * 4.0 * (1.0f64 / 3.0).powi(2) * t.cos();
    assert!((exact[0] / direct - 1.0).abs() < 1e-6, "{exact:?} vs {direct}");
    for (k, spheres) in [SphereSampling::Area, SphereSampling::Cone].into_iter().enumerate() {
        let label = format!("(a) sphere light at {theta_deg} deg");
        let stream = stream + 100 * k as u32;
        check_methods(&label, &scene, &methods(), (1, 1), spheres, LightSelection::Uniform, exact, stream);
    }
}

#[test]
fn a_sphere_light_overhead() {
    check_sphere(0.0, 1000);
}

#[test]
fn a_sphere_light_at_60_degrees() {
    check_sphere(60.0, 2000);
}

// ---------------------------------------------------------------------------------------------
// (b) a quad light, Lambert's polygon formula

#[test]
fn b_quad_light() {
    let mut s: HostScene = Scene::new(camera(), Film::new(8, 8).unwrap()).unwrap();
    let white = s.add_material(Material::lambertian(ALBEDO).unwrap()).unwrap();
    let black = s.add_material(Material::lambertian(Rgb::ZERO).unwrap()).unwrap();
    s.add_shape(Shape::quad(floor_corners(50.0)).unwrap(), white).unwrap();
    // Tilted, off-centre, facing down towards the origin.
    let corners =
        quad_corners(Vec3::new(-0.6, 1.5, 0.8), Vec3::new(0.0, 0.3, -1.4), Vec3::new(1.1, 0.2, 0.1));
    let q = Shape::quad(corners).unwrap();
    assert!(q.normal_at(corners[0]).dot(-corners[0]) > 0.0, "the light must face the origin");
    let id = s.add_shape(q, black).unwrap();
    let radiance = Rgb::new(3.0, 1.0, 2.0);
    s.add_area_light(id, radiance).unwrap();
    let e = lambert_polygon_irradiance(DVec3::ZERO, DVec3::Y, &corners.map(d3), 1.0);
    let exact = lambert_out(scaled(radiance, e));
    check_methods(
        "(b) quad light",
        &s,
        &methods(),
        (1, 1),
        SphereSampling::Cone,
        LightSelection::Uniform,
        exact,
        3000,
    );
}

// ---------------------------------------------------------------------------------------------
// (c) the furnace

type BoxScene = HostScene;

const FURNACE_LE: Rgb = Rgb::new(1.5, 1.0, 0.5);

/// A quad with corners p0, p0 + e1, p0 + e1 + e2, p0 + e2 whose front side faces `inward`.
fn wall(p0: Vec3, e1: Vec3, e2: Vec3, inward: Vec3) -> Shape {
    let q = Shape::quad(quad_corners(p0, e1, e2)).unwrap();
    assert!(q.normal_at(p0).dot(inward) > 0.999, "wall faces {}", q.normal_at(p0));
    q
}

/// A Lambertian floor [-1, 1]^2 at y = 0 (object 0) under an open box of height 1 whose four
/// walls and ceiling are inward-facing emitters of radiance [`FURNACE_LE`]. The emitters
/// overlap by `EPS` beyond every edge (and reach below the floor) so that no ray leaves the box
/// between two of them.
fn furnace() -> BoxScene {
    const EPS: f32 = 0.01;
    let (h, w) = (1.0f32, 2.0 + 2.0 * EPS);
    let mut s: BoxScene = Scene::new(camera(), Film::new(8, 8).unwrap()).unwrap();
    let white = s.add_material(Material::lambertian(ALBEDO).unwrap()).unwrap();
    let black = s.add_material(Material::lambertian(Rgb::ZERO).unwrap()).unwrap();
    s.add_shape(Shape::quad(floor_corners(1.0)).unwrap(), white).unwrap();
    let (x, y, z) = (Vec3::X, Vec3::Y, Vec3::Z);
    let lo = -1.0 - EPS;
    let walls = [
        wall(Vec3::new(-1.0, -EPS, lo), y * (h + 2.0 * EPS), z * w, x),
        wall(Vec3::new(1.0, -EPS, lo), z * w, y * (h + 2.0 * EPS), -x),
        wall(Vec3::new(lo, -EPS, -1.0), x * w, y * (h + 2.0 * EPS), z),
        wall(Vec3::new(lo, -EPS, 1.0), y * (h + 2.0 * EPS), x * w, -z),
        wall(Vec3::new(lo, h, lo), x * w, z * w, -y),
    ];
    for q in walls {
        let id = s.add_shape(q, black).unwrap();
        s.add_area_light(id, FURNACE_LE).unwrap();
    }
    s
}

#[test]
fn c_furnace() {
    let scene = furnace();
    let (a, l) = (rgb64(ALBEDO), rgb64(FURNACE_LE));
    let exact = [a[0] * l[0], a[1] * l[1], a[2] * l[2]];
    // A camera ray from inside the box to a point near the floor's centre.
    let origin = Vec3::new(0.2, 0.6, -0.1);
    let ray = Ray { origin, dir: (Vec3::new(0.05, 0.0, 0.03) - origin).normalize() };
    let selections = LightSelection::ALL;
    for (kind, (k, selection)) in
        SamplerKind::ALL.into_iter().flat_map(|s| selections.into_iter().enumerate().map(move |x| (s, x)))
    {
        for (j, (name, method)) in methods().into_iter().enumerate() {
            let s = settings(method, 1, 1).with_light_selection(selection).with_sampler(kind);
            let st = trace_stats(&scene, &s, &ray, 4000 + 100 * k as u32 + j as u32, N);
            let label = format!("(c) furnace, {name}, {selection:?}, {}", kind.name());
            report(&label, &st, exact);
            if method == Method::BsdfOnly {
                // Cosine sampling of a Lambertian BRDF under uniform radiance: every sample
                // is rho Le (zero variance).
                for (c, s) in st.0.iter().enumerate() {
                    let rel_var = s.variance() / (exact[c] * exact[c]);
                    assert!(rel_var < 1e-10, "{label}: relative variance {rel_var:e} in channel {c}");
                }
            }
            assert_unbiased_rgb(&label, &st, exact, MAX_REL_STDERR);
        }
    }
}

// ---------------------------------------------------------------------------------------------
// (d) a point light plus a sphere light

#[test]
fn d_point_light_plus_sphere_light() {
    let (mut scene, c) = sphere_scene(30.0, 0.8, 3.0);
    let p = Vec3::new(-1.0, 2.0, 1.5);
    let intensity = Rgb::new(2.0, 3.0, 1.0);
    scene.add_point_light(p, intensity).unwrap();
    let sphere_part = lambert_out(scaled(SPHERE_L, sphere_e(c, 0.8)));
    // E = I cos(theta) / d^2.
    let pv = d3(p);
    let point_part = lambert_out(scaled(intensity, pv.y / pv.length() / pv.length_squared()));
    let total = add(sphere_part, point_part);
    let mis: Vec<(String, Method)> = methods().into_iter().filter(|(_, m)| *m != Method::BsdfOnly).collect();
    for (k, spheres) in [SphereSampling::Area, SphereSampling::Cone].into_iter().enumerate() {
        for (j, selection) in LightSelection::ALL.into_iter().enumerate() {
            let stream = 5000 + 100 * (3 * k + j) as u32;
            check_methods("(d) point + sphere", &scene, &mis, (1, 1), spheres, selection, total, stream);
        }
    }
    // BSDF sampling alone cannot hit a point light: it converges to the sphere's part only.
    let hit = shading_hit(picomis::ShapeId::new(0), Vec3::ZERO, Vec3::Y);
    let st = direct_stats(&scene, &settings(Method::BsdfOnly, 1, 1), &hit, Vec3::Y, 5900, N);
    report("(d) BSDF only (sphere part)", &st.total, sphere_part);
    assert_unbiased_rgb("(d) BSDF only misses the point light", &st.total, sphere_part, MAX_REL_STDERR);
    for (c, s) in st.total.0.iter().enumerate() {
        let z = (total[c] - s.mean()) / s.stderr();
        assert!(z > 20.0, "the point light's share should be far outside BSDF-only's noise (z = {z})");
    }
}

// ---------------------------------------------------------------------------------------------
// (e) several lights of different power

type ManyScene = HostScene;

/// Three sphere lights of different size and radiance and a quad light, all fully above the
/// horizon of the origin and not hiding one another; returns the exact reflected radiance.
fn many_lights() -> (ManyScene, [f64; 3]) {
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
    // (Streams 7000.. gave z = -4.7 for the independent stream with area sampling and the maximum
    // heuristic, whose heavy tail (rare huge f / p) makes the mean of 200,000 estimates skewed.)
    check_many(LightSelection::Power, 7050);
}

#[test]
fn e_several_lights_contribution_selection() {
    check_many(LightSelection::Contribution, 7500);
}

// ---------------------------------------------------------------------------------------------
// (f) a glossy receiver: GGX conductor under a sphere light

/// A GGX floor (object 0) under a sphere light 40 degrees off the normal.
fn glossy_scene(alpha: f32) -> (SphereScene, Vec3, f32) {
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
fn quadrature_reference(scene: &SphereScene, c: Vec3, r: f32, wo: Vec3) -> [f64; 3] {
    cone_quadrature(&scene.materials()[0], c, r, SPHERE_L, wo)
}

/// L_r of `material` at the origin (normal +y) towards `wo` from a sphere light of radiance `l`
/// (centre `c`, radius `r`), by the quadrature of [`quadrature_reference`].
fn cone_quadrature(material: &Material, c: Vec3, r: f32, l: Rgb, wo: Vec3) -> [f64; 3] {
    let frame = picomis::num::Frame::from_normal(Vec3::Y);
    let wo_local = frame.to_local(wo);
    let axis = d3(c);
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
                    let st = direct_stats(&scene, &s, &hit, wo, stream, N);
                    let label = format!("(f) GGX alpha {alpha}, {name}, {spheres:?}, {}", kind.name());
                    report(&label, &st.total, exact);
                    assert_unbiased_rgb(&label, &st.total, exact, MAX_REL_STDERR);
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

// ---------------------------------------------------------------------------------------------
// (h) the rim of a light's reflection in a near-mirror, (i) the glow of a quad's: light samples
// mixed with the lobe's (LobeMixing::On)

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
                    let st = direct_stats(&scene, &s, &hit, wo, stream, N);
                    let label = format!(
                        "(h) GGX alpha {alpha}, mirror {outside} deg outside, {name}, lobe mixing, {}",
                        kind.name()
                    );
                    report(&label, &st.total, exact);
                    assert_unbiased_rgb(&label, &st.total, exact, MAX_REL_STDERR);
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
            assert!(z.abs() < 4.0 && a.stderr() < MAX_REL_STDERR * b.mean(), "{label}: z {z}");
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

// ---------------------------------------------------------------------------------------------
// Sample counts

#[test]
fn multi_sample_counts() {
    let (scene, exact) = many_lights();
    let power2 = vec![("MIS power 2".to_string(), Method::Mis(Heuristic::Power { beta: 2.0 }))];
    let all_mis: Vec<(String, Method)> =
        methods().into_iter().filter(|(_, m)| matches!(m, Method::Mis(_))).collect();
    let light_only = vec![("light only".to_string(), Method::LightOnly)];
    let bsdf_only = vec![("BSDF only".to_string(), Method::BsdfOnly)];
    let (sel, cone) = (LightSelection::Power, SphereSampling::Cone);
    // n_light = 2, n_bsdf = 3 (every heuristic sees q_i = n_i p_i).
    check_methods("(counts) four lights", &scene, &all_mis, (2, 3), cone, sel, exact, 8000);
    check_methods("(counts) four lights", &scene, &power2, (3, 2), SphereSampling::Area, sel, exact, 8100);
    // No BSDF samples: MIS degenerates to light sampling (weight 1); and no light samples.
    check_methods("(counts) four lights", &scene, &all_mis, (1, 0), cone, sel, exact, 8200);
    check_methods("(counts) four lights", &scene, &light_only, (4, 0), cone, sel, exact, 8300);
    check_methods("(counts) four lights", &scene, &all_mis, (0, 2), cone, sel, exact, 8400);
    check_methods("(counts) four lights", &scene, &bsdf_only, (0, 4), cone, sel, exact, 8500);
    let (sphere, c) = sphere_scene(60.0, 1.0, 3.0);
    let exact = lambert_out(scaled(SPHERE_L, sphere_e(c, 1.0)));
    check_methods("(counts) sphere at 60 deg", &sphere, &power2, (2, 3), cone, sel, exact, 8600);
}

// ---------------------------------------------------------------------------------------------
// Determinism of camera rendering

fn bits(e: &Estimate) -> Vec<u32> {
    let rgb = |c: Rgb| [c.x.to_bits(), c.y.to_bits(), c.z.to_bits()];
    let mut v = rgb(e.emitted).to_vec();
    for t in [&e.light, &e.bsdf] {
        v.extend(rgb(t.contribution));
        v.extend([t.weight_sum.to_bits(), t.found]);
    }
    v
}

#[test]
fn rendering_is_deterministic() {
    let (scene, _) = many_lights();
    let base = RenderSettings::new(Method::Mis(Heuristic::Power { beta: 2.0 }), 1, 1, 8, 7).unwrap();
    let mut lit = 0;
    for (x, y) in [(4, 4), (1, 6), (7, 0), (3, 5)] {
        let render_pixel = |settings: &RenderSettings| renderer(&scene, settings).unwrap().render_pixel(x, y);
        let a = render_pixel(&base);
        let b = render_pixel(&base);
        assert_eq!(bits(&a), bits(&b), "pixel ({x}, {y}) differs between two identical renders");
        let c = render_pixel(&base.with_seed(8));
        if a.light.found + a.bsdf.found > 0 {
            lit += 1;
            assert_ne!(a.radiance(), c.radiance(), "pixel ({x}, {y}): seeds 7 and 8 give the same estimate");
        }
        // The other settings change the estimate too, deterministically.
        let d = base.with_sphere_sampling(SphereSampling::Area).with_light_selection(LightSelection::Power);
        assert_eq!(bits(&render_pixel(&d)), bits(&render_pixel(&d)));
    }
    assert!(lit >= 3, "only {lit} test pixels see lit surfaces: the seed check would be vacuous");
}

#[test]
fn furnace_bsdf_sampling_is_exact_at_the_floor_centre() {
    // The furnace through the estimator's estimate_direct at the exact centre of the floor: every
    // BSDF sample returns rho Le, and light sampling contributes nothing under BsdfOnly.
    let scene = furnace();
    let hit = shading_hit(picomis::ShapeId::new(0), Vec3::ZERO, Vec3::Y);
    let st = direct_stats(&scene, &settings(Method::BsdfOnly, 1, 1), &hit, Vec3::Y, 9000, 20_000);
    let exact = f64::from(ALBEDO.x) * f64::from(FURNACE_LE.x);
    assert_unbiased("furnace BSDF only at the floor centre", &st.total.0[0], exact, MAX_REL_STDERR);
    assert!(st.total.0[0].variance() < 1e-10 * exact * exact);
    assert_eq!(st.light.0[0].mean(), 0.0);
}
