//! (c) The furnace: an open box of five emitting walls over a Lambertian floor, L = rho Le, where
//! BSDF sampling has zero variance (through a camera ray, and exactly at the floor's centre).

use crate::harness::{ALBEDO, MAX_REL_STDERR, N, assert_estimates, methods, settings, z_max};
use picomis::{Film, LightSelection, Material, Method, Ray, Rgb, SamplerKind, Scene, Shape, Vec3};
use picomis_host::HostScene;
use picomis_tests::{
    camera, check_z_within, direct_stats, floor_corners, quad_corners, rgb64, shading_hit, trace_run,
};

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
            let run = trace_run(&scene, &s, &ray, 4000 + 100 * k as u32 + j as u32, N);
            let label = format!("(c) furnace, {name}, {selection:?}, {}", kind.name());
            if method == Method::BsdfOnly {
                // Cosine sampling of a Lambertian BRDF under uniform radiance: every sample
                // is rho Le (zero variance), but for the rare one that finds no light (measured:
                // one in the 200,000 of one stream; a direction on the floor's horizon or along
                // a seam of the walls). m such samples in N make the relative variance about
                // m / N: at most five are allowed.
                for (c, s) in run.stats.0.iter().enumerate() {
                    let rel_var = s.variance() / (exact[c] * exact[c]);
                    let bound = 5.0 / f64::from(N);
                    assert!(rel_var < bound, "{label}: relative variance {rel_var:e} in channel {c}");
                }
            }
            assert_estimates(&label, &run.totals(), exact);
        }
    }
}

#[test]
fn furnace_bsdf_sampling_is_exact_at_the_floor_centre() {
    // The furnace through the estimator's estimate_direct at the exact centre of the floor: every
    // BSDF sample returns rho Le, and light sampling contributes nothing under BsdfOnly.
    let scene = furnace();
    let hit = shading_hit(picomis::ShapeId::new(0), Vec3::ZERO, Vec3::Y);
    let st = direct_stats(&scene, &settings(Method::BsdfOnly, 1, 1), &hit, Vec3::Y, 9000, 20_000);
    let exact = f64::from(ALBEDO.x) * f64::from(FURNACE_LE.x);
    let s0 = &st.total.0[0];
    let label = "furnace BSDF only at the floor centre";
    check_z_within(label, s0.mean(), s0.stderr(), s0.n(), exact, 0.0, MAX_REL_STDERR, z_max())
        .unwrap_or_else(|e| panic!("{e}"));
    assert!(st.total.0[0].variance() < 1e-10 * exact * exact);
    assert_eq!(st.light.0[0].mean(), 0.0);
}
