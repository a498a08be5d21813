//! What every check shares: the estimates per check and the tolerance, the methods, their
//! settings, the closed forms' small helpers, and the check of every method at the origin of a
//! floor against an exact value, for every sample stream.

use picomis::{Heuristic, LightSelection, Method, RenderSettings, Rgb, SamplerKind, SphereSampling, Vec3};
use picomis_host::HostScene;
use picomis_tests::{
    MeanEstimate, RgbStats, check_mean_at, d3, direct_run, family_z, rgb64, shading_hit, sphere_irradiance,
};
use std::f64::consts::PI;

/// Estimates per check.
pub const N: u32 = 200_000;
/// Largest standard error allowed, relative to the exact value.
pub const MAX_REL_STDERR: f64 = 0.02;
/// The suite's z-tests: every check of every test here, one per colour channel (3,159 counted on
/// 2026-12-07 by printing a line from each; rounded up). With a threshold of 4 on each, one of
/// them fails by chance on about a fifth of fresh draws of the streams (3,159 x 6.3e-5); at
/// [`z_max`] on at most [`FAMILY_LEVEL`] of them.
pub const Z_TESTS: f64 = 3200.0;
/// The chance that the whole suite fails by chance on a fresh draw of its streams.
pub const FAMILY_LEVEL: f64 = 1e-3;

/// The threshold on |z| of each check ([`family_z`]: Bonferroni over [`Z_TESTS`]).
pub fn z_max() -> f64 {
    family_z(Z_TESTS, FAMILY_LEVEL)
}

/// The two-sided level of each check (for the checks with Student's t: [`check_mean_at`]).
pub fn level() -> f64 {
    FAMILY_LEVEL / Z_TESTS
}

/// Seed of every render setting here.
const SEED: u32 = 2024;

pub const ALBEDO: Rgb = Rgb::new(0.8, 0.5, 0.2);

/// Every method of the kernel.
pub fn methods() -> Vec<(String, Method)> {
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

pub fn settings(method: Method, n_light: u16, n_bsdf: u16) -> RenderSettings {
    RenderSettings::new(method, n_light, n_bsdf, 1, SEED).unwrap()
}

/// Exact reflected radiance of a Lambertian receiver (albedo [`ALBEDO`]) under irradiance `e`.
pub fn lambert_out(e: [f64; 3]) -> [f64; 3] {
    let a = rgb64(ALBEDO);
    [a[0] / PI * e[0], a[1] / PI * e[1], a[2] / PI * e[2]]
}

pub fn scaled(c: Rgb, s: f64) -> [f64; 3] {
    rgb64(c).map(|v| v * s)
}

pub fn add(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

/// Irradiance per unit radiance at the origin (normal +y) from a sphere.
pub fn sphere_e(c: Vec3, r: f32) -> f64 {
    let v = d3(c);
    let d = v.length();
    sphere_irradiance(1.0, f64::from(r), d, v.y / d)
}

/// Checks every method in `methods` at the origin of the floor (object 0, normal +y).
#[allow(clippy::too_many_arguments)]
pub fn check_methods(
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
            let run = direct_run(scene, &s, &hit, wo, stream + k as u32, N);
            let label =
                format!("{label}, {name}, n = {counts:?}, {spheres:?}, {selection:?}, {}", kind.name());
            assert_estimates(&label, &run.totals(), exact);
        }
    }
}

/// Prints the estimate of channel 0 against `exact` and asserts every channel's within the
/// suite's level ([`level`]): the standard error is the spread of the 32 scrambles for sobol
/// (Student's t, 31 degrees of freedom), the per-sample formula for the independent stream.
#[track_caller]
pub fn assert_estimates(label: &str, est: &[MeanEstimate; 3], exact: [f64; 3]) {
    let e = &est[0];
    println!(
        "{label}: mean {:.5e} exact {:.5e} stderr {:.3}% z {:+.2} ({} dof)",
        e.mean,
        exact[0],
        100.0 * e.stderr / exact[0],
        e.z(exact[0]),
        e.dof
    );
    for (c, (e, x)) in est.iter().zip(exact).enumerate() {
        if let Err(msg) = check_mean_at(&format!("{label} [channel {c}]"), e, x, MAX_REL_STDERR, level()) {
            panic!("{msg}");
        }
    }
}

/// The view direction of [`check_methods`].
pub fn check_wo() -> Vec3 {
    Vec3::new(0.3, 0.9, -0.2).normalize()
}

pub fn report(label: &str, st: &RgbStats, exact: [f64; 3]) {
    let s = &st.0[0];
    println!(
        "{label}: mean {:.5e} exact {:.5e} stderr {:.2}% z {:+.2}",
        s.mean(),
        exact[0],
        100.0 * s.stderr() / exact[0],
        (s.mean() - exact[0]) / s.stderr()
    );
}
