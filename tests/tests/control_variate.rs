//! The analytic control variate (`ControlVariate::On`): integral f V = integral f (closed form) +
//! integral f (V - 1) (sampled with MIS), for Lambertian receivers under quad and sphere lights.
//!
//! 1. The kernel's closed forms (`picomis::analytic`, f32) against adaptive quadrature in f64:
//!    quads wholly above, cut by and below the receiver's horizon, and spheres wholly above,
//!    cut by (Snyder's form) and below the horizon.
//! 2. Unbiasedness: with occluders casting partial shadows, every heuristic and both MIS models
//!    with the control variate agree with the plain estimator (z-tests), and without occluders
//!    the estimate is the closed form with zero variance. BSDF sampling alone has no control
//!    variate (its closed form is the light technique's part): the settings refuse it.
//! 3. Camera rays through `trace` (what the images are made of): with and without the control
//!    variate the pixels converge to the same values.
//! 4. The control variate by its rule (`ControlVariate::Auto`, the best preset's): in a scene of
//!    area lights only it is `On`, bit for bit; beside a point light it covers only the lights the
//!    shadow cull says nothing can block, it agrees with the plain estimator under every light
//!    selection, heuristic and model, and where every sampled light is unblocked the estimate is
//!    exact (zero variance: selection by contribution gives the exact lights no samples).
//! 5. The control variate by size (`ControlVariate::BySize`, the best preset's since): a lone
//!    light is `On`'s where it looks large from the receiver and `Off`'s where it looks small and
//!    something may block it, bit for bit; beside other lights it is `Auto`, bit for bit.

use picomis::integrator::{quad_projected_solid_angle, sphere_projected_solid_angle};
use picomis::{
    ControlVariate, Film, Heuristic, Hit, LightId, LightSelection, Material, Method, MisModel, QuadSampling,
    Ray, RenderSettings, Rgb, Scene, SceneError, Shape, ShapeId, Vec3,
};
use picomis_host::HostScene;
use picomis_tests::{
    Cap, DVec3, Stats, assert_unbiased, camera, check_agreement, d3, direct_stats, f3, floor_corners,
    integrate_adaptive, quad_corners, shading_hit, trace_stats,
};
use std::f64::consts::PI;

const N: u32 = 200_000;
const MAX_REL_STDERR: f64 = 0.02;
const SEED: u32 = 0x00C0_FFEE;
const RHO: f32 = 0.8;

// ---------------------------------------------------------------------------------------------
// 1. Closed forms against quadrature

/// integral over the quad's area of max(0, n . w) cos(theta_y) / d^2 (front side only).
fn quad_quadrature(x: DVec3, n: DVec3, c: [DVec3; 4]) -> f64 {
    let (p0, e1, e2) = (c[0], c[1] - c[0], c[3] - c[0]);
    let nq = e1.cross(e2).normalize();
    let area = e1.cross(e2).length();
    let f = |s: f64, t: f64| {
        let v = p0 + e1 * s + e2 * t - x;
        let d2 = v.length_squared();
        let d = d2.sqrt();
        (n.dot(v) / d).max(0.0) * (-nq.dot(v) / d).max(0.0) / d2
    };
    integrate_adaptive(&f, [0.0, 1.0], [0.0, 1.0], 1e-10, 12) * area
}

/// integral over the sphere's cone of max(0, n . w) dw.
fn sphere_quadrature(x: DVec3, n: DVec3, centre: DVec3, r: f64) -> f64 {
    let axis = centre - x;
    let cap = Cap::new(axis, (r / axis.length()).asin());
    let f = cap.density(|w| n.dot(w).max(0.0));
    integrate_adaptive(&f, [0.0, 1.0], [0.0, 1.0], 1e-11, 12)
}

fn close(label: &str, kernel: Option<f32>, exact: f64, tol: f64) {
    let k = f64::from(kernel.unwrap_or_else(|| panic!("{label}: the kernel has no closed form")));
    let rel = if exact > 0.0 { k / exact - 1.0 } else { k };
    println!("{label}: kernel {k:.7e}, quadrature {exact:.7e}, relative {rel:+.1e}");
    assert!(rel.abs() < tol, "{label}: kernel {k} vs quadrature {exact}");
}

#[test]
fn closed_forms_match_quadrature() {
    let n = DVec3::Y;
    let down = |p0: Vec3, a: f32, b: f32| quad_corners(p0, Vec3::new(a, 0.0, 0.0), Vec3::new(0.0, 0.0, b));
    // A wall facing -x, standing across the horizon: corners below and above.
    let wall =
        |y0: f32| quad_corners(Vec3::new(1.0, y0, -1.0), Vec3::new(0.0, 0.0, 2.0), Vec3::new(0.0, 2.0, 0.0));
    let quads = [
        ("quad overhead", down(Vec3::new(-0.4, 1.0, -0.3), 1.0, 0.8)),
        ("quad off to the side", down(Vec3::new(1.0, 0.5, 0.2), 2.0, 1.0)),
        ("wall cut by the horizon", wall(-0.7)),
        ("wall mostly below the horizon", wall(-1.8)),
        ("wall wholly below the horizon", wall(-2.5)),
        (
            "tilted quad",
            quad_corners(Vec3::new(-0.6, 1.5, 0.8), Vec3::new(0.0, 0.3, -1.4), Vec3::new(1.1, 0.2, 0.1)),
        ),
    ];
    for (label, c) in quads {
        let v = c.map(|p| p - Vec3::ZERO);
        let exact = quad_quadrature(DVec3::ZERO, n, c.map(d3));
        let kernel = quad_projected_solid_angle(v, Vec3::Y);
        if exact == 0.0 {
            assert_eq!(kernel, Some(0.0), "{label}");
        } else {
            close(label, kernel, exact, 2e-5);
        }
        // Its back side gives nothing.
        let mut back = v;
        back.reverse();
        assert_eq!(quad_projected_solid_angle(back, Vec3::Y), Some(0.0), "{label}, back side");
    }
    // Spheres: above (pi sin^2 cos), cut by the horizon (Snyder), below.
    for (theta_deg, r, d) in [
        (0.0, 1.0, 3.0),
        (50.0, 0.5, 2.0),
        (80.0, 1.0, 2.0),
        (95.0, 1.0, 2.0),
        (89.0, 0.1, 1.0),
        (60.0, 0.9, 1.0),
    ] {
        let t = f64::to_radians(theta_deg);
        let c = DVec3::new(d * t.sin(), d * t.cos(), 0.0);
        let exact = sphere_quadrature(DVec3::ZERO, n, c, r);
        let kernel = sphere_projected_solid_angle(f3(c), r as f32, Vec3::Y);
        close(&format!("sphere at {theta_deg} deg, r/d = {:.2}", r / d), kernel, exact, 2e-5);
    }
    // A small sphere grazing the horizon: Snyder's terms cancel in f32, so the kernel declines
    // (that light is then sampled as usual there).
    let t = f64::to_radians(89.99);
    let grazing = DVec3::new(t.sin(), t.cos(), 0.0);
    assert_eq!(sphere_projected_solid_angle(f3(grazing), 0.01, Vec3::Y), None);
    let below = DVec3::new(0.0, -3.0, 0.0);
    assert_eq!(sphere_projected_solid_angle(f3(below), 1.0, Vec3::Y), Some(0.0));
}

// ---------------------------------------------------------------------------------------------
// 2. Unbiasedness with partial shadows

/// The scenes' type: the host's (the settings are chosen at run time).
type S = HostScene;

/// A Lambertian floor under a quad light and a sphere light, each partly shadowed by a sphere.
fn shadowed_scene() -> S {
    let mut s: S = Scene::new(camera(), Film::new(8, 8).unwrap()).unwrap();
    let white = s.add_material(Material::lambertian(Rgb::splat(RHO)).unwrap()).unwrap();
    let black = s.add_material(Material::lambertian(Rgb::ZERO).unwrap()).unwrap();
    let grey = s.add_material(Material::lambertian(Rgb::splat(0.5)).unwrap()).unwrap();
    s.add_shape(Shape::quad(floor_corners(50.0)).unwrap(), white).unwrap();
    let q = quad_corners(Vec3::new(-1.0, 2.0, -0.5), Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 0.0, 1.0));
    let ql = s.add_shape(Shape::quad(q).unwrap(), black).unwrap();
    s.add_area_light(ql, Rgb::new(2.0, 1.5, 1.0)).unwrap();
    let sl = s.add_shape(Shape::sphere(Vec3::new(1.5, 2.5, 0.5), 0.6).unwrap(), black).unwrap();
    s.add_area_light(sl, Rgb::splat(3.0)).unwrap();
    s.add_shape(Shape::sphere(Vec3::new(-0.4, 1.0, 0.0), 0.3).unwrap(), grey).unwrap();
    s.add_shape(Shape::sphere(Vec3::new(0.7, 1.2, 0.3), 0.25).unwrap(), grey).unwrap();
    s
}

fn settings(method: Method, model: MisModel, cv: ControlVariate) -> RenderSettings {
    try_settings(method, model, cv).unwrap()
}

/// [`settings`], or why the kernel refuses them (the control variate without light samples).
fn try_settings(method: Method, model: MisModel, cv: ControlVariate) -> Result<RenderSettings, SceneError> {
    Ok(RenderSettings::new(method, 1, 1, 1, SEED)?
        .with_mis_model(model)?
        .with_control_variate(cv)?
        .with_quad_sampling(QuadSampling::SolidAngle))
}

fn origin() -> Hit {
    shading_hit(picomis::ShapeId::new(0), Vec3::ZERO, Vec3::Y)
}

fn wo() -> Vec3 {
    Vec3::new(0.3, 0.9, -0.2).normalize()
}

fn total(s: &S, st: &RenderSettings, stream: u32, n: u32) -> Stats {
    direct_stats(s, st, &origin(), wo(), stream, n).total.0[0]
}

#[test]
fn unbiased_with_partial_shadows() {
    let s = shadowed_scene();
    let plain = settings(Method::Mis(Heuristic::Balance), MisModel::Multi, ControlVariate::Off);
    let reference = total(&s, &plain, 1, 8 * N);
    let mut stream = 10;
    for model in [MisModel::Multi, MisModel::One { c_light: 0.5 }] {
        let methods = [
            Method::LightOnly,
            Method::BsdfOnly,
            Method::Mis(Heuristic::Balance),
            Method::Mis(Heuristic::Power { beta: 2.0 }),
            Method::Mis(Heuristic::Maximum),
            Method::Mis(Heuristic::Average),
        ];
        for method in methods {
            let (cv_stream, off_stream) = (stream, stream + 1);
            stream += 2;
            if method == Method::BsdfOnly {
                // The closed form is the light technique's part: without light samples the
                // kernel refuses the control variate.
                assert_eq!(
                    try_settings(method, model, ControlVariate::On),
                    Err(SceneError::ControlVariateWithoutLight),
                    "{model:?} {method:?}"
                );
                continue;
            }
            let cv = total(&s, &settings(method, model, ControlVariate::On), cv_stream, N);
            let off = total(&s, &settings(method, model, ControlVariate::Off), off_stream, N);
            println!(
                "{model:?} {method:?}: relative variance with the control variate {:.3e}, without {:.3e}",
                cv.variance() / reference.mean().powi(2),
                off.variance() / reference.mean().powi(2)
            );
            check_agreement(
                &format!("{model:?} {method:?} with the control variate"),
                &cv,
                &reference,
                MAX_REL_STDERR,
            )
            .unwrap();
        }
    }
}

#[test]
fn unoccluded_light_is_exact() {
    // Without the occluders every estimate is the closed form.
    let mut s: S = Scene::new(camera(), Film::new(8, 8).unwrap()).unwrap();
    let white = s.add_material(Material::lambertian(Rgb::splat(RHO)).unwrap()).unwrap();
    let black = s.add_material(Material::lambertian(Rgb::ZERO).unwrap()).unwrap();
    s.add_shape(Shape::quad(floor_corners(50.0)).unwrap(), white).unwrap();
    let q = quad_corners(Vec3::new(-1.0, 2.0, -0.5), Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 0.0, 1.0));
    let ql = s.add_shape(Shape::quad(q).unwrap(), black).unwrap();
    s.add_area_light(ql, Rgb::splat(2.0)).unwrap();
    let c = Vec3::new(1.5, 2.5, 0.5);
    let sl = s.add_shape(Shape::sphere(c, 0.6).unwrap(), black).unwrap();
    s.add_area_light(sl, Rgb::splat(3.0)).unwrap();
    let e = 2.0 * quad_quadrature(DVec3::ZERO, DVec3::Y, q.map(d3))
        + 3.0 * sphere_quadrature(DVec3::ZERO, DVec3::Y, d3(c), 0.6);
    let exact = f64::from(RHO) / PI * e;
    let st = total(
        &s,
        &settings(Method::Mis(Heuristic::Power { beta: 2.0 }), MisModel::Multi, ControlVariate::On),
        500,
        1000,
    );
    assert_eq!(st.variance(), 0.0, "no occluder: no noise");
    assert!((st.mean() / exact - 1.0).abs() < 1e-5, "{} vs {exact}", st.mean());
    let off = total(
        &s,
        &settings(Method::Mis(Heuristic::Power { beta: 2.0 }), MisModel::Multi, ControlVariate::Off),
        501,
        N,
    );
    assert_unbiased("without the control variate", &off, exact, MAX_REL_STDERR);
    // A GGX receiver is not Lambertian: the control variate does not apply (same numbers).
    let mut glossy = s.clone();
    let m = glossy.add_material(Material::ggx_conductor(0.3, Rgb::ONE).unwrap()).unwrap();
    let plate =
        glossy.add_shape(Shape::quad(floor_corners(1.0).map(|v| v + Vec3::Y * 0.01)).unwrap(), m).unwrap();
    let hit = shading_hit(plate, Vec3::new(0.0, 0.01, 0.0), Vec3::Y);
    let on = direct_stats(
        &glossy,
        &settings(Method::Mis(Heuristic::Balance), MisModel::Multi, ControlVariate::On),
        &hit,
        wo(),
        7,
        1000,
    );
    let off = direct_stats(
        &glossy,
        &settings(Method::Mis(Heuristic::Balance), MisModel::Multi, ControlVariate::Off),
        &hit,
        wo(),
        7,
        1000,
    );
    assert_eq!(on.total.0[0].mean(), off.total.0[0].mean());
}

// ---------------------------------------------------------------------------------------------
// 3. Camera rays

#[test]
fn pixels_converge_to_the_same_values() {
    let s = shadowed_scene();
    let eye = Vec3::new(0.0, 3.0, 4.0);
    for (k, target) in [Vec3::new(-0.5, 0.0, 0.1), Vec3::new(0.6, 0.0, 0.2), Vec3::new(2.0, 0.0, -1.0)]
        .into_iter()
        .enumerate()
    {
        let ray = Ray { origin: eye, dir: (target - eye).normalize() };
        let method = Method::Mis(Heuristic::Power { beta: 2.0 });
        let on =
            trace_stats(&s, &settings(method, MisModel::Multi, ControlVariate::On), &ray, 900 + k as u32, N);
        let off =
            trace_stats(&s, &settings(method, MisModel::Multi, ControlVariate::Off), &ray, 950 + k as u32, N);
        for c in 0..3 {
            let label = format!("camera ray {k}, channel {c}");
            println!(
                "{label}: {:.5e} ± {:.1e} with, {:.5e} ± {:.1e} without",
                on.0[c].mean(),
                on.0[c].stderr(),
                off.0[c].mean(),
                off.0[c].stderr()
            );
            check_agreement(&label, &on.0[c], &off.0[c], MAX_REL_STDERR).unwrap();
        }
    }
}

// ---------------------------------------------------------------------------------------------
// 4. The control variate by its rule

/// The quad light nothing can block from the floor: low and off to the side, under everything
/// else (facing down).
fn low_quad() -> [Vec3; 4] {
    quad_corners(Vec3::new(3.0, 0.5, -0.5), Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 0.0, 1.0))
}

const POINT: Vec3 = Vec3::new(-1.5, 3.0, -1.0);
const POINT_INTENSITY: f32 = 4.0;
/// A point light below the quad light's height (0.5): no shadow ray from the floor to it can
/// meet the quad.
const LOW_POINT: Vec3 = Vec3::new(-1.5, 0.4, -1.0);
const LOW_RADIANCE: f32 = 2.0;

/// Whether the shadow cull says that nothing can block `light` from the floor (object 0).
fn unblocked(s: &S, light: usize) -> bool {
    s.shadow_candidates(ShapeId::new(0), LightId::new(light as u16)) == 0
}

#[test]
fn auto_is_on_where_every_light_is_an_area_light() {
    let s = shadowed_scene();
    // (Both lights may be blocked: `auto` then covers and samples what `on` does.)
    assert!(!unblocked(&s, 0) && !unblocked(&s, 1));
    for method in
        [Method::Mis(Heuristic::Balance), Method::Mis(Heuristic::Power { beta: 2.0 }), Method::LightOnly]
    {
        let on = total(&s, &settings(method, MisModel::Multi, ControlVariate::On), 40, 2000);
        let auto = total(&s, &settings(method, MisModel::Multi, ControlVariate::Auto), 40, 2000);
        assert_eq!((auto.mean(), auto.variance()), (on.mean(), on.variance()), "{method:?}");
    }
}

#[test]
fn auto_beside_a_point_light_is_unbiased() {
    // The shadowed scene, a point light, and a quad light nothing can block: `auto` covers the
    // unblocked quad only (exact, no samples under selection by contribution) and samples the rest.
    let mut s = shadowed_scene();
    let black = s.add_material(Material::lambertian(Rgb::ZERO).unwrap()).unwrap();
    let low = s.add_shape(Shape::quad(low_quad()).unwrap(), black).unwrap();
    s.add_area_light(low, Rgb::splat(LOW_RADIANCE)).unwrap();
    s.add_point_light(POINT, Rgb::splat(POINT_INTENSITY)).unwrap();
    assert_eq!(s.lights().len(), 4);
    assert!(!unblocked(&s, 0) && !unblocked(&s, 1) && unblocked(&s, 2), "the scene tests what it says");
    let plain = settings(Method::Mis(Heuristic::Balance), MisModel::Multi, ControlVariate::Off);
    let reference = total(&s, &plain.with_light_selection(LightSelection::Uniform), 1, 8 * N);
    let mut stream = 100;
    for selection in LightSelection::ALL {
        for model in [MisModel::Multi, MisModel::One { c_light: 0.5 }] {
            for method in [
                Method::LightOnly,
                Method::Mis(Heuristic::Balance),
                Method::Mis(Heuristic::Power { beta: 2.0 }),
            ] {
                let st = settings(method, model, ControlVariate::Auto).with_light_selection(selection);
                let auto = total(&s, &st, stream, N / 2);
                stream += 1;
                let label = format!("auto, {} selection, {model:?} {method:?}", selection.name());
                println!(
                    "{label}: {:.5e} ± {:.1e} (reference {:.5e} ± {:.1e})",
                    auto.mean(),
                    auto.stderr(),
                    reference.mean(),
                    reference.stderr()
                );
                check_agreement(&label, &auto, &reference, MAX_REL_STDERR).unwrap();
            }
        }
    }
}

#[test]
fn unblocked_lights_beside_a_point_light_are_exact() {
    // A floor, the unblocked quad and an unblocked point light. `auto` takes the quad in closed
    // form; selection by contribution then draws the point light only: one deterministic sample.
    let mut s: S = Scene::new(camera(), Film::new(8, 8).unwrap()).unwrap();
    let white = s.add_material(Material::lambertian(Rgb::splat(RHO)).unwrap()).unwrap();
    let black = s.add_material(Material::lambertian(Rgb::ZERO).unwrap()).unwrap();
    s.add_shape(Shape::quad(floor_corners(50.0)).unwrap(), white).unwrap();
    let low = s.add_shape(Shape::quad(low_quad()).unwrap(), black).unwrap();
    s.add_area_light(low, Rgb::splat(LOW_RADIANCE)).unwrap();
    s.add_point_light(LOW_POINT, Rgb::splat(POINT_INTENSITY)).unwrap();
    assert!(
        unblocked(&s, 0),
        "the quad light is unblocked: {:#b}",
        s.shadow_candidates(ShapeId::new(0), LightId::new(0))
    );
    assert!(
        unblocked(&s, 1),
        "the point light is unblocked: {:#b}",
        s.shadow_candidates(ShapeId::new(0), LightId::new(1))
    );
    let d = d3(LOW_POINT);
    let point = f64::from(POINT_INTENSITY) * d.normalize().dot(DVec3::Y) / d.length_squared();
    let quad = f64::from(LOW_RADIANCE) * quad_quadrature(DVec3::ZERO, DVec3::Y, low_quad().map(d3));
    let exact = f64::from(RHO) / PI * (quad + point);
    for method in
        [Method::Mis(Heuristic::Power { beta: 2.0 }), Method::Mis(Heuristic::Balance), Method::LightOnly]
    {
        let st = settings(method, MisModel::Multi, ControlVariate::Auto)
            .with_light_selection(LightSelection::Contribution);
        let auto = total(&s, &st, 600, 1000);
        assert_eq!(auto.variance(), 0.0, "{method:?}: no noise");
        assert!((auto.mean() / exact - 1.0).abs() < 1e-5, "{method:?}: {} vs {exact}", auto.mean());
        // Uniform selection still draws the exact light (its samples add f (V - 1) = 0): noise,
        // the same mean.
        let uniform = total(&s, &st.with_light_selection(LightSelection::Uniform), 601, N / 4);
        assert!(uniform.variance() > 0.0, "{method:?}: uniform selection draws either light");
        assert_unbiased(&format!("{method:?}, uniform selection"), &uniform, exact, MAX_REL_STDERR);
    }
}

#[test]
fn by_size_takes_a_lone_light_where_it_looks_large() {
    let methods =
        [Method::Mis(Heuristic::Balance), Method::Mis(Heuristic::Power { beta: 2.0 }), Method::LightOnly];
    // (name, the light's corner, its side, whether it looks large from the origin: its diagonal
    // against the distance to its centre)
    let lights = [
        ("small and high (diagonal 1.41 at distance 2)", Vec3::new(-0.5, 2.0, -0.5), 1.0, false),
        ("large and low (diagonal 4.24 at distance 1)", Vec3::new(-1.5, 1.0, -1.5), 3.0, true),
    ];
    for (name, corner, side, large) in lights {
        let mut s: S = Scene::new(camera(), Film::new(8, 8).unwrap()).unwrap();
        let white = s.add_material(Material::lambertian(Rgb::splat(RHO)).unwrap()).unwrap();
        let black = s.add_material(Material::lambertian(Rgb::ZERO).unwrap()).unwrap();
        let grey = s.add_material(Material::lambertian(Rgb::splat(0.5)).unwrap()).unwrap();
        s.add_shape(Shape::quad(floor_corners(50.0)).unwrap(), white).unwrap();
        let q = quad_corners(corner, Vec3::new(side, 0.0, 0.0), Vec3::new(0.0, 0.0, side));
        let light = s.add_shape(Shape::quad(q).unwrap(), black).unwrap();
        s.add_area_light(light, Rgb::splat(2.0)).unwrap();
        s.add_shape(Shape::sphere(Vec3::new(0.2, 0.6, 0.1), 0.2).unwrap(), grey).unwrap();
        assert!(!unblocked(&s, 0), "{name}: the occluder may block the light");
        for method in methods {
            let on = total(&s, &settings(method, MisModel::Multi, ControlVariate::On), 40, 2000);
            let off = total(&s, &settings(method, MisModel::Multi, ControlVariate::Off), 40, 2000);
            let by_size = total(&s, &settings(method, MisModel::Multi, ControlVariate::BySize), 40, 2000);
            assert_ne!(on.mean(), off.mean(), "{name}, {method:?}: the check must see the choice");
            let want = if large { &on } else { &off };
            assert_eq!(
                (by_size.mean(), by_size.variance()),
                (want.mean(), want.variance()),
                "{name}, {method:?}"
            );
        }
    }
    // Beside another light: `auto`'s (here `on`'s), whatever the lights' sizes.
    let s = shadowed_scene();
    for method in methods {
        let auto = total(&s, &settings(method, MisModel::Multi, ControlVariate::Auto), 40, 2000);
        let by_size = total(&s, &settings(method, MisModel::Multi, ControlVariate::BySize), 40, 2000);
        assert_eq!((by_size.mean(), by_size.variance()), (auto.mean(), auto.variance()), "{method:?}");
    }
}
