//! The fixed-point ray queries (`Arith::Fixed`, `picomis-sim render --arith fixed`) against f32.
//!
//! 1. On every built-in scene (the `picomis-builtins` list, as `picomis-sim scenes` prints it)
//!    that the format supports, the fixed image agrees with the f32 image: per pixel and over the
//!    whole film, the difference of the means of `N` camera samples is within `Z_PIXEL` (resp.
//!    `Z_IMAGE`) standard errors, the standard error being that of two independent estimates,
//!    `sqrt(se_f32^2 + se_fixed^2)`, each estimated from the pixel's own samples.
//!
//!    Why that bound: if the two renders were independent, each z would be close to a standard
//!    normal (64 samples a pixel). Both take the same random numbers (same seed, pixel and
//!    sample), so their errors are strongly positively correlated and the difference's
//!    variance is smaller than the sum: the test is conservative. It fails when the fixed path's
//!    bias is comparable to the f32 path's own noise at `N` samples (a visible error), and
//!    `a_biased_image_is_rejected` shows that it does for a 10 % bias. A pixel without noise
//!    (both standard errors 0: e.g. only the emitter seen) must agree to `FLAT_RELATIVE`
//!    (hit points move by a few units of 2^-22 of the scene's extent; radiance changes far less).
//! 2. Every built-in scene that the format does not support is rejected with
//!    `SceneError::NotRepresentable`, and so is the fixture `tests/scenes/tiny_light.json` (a
//!    sphere light of radius 1e-4 over a 40-unit plane), naming its light's entry; the command line
//!    says so, naming the file's entry, and exits with status 2.

mod common;

use std::path::{Path, PathBuf};

use picomis::{Arith, Film, RenderSettings, SceneError, Unrepresentable};
use picomis_sim::scenes::{self, BUILTINS, HostScene};
use rayon::prelude::*;

const W: u32 = 24;
const H: u32 = 18;
/// Camera samples per pixel.
const N: u32 = 64;
const SEED: u32 = 11;
/// Largest |z| of a pixel.
const Z_PIXEL: f64 = 5.0;
/// Largest |z| of the film's sum.
const Z_IMAGE: f64 = 4.0;
/// Relative agreement of pixels without noise.
const FLAT_RELATIVE: f64 = 1e-4;
/// Largest relative MSE of the fixed image against the f32 one. Both use the same random
/// numbers, so their noise cancels and only the ray queries' rounding is left (at most 1.2e-11
/// measured): a shape that reaches past its edge shows here even where the z bounds hold
/// because some pixel is noisier still (quads with Q30 dual axes alone gave 0.92 on `stress`).
const MAX_REL_MSE: f64 = 1e-9;

/// Per pixel (row-major): the mean of the `N` camera samples' radiance (the sum of the
/// channels) and the standard error of that mean.
struct Stats {
    mean: Vec<f64>,
    se: Vec<f64>,
}

fn stats(scene: &HostScene, settings: &RenderSettings) -> Stats {
    let renderer = picomis_host::renderer(scene, settings).unwrap();
    let renderer = &*renderer;
    let per_pixel: Vec<(f64, f64)> = (0..W * H)
        .into_par_iter()
        .map(|p| {
            let (x, y) = (p % W, p / W);
            let v: Vec<f64> = (0..N)
                .map(|s| {
                    let r = renderer.camera_sample(x, y, s).radiance();
                    f64::from(r.x) + f64::from(r.y) + f64::from(r.z)
                })
                .collect();
            let n = f64::from(N);
            let mean = v.iter().sum::<f64>() / n;
            let var = v.iter().map(|a| (a - mean).powi(2)).sum::<f64>() / (n - 1.0);
            (mean, (var / n).sqrt())
        })
        .collect();
    Stats { mean: per_pixel.iter().map(|p| p.0).collect(), se: per_pixel.iter().map(|p| p.1).collect() }
}

/// How far `fixed` is from `f32`: the largest |z| of a pixel, that of the film's sum, and the
/// pixels without noise that differ; `Err` says which bound is broken.
fn agreement(f32s: &Stats, fixed: &Stats) -> Result<(f64, f64), String> {
    let (mut z_max, mut sum, mut var) = (0.0f64, 0.0, 0.0);
    for (p, ((a, sa), (b, sb))) in
        f32s.mean.iter().zip(&f32s.se).zip(fixed.mean.iter().zip(&fixed.se)).enumerate()
    {
        let se = (sa * sa + sb * sb).sqrt();
        let d = b - a;
        if se == 0.0 {
            if d.abs() > FLAT_RELATIVE * a.abs().max(b.abs()) {
                return Err(format!("pixel {p} without noise: f32 {a}, fixed {b}"));
            }
            continue;
        }
        z_max = z_max.max((d / se).abs());
        sum += d;
        var += se * se;
    }
    let z_image = if var > 0.0 { (sum / var.sqrt()).abs() } else { 0.0 };
    if z_max > Z_PIXEL {
        return Err(format!("a pixel differs by {z_max:.2} standard errors (bound {Z_PIXEL})"));
    }
    if z_image > Z_IMAGE {
        return Err(format!("the film's sum differs by {z_image:.2} standard errors (bound {Z_IMAGE})"));
    }
    Ok((z_max, z_image))
}

/// How big the difference is: the film's sum, fixed minus f32, relative to f32's, and the
/// relative MSE of the fixed image against the f32 image (mean over pixels of
/// (fixed - f32)^2 / (f32^2 + 0.01), on the pixel means: the study's metric).
fn difference(f32s: &Stats, fixed: &Stats) -> (f64, f64) {
    let (a, b): (f64, f64) = (f32s.mean.iter().sum(), fixed.mean.iter().sum());
    let rel_mse =
        f32s.mean.iter().zip(&fixed.mean).map(|(a, b)| (b - a).powi(2) / (a * a + 0.01)).sum::<f64>()
            / f32s.mean.len().max(1) as f64;
    ((b - a) / a, rel_mse)
}

/// The f32 and fixed statistics of a scene, or the scene's error when fixed point cannot
/// represent it (checked twice: `supports` and `enable_arith` must agree).
fn compare(loaded: &scenes::Loaded) -> Result<(Stats, Stats), SceneError> {
    let settings = loaded.file.default_settings().with_spp(N).unwrap().with_seed(SEED);
    let scene = loaded.build(Film::new(W, H).unwrap()).unwrap();
    let supported = scene.supports(Arith::Fixed);
    let mut fixed = scene.clone();
    let enabled = fixed.enable_arith(Arith::Fixed);
    assert_eq!(supported, enabled, "supports and enable_arith disagree");
    supported?;
    assert_eq!((scene.arith(), fixed.arith()), (Arith::F32, Arith::Fixed));
    Ok((stats(&scene, &settings), stats(&fixed, &settings)))
}

#[test]
fn fixed_agrees_with_f32_on_every_builtin_scene_it_supports() {
    println!(
        "| scene | film | film sum, (fixed - f32) / f32 | rel. MSE fixed vs f32 | largest pixel |z| | film |z| |\n\
         |---|---|---:|---:|---:|---:|"
    );
    let mut supported = Vec::new();
    for b in BUILTINS {
        let loaded = scenes::load(Some(b.name)).unwrap();
        match compare(&loaded) {
            Ok((f32s, fixed)) => {
                let (z_pixel, z_image) =
                    agreement(&f32s, &fixed).unwrap_or_else(|e| panic!("{}: {e}", b.name));
                let (rel_diff, rel_mse) = difference(&f32s, &fixed);
                assert!(rel_mse <= MAX_REL_MSE, "{}: relative MSE against f32 {rel_mse:.2e}", b.name);
                // A row of the README's speed-against-accuracy table (`--nocapture`).
                println!(
                    "| {} | {W}x{H}, {N} spp | {rel_diff:+.1e} | {rel_mse:.1e} | {z_pixel:.2} | {z_image:.2} |",
                    b.name
                );
                supported.push(b.name);
            }
            Err(SceneError::NotRepresentable { entry, reason }) => {
                println!("| {} | rejected: shape {entry}, {reason} | | | | |", b.name);
            }
            Err(e) => panic!("{}: unexpected error {e:?}", b.name),
        }
    }
    // The firmware's scene, and the closed-form one, are among them (not a vacuous loop).
    assert!(supported.contains(&"veach_mis") && supported.contains(&"lambert_sphere"), "{supported:?}");
}

#[test]
fn a_biased_image_is_rejected() {
    // The check can fail: the fixed image of the Veach scene with 10 % more radiance.
    let loaded = scenes::load(Some("veach_mis")).unwrap();
    let (f32s, mut fixed) = compare(&loaded).unwrap();
    assert!(agreement(&f32s, &fixed).is_ok());
    fixed.mean.iter_mut().for_each(|m| *m *= 1.1);
    fixed.se.iter_mut().for_each(|s| *s *= 1.1);
    assert!(agreement(&f32s, &fixed).is_err());
}

fn tiny_light() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/scenes/tiny_light.json")
}

#[test]
fn a_tiny_light_is_rejected_naming_its_entry() {
    let loaded = scenes::load(Some(tiny_light().to_str().unwrap())).unwrap();
    let err = compare(&loaded).err();
    assert_eq!(err, Some(SceneError::NotRepresentable { entry: 1, reason: Unrepresentable::TooSmall }));
    assert_eq!(loaded.file.shape_entry(1), Some("shapes[1] \"tiny_light\""));

    let dir = tempfile::tempdir().unwrap();
    let path = tiny_light();
    let args = ["render", path.to_str().unwrap(), "--width", "8", "--height", "6", "--spp", "1"];
    let out = common::run_in(dir.path(), &[&args[..], &["--arith", "fixed", "--out", "t.png"]].concat());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("shapes[1] \"tiny_light\"") && stderr.contains("too small"), "{stderr}");
    // In f32 the same scene renders.
    common::run_ok(dir.path(), &[&args[..], &["--arith", "f32", "--out", "t.png"]].concat());
}
