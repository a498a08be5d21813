//! Statistical power (issue 37, item 10): the suite's z-test catches a bias of 1 % at a
//! Lambertian receiver and of 2 % on the glossy plates of the Veach scene.
//!
//! Each case is a check made as the suite makes it: [`N`] estimates of the direct light at a
//! shading point through the estimator (`direct_run`: for sobol, 32 independent scrambles whose
//! spread gives the standard error, with Student's t threshold for its 31 degrees of freedom),
//! tested against an exact value by `check_mean`. The check must pass on the estimate and fail on
//! the same estimate with the bias injected, times 1 + b and times 1 - b (`MeanEstimate::scaled`).
//! Which checks can catch the bias is printed per method and sample stream (the least bias each
//! check can see is its threshold times its relative standard error); the assertions hold for the
//! estimators the product renders with, the lecture's strategies and the defaults' (the best
//! preset) on the sobol stream, where the scrambles give the standard error: at the Lambertian
//! floor every method; on the plates every combination but the average (weights 1/2, the mean
//! of the two techniques' variances), which cannot see 2 % on the sharpest plates, nor can light
//! or BSDF sampling alone. With the independent stream the per-sample standard error of N
//! estimates is the whole story: printed, not required.

use crate::glossy::cone_quadrature_at;
use crate::harness::{N, add, lambert_out, level, methods, scaled, settings, sphere_e};
use crate::lambertian::{SPHERE_L, sphere_scene};
use picomis::{Heuristic, Light, Method, Preset, RenderSettings, SamplerKind, Shape, ShapeId, Vec3};
use picomis_host::{HOST_LIGHTS, HOST_MATERIALS, HOST_SHAPES, HostScene};
use picomis_tests::{check_mean_at, d3, direct_run, shading_hit, t_threshold};
use std::path::Path;

/// A standard error no larger than this share of the value (the suite's own limit is 2 %).
const MAX_REL_STDERR: f64 = 0.02;

/// One check and its injected biases, on every channel.
struct Row {
    label: String,
    /// The largest |z| of the estimate (must be within the threshold).
    z: f64,
    /// The largest relative standard error of the channels.
    rel_se: f64,
    /// The threshold of the check.
    threshold: f64,
    /// The smallest |z| of the biased estimates.
    z_biased: f64,
    /// Whether the check fails on every biased estimate.
    caught: bool,
}

impl Row {
    fn catches(&self) -> bool {
        self.caught
    }
}

/// A shading point, the direction it is seen from, and its exact reflected radiance.
struct Point {
    hit: picomis::Hit,
    wo: Vec3,
    exact: [f64; 3],
}

/// Runs the check of `settings` at `at` and with the bias `bias` injected; `Err` when the check
/// fails on the estimate itself.
fn check(
    label: &str,
    scene: &HostScene,
    settings: &RenderSettings,
    at: &Point,
    stream: u32,
    bias: f64,
) -> Result<Row, String> {
    let Point { hit, wo, exact } = at;
    let run = direct_run(scene, settings, hit, *wo, stream, N);
    let mut row = Row {
        label: label.to_string(),
        z: 0.0,
        rel_se: 0.0,
        threshold: 0.0,
        z_biased: f64::INFINITY,
        caught: true,
    };
    for (c, est) in run.totals().iter().enumerate() {
        let z = check_mean_at(&format!("{label} [channel {c}]"), est, exact[c], MAX_REL_STDERR, level())?;
        row.z = row.z.max(z.abs());
        row.rel_se = row.rel_se.max(est.stderr / exact[c].abs());
        row.threshold = t_threshold(est.dof, level());
        for k in [1.0 + bias, 1.0 - bias] {
            let scaled = est.scaled(k);
            // |z| of the biased estimate (infinite for an exact one: a zero standard error, as
            // the control variate gives where every light is unblocked).
            let z = if scaled.stderr > 0.0 { scaled.z(exact[c]).abs() } else { f64::INFINITY };
            row.z_biased = row.z_biased.min(z);
            row.caught &= check_mean_at("biased", &scaled, exact[c], MAX_REL_STDERR, level()).is_err();
        }
    }
    Ok(row)
}

/// The lecture's strategies and the defaults' (the best preset's), with `method`.
fn strategies(method: Method, kind: SamplerKind) -> [(&'static str, RenderSettings); 2] {
    let lecture = settings(method, 1, 1).with_sampler(kind);
    let best = settings(Method::Mis(Heuristic::Power { beta: 2.0 }), 1, 1)
        .with_strategies_of(Preset::Best)
        .with_method(method)
        .expect("the best preset takes every method")
        .with_sampler(kind);
    [("lecture", lecture), ("defaults", best)]
}

/// Prints the rows and fails on the checks that must catch the bias but do not.
fn report(title: &str, bias: f64, rows: &[(bool, Row)], failures: Vec<String>) {
    println!("\n{title}: can each check see a bias of {:.0} %?", 100.0 * bias);
    println!("| check | max |z| | rel. stderr | threshold | least bias seen | |z| biased | caught |");
    println!("|---|---:|---:|---:|---:|---:|---|");
    let mut failures = failures;
    for (must, r) in rows {
        println!(
            "| {} | {:.2} | {:.4} % | {:.2} | {:.2} % | {:.1} | {} |",
            r.label,
            r.z,
            100.0 * r.rel_se,
            r.threshold,
            100.0 * r.threshold * r.rel_se,
            r.z_biased,
            if r.catches() {
                "yes"
            } else if *must {
                "NO"
            } else {
                "no (not required)"
            }
        );
        if *must && !r.catches() {
            failures.push(format!(
                "{}: a {:.0} % bias passes (|z| {:.2})",
                r.label,
                100.0 * bias,
                r.z_biased
            ));
        }
    }
    let caught = rows.iter().filter(|(_, r)| r.catches()).count();
    let required = rows.iter().filter(|(must, _)| *must).count();
    println!("{caught} of {} checks catch it; {required} must.", rows.len());
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// 1 % at a Lambertian floor under a sphere light overhead (case (a)), every method.
#[test]
fn a_one_percent_bias_at_a_lambertian_receiver_is_caught() {
    let bias = 0.01;
    let (r, d) = (1.0, 3.0);
    let (scene, c) = sphere_scene(0.0, r, d);
    let exact = lambert_out(scaled(SPHERE_L, sphere_e(c, r)));
    let at = Point {
        hit: shading_hit(ShapeId::new(0), Vec3::ZERO, Vec3::Y),
        wo: crate::harness::check_wo(),
        exact,
    };
    let (mut rows, mut failures) = (Vec::new(), Vec::new());
    for kind in SamplerKind::ALL {
        for (i, (name, method)) in methods().into_iter().enumerate() {
            for (j, (preset, s)) in strategies(method, kind).into_iter().enumerate() {
                let label = format!("Lambert, {name}, {preset}, {}", kind.name());
                let stream = 30_000 + 100 * j as u32 + i as u32;
                match check(&label, &scene, &s, &at, stream, bias) {
                    Ok(row) => rows.push((kind == SamplerKind::Sobol, row)),
                    Err(e) => failures.push(e),
                }
            }
        }
    }
    report("(a) a Lambertian floor under a sphere light", bias, &rows, failures);
}

/// The Veach scene (scenes/veach_mis.json) and its plates: (shape, material's alpha).
fn veach() -> (HostScene, Vec<ShapeId>) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/veach_mis.json");
    let file = picomis_format::SceneFile::load(&path).unwrap_or_else(|e| panic!("{e}"));
    let scene = file.build::<HOST_SHAPES, HOST_LIGHTS, HOST_MATERIALS>().unwrap_or_else(|e| panic!("{e}"));
    let plates = (0..scene.objects().len() as u16)
        .map(ShapeId::new)
        .filter(|&id| scene.material(id).is_some_and(|m| matches!(m, picomis::Material::GgxConductor { .. })))
        .collect();
    (scene, plates)
}

/// The point of the plate (a quad, corners `q`, unit normal `n`) that mirrors the centre `c` of
/// a light to the eye `e`: where the line from the eye to `c` reflected in the plate's plane
/// meets the plane.
fn mirror_point(q: [Vec3; 4], n: Vec3, e: Vec3, c: Vec3) -> Vec3 {
    let mirrored = c - 2.0 * (c - q[0]).dot(n) * n;
    let dir = mirrored - e;
    e + dir * ((q[0] - e).dot(n) / dir.dot(n))
}

/// 2 % on each of Veach's four glossy plates (GGX alpha 0.005 to 0.1), at the points where each
/// plate mirrors each of the four row lights towards the camera: the reflected light of every
/// sphere light by quadrature over its cone (`cone_quadrature_at`; no surface blocks a light
/// there: checked by rays through each light's cone).
#[test]
fn a_two_percent_bias_on_the_veach_plates_is_caught() {
    let bias = 0.02;
    let (scene, plates) = veach();
    assert_eq!(plates.len(), 4, "the Veach scene has four glossy plates");
    let eye = scene.camera().desc().origin;
    let lights: Vec<(ShapeId, Vec3, f32, picomis::Rgb)> = scene
        .lights()
        .iter()
        .filter_map(|l| match *l {
            Light::Area { shape, radiance } => {
                scene.shape(shape).and_then(Shape::as_sphere).map(|(c, r)| (shape, c, r, radiance))
            }
            _ => None,
        })
        .collect();
    assert_eq!(lights.len(), 5, "four row lights and the fill light");
    let (mut rows, mut failures, mut points) = (Vec::new(), Vec::new(), 0);
    for (p, &plate) in plates.iter().enumerate() {
        let shape = scene.shape(plate).expect("a plate");
        let q = shape.corners().expect("a quad");
        let n = shape.normal_at(q[0]);
        let material = *scene.material(plate).expect("the plate's material");
        // The four row lights (y = 0), each mirrored to the eye somewhere on the plate.
        for (k, &(_, c, _, _)) in lights.iter().filter(|l| l.1.y == 0.0).enumerate() {
            let x = mirror_point(q, n, eye, c);
            let wo = (eye - x).normalize();
            // Every light in full view or hidden (a light half hidden has no quadrature here).
            let Some(exact) = lights.iter().try_fold([0.0; 3], |sum, &(id, lc, lr, l)| {
                Some(match visibility(&scene, x, n, id, lc, lr)? {
                    true => add(sum, cone_quadrature_at(&material, x, n, lc, lr, l, wo)),
                    false => sum,
                })
            }) else {
                println!(
                    "plate {}: the point mirroring light {k} sees a light partly hidden; left out",
                    p + 1
                );
                continue;
            };
            points += 1;
            let at = Point { hit: shading_hit(plate, x, n), wo, exact };
            for (i, (name, method)) in methods().into_iter().enumerate() {
                for (j, (preset, s)) in strategies(method, SamplerKind::Sobol).into_iter().enumerate() {
                    let label = format!("plate {} (x {:.2}), {name}, {preset}", p + 1, x.x);
                    let stream = 40_000 + 1000 * p as u32 + 100 * k as u32 + 10 * j as u32 + i as u32;
                    // Light sampling alone and BSDF sampling alone are not what renders a plate,
                    // nor the average of the two (weights 1/2: the mean of their variances);
                    // every other combination of the two must see the bias.
                    let must = matches!(method, Method::Mis(h) if h != Heuristic::Average);
                    match check(&label, &scene, &s, &at, stream, bias) {
                        Ok(row) => rows.push((must, row)),
                        Err(e) if must => failures.push(e),
                        Err(e) => println!("not required: {e}"),
                    }
                }
            }
        }
    }
    assert!(points >= 12, "only {points} of the 16 points see every light whole or not at all");
    report("Veach's glossy plates, sobol", bias, &rows, failures);
}

/// Whether rays from `x` (normal `n`) through the cone of the sphere light `light` (centre `c`,
/// radius `r`; 64 x 64 directions over the cone) all reach it first (`Some(true)`), none does
/// (`Some(false)`), or some do (`None`).
fn visibility(scene: &HostScene, x: Vec3, n: Vec3, light: ShapeId, c: Vec3, r: f32) -> Option<bool> {
    let axis = d3(c) - d3(x);
    let cap = picomis_tests::Cap::new(axis.normalize(), (f64::from(r) / axis.length()).asin());
    let origin = x + 1e-4 * n;
    let seen = (0..64 * 64)
        .filter(|i| {
            let (a, b) = ((f64::from(i % 64) + 0.5) / 64.0, (f64::from(i / 64) + 0.5) / 64.0);
            let ray = picomis::Ray { origin, dir: picomis_tests::f3(cap.direction(a, b)) };
            scene.intersect(&ray, 0.0, f32::INFINITY, None).is_some_and(|h| h.object == light)
        })
        .count();
    match seen {
        0 => Some(false),
        4096 => Some(true),
        _ => None,
    }
}
