//! The Veach scene rendered by picomis converges to an independent renderer's image: Mitsuba 3.9.1
//! (`direct` integrator, power heuristic, ~37,000 spp, independent sampler, box filter),
//! `tests/data/veach_mis.ref.exr` (see scenes/FORMAT.md).
//!
//! Both images carry Monte Carlo noise, so the comparison is statistical, per RGB channel, on
//! 16x16-pixel blocks:
//! - picomis renders the scene K times with independent seeds. Pixels are independent in picomis
//!   (each has its own random stream), so a block mean's variance is the sum of its pixels'
//!   variances over n^2, each estimated from the K sub-renders: a well-determined standard error.
//! - Pixels that see an emitter (any camera sample hit one) are left out of the block means: their
//!   values are the emitters' radiance, not the estimator under test, with huge variance at the
//!   silhouettes.
//! - The reference's own noise. It is a single image (the mean of its passes; no per-pass data or
//!   variance channel exists), so its per-pixel variance can only be estimated from local
//!   neighbourhoods: the discrete Laplacian L[x](p) = x(p) - (sum of the 4 neighbours) / 4
//!   removes the smooth signal, and applied to both images it also removes what they share, so
//!   e(p) = L[ref](p) - L[ours](p) has mean 0 where both are unbiased and variance
//!   ~1.25 (var_ref + var_ours) (pixels are independent in both renderers: Mitsuba's sampler is
//!   `independent`, the filter `box`); var_ref = mean(e^2 - 1.25 var_ours) / 1.25 with var_ours
//!   known from the K sub-renders. MEASURED this way over all blocks, with its standard error.
//!   The measurement is loose (it subtracts our own, much larger noise): too loose per block, so
//!   the z-scores use a MODEL, the larger of FORMAT.md's 0.015 RMS per pixel and our block error
//!   times sqrt(our spp / 37,000) (Mitsuba ran the same estimator), and the test asserts that the
//!   model agrees with the measurement within 4 of its standard errors.
//! - z = (ours - ref) / sqrt(se_ours^2 + se_ref^2) per block and per channel.
//!
//! Asserted, for each of R, G and B: more than 300 blocks; |z| < 3 in at least 98 % of them; no
//! block at |z| >= 5; the whole image (sum of the blocks) within |z| < 4; the same renders scaled
//! by 0.95 or 1.05 fail those checks (so the test can fail); and the noise model agrees with the
//! measured noise. The test prints its figures
//! (`--nocapture`); the README quotes the current run.

use picomis::{Heuristic, Method, RenderSettings, Rgb, SamplerKind};
use picomis_sim::output::read_exr;
use picomis_sim::render::RenderBatch;
use picomis_sim::scenes;

const BLOCK: usize = 16;
/// Samples per pixel of the reference (scenes/FORMAT.md).
const REFERENCE_SPP: f64 = 37_000.0;
/// Independent sub-renders (seeds 1..=K).
const K: u32 = 8;

/// Camera samples per sub-render: 32 in release builds (about 25 M camera samples in all, a few
/// seconds on 2 cores); 8 in debug builds, where the kernel is ~10x slower. The z-scores account
/// for the noise either way.
const SPP: u32 = if cfg!(debug_assertions) { 8 } else { 32 };

const CHANNELS: [&str; 3] = ["R", "G", "B"];

fn channel(c: Rgb, k: usize) -> f64 {
    f64::from([c.x, c.y, c.z][k])
}

#[derive(Debug)]
struct Comparison {
    blocks: usize,
    max_abs_z: f64,
    within_3: f64,
    mean_rel_diff: f64,
    overall_rel_diff: f64,
    overall_z: f64,
    /// RMS of the reference's measured per-pixel noise over the blocks' pixels.
    ref_rms_noise: f64,
    /// Standard error of the measured mean per-pixel variance behind `ref_rms_noise`.
    ref_var_se: f64,
    /// The mean per-pixel variance of the reference that the model predicts (our noise scaled).
    ref_var_model: f64,
    /// RMS of our mean image's per-pixel noise (K x SPP spp).
    ours_rms_noise: f64,
}

/// Per-pixel statistics of one channel: picomis' K sub-renders (mean, variance of that mean) and
/// the reference; the emitter mask is shared by the channels.
struct Renders {
    width: usize,
    height: usize,
    mean: Vec<f64>,
    var_of_mean: Vec<f64>,
    reference: Vec<f64>,
}

fn render(loaded: &scenes::Loaded) -> (Vec<Renders>, Vec<bool>) {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/veach_mis.ref.exr");
    let reference = read_exr(std::path::Path::new(path)).expect("reading the reference");
    let film = loaded.file.film();
    assert_eq!((reference.width, reference.height), (film.width(), film.height()));
    // The reference's settings: power heuristic (beta 2), 1 light + 1 BSDF sample, independent
    // numbers: the model of the reference's noise scales our per-pixel variance to its spp, which
    // holds for Monte Carlo variance (Mitsuba's reference), not for a stratified stream's, whose
    // variance falls faster than 1 / spp (its convergence is the study's, not this test's).
    let method = Method::Mis(Heuristic::Power { beta: 2.0 });
    let settings: Vec<RenderSettings> = (1..=K)
        .map(|seed| {
            RenderSettings::new(method, 1, 1, SPP, seed).unwrap().with_sampler(SamplerKind::Independent)
        })
        .collect();
    let scene = loaded.build(film).unwrap();
    let batch = RenderBatch { settings: &settings, message: "veach_mis" }.run(&scene).unwrap();
    let (width, height) = (film.width() as usize, film.height() as usize);
    let k = f64::from(K);
    let emitter: Vec<bool> = (0..width * height)
        .map(|p| batch.images.iter().any(|img| img.pixels[p].emitted != Rgb::ZERO))
        .collect();
    let per_channel = (0..3)
        .map(|c| {
            let mut r = Renders {
                width,
                height,
                mean: vec![0.0; width * height],
                var_of_mean: vec![0.0; width * height],
                reference: reference.data.iter().map(|&v| channel(v, c)).collect(),
            };
            for p in 0..width * height {
                let v: Vec<f64> =
                    batch.images.iter().map(|img| channel(img.pixels[p].radiance(), c)).collect();
                let m = v.iter().sum::<f64>() / k;
                r.mean[p] = m;
                r.var_of_mean[p] = v.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / (k - 1.0) / k;
            }
            r
        })
        .collect();
    (per_channel, emitter)
}

/// The reference's per-pixel noise variance averaged over the pixels of one block, from the
/// Laplacian residual (module docs); `None` if the block has too few usable pixels.
fn reference_variance(r: &Renders, emitter: &[bool], bx: usize, by: usize, scale: f64) -> Option<(f64, f64)> {
    let (w, h) = (r.width, r.height);
    let (mut sum, mut sum2, mut n) = (0.0, 0.0, 0.0);
    for y in (by * BLOCK).max(1)..((by + 1) * BLOCK).min(h - 1) {
        for x in (bx * BLOCK).max(1)..((bx + 1) * BLOCK).min(w - 1) {
            let p = y * w + x;
            let nb = [p - 1, p + 1, p - w, p + w];
            if emitter[p] || nb.iter().any(|&q| emitter[q]) {
                continue;
            }
            let lap = |img: &dyn Fn(usize) -> f64| img(p) - nb.iter().map(|&q| img(q)).sum::<f64>() / 4.0;
            let e = lap(&|q| r.reference[q]) - lap(&|q| scale * r.mean[q]);
            let var_ours =
                scale * scale * (r.var_of_mean[p] + nb.iter().map(|&q| r.var_of_mean[q]).sum::<f64>() / 16.0);
            let x = (e * e - var_ours) / 1.25;
            sum += x;
            sum2 += x * x;
            n += 1.0;
        }
    }
    // The per-pixel mean of the estimate and the sum of its squares (for its standard error).
    (n >= (BLOCK * BLOCK / 2) as f64).then(|| ((sum / n).max(0.0), sum2))
}

/// Compares `scale` times picomis' image with the reference, in one channel.
fn compare(r: &Renders, emitter: &[bool], scale: f64) -> Comparison {
    let b = BLOCK;
    let (mut zs, mut rel) = (Vec::new(), Vec::new());
    let (mut sum_ours, mut sum_ref, mut sum_var) = (0.0, 0.0, 0.0);
    let (mut ref_noise, mut ours_noise, mut noise_pixels) = (0.0, 0.0, 0.0);
    let (mut ref_x2, mut model_var) = (0.0, 0.0);
    for by in 0..r.height / b {
        for bx in 0..r.width / b {
            let (mut o, mut re, mut v, mut n) = (0.0, 0.0, 0.0, 0.0);
            for y in by * b..(by + 1) * b {
                for x in bx * b..(bx + 1) * b {
                    let p = y * r.width + x;
                    if !emitter[p] {
                        o += scale * r.mean[p];
                        re += r.reference[p];
                        v += scale * scale * r.var_of_mean[p];
                        n += 1.0;
                    }
                }
            }
            if n < (b * b / 2) as f64 {
                continue; // a block that is mostly emitter
            }
            let Some((var_ref_pixel, x2)) = reference_variance(r, emitter, bx, by, scale) else { continue };
            ref_x2 += x2;
            // The reference's error in z (of the block's sum): the model, the larger of FORMAT.md's
            // 0.015 RMS per pixel and our noise scaled to its sample count (Mitsuba ran the same
            // estimator). The measured value is too loose to use per block (see the test).
            let var_ref = (0.015f64 * 0.015 * n).max(v * f64::from(K * SPP) / REFERENCE_SPP);
            model_var += v * f64::from(K * SPP) / REFERENCE_SPP;
            sum_ours += o;
            sum_ref += re;
            sum_var += v + var_ref;
            ref_noise += var_ref_pixel * n; // measured
            ours_noise += v; // sum of the per-pixel variances of our mean
            noise_pixels += n;
            let (o, re) = (o / n, re / n);
            let se2 = (v + var_ref) / (n * n);
            zs.push((o - re) / se2.sqrt());
            rel.push((o - re).abs() / re.abs().max(1e-3));
        }
    }
    let blocks = zs.len();
    Comparison {
        blocks,
        max_abs_z: zs.iter().fold(0.0f64, |m, z| m.max(z.abs())),
        within_3: zs.iter().filter(|z| z.abs() < 3.0).count() as f64 / blocks as f64,
        mean_rel_diff: rel.iter().sum::<f64>() / blocks as f64,
        overall_rel_diff: (sum_ours - sum_ref) / sum_ref,
        overall_z: (sum_ours - sum_ref) / sum_var.sqrt(),
        ref_rms_noise: (ref_noise / noise_pixels).sqrt(),
        ref_var_se: ((ref_x2 / noise_pixels - (ref_noise / noise_pixels).powi(2)) / noise_pixels).sqrt(),
        ref_var_model: model_var / noise_pixels,
        ours_rms_noise: (ours_noise / noise_pixels).sqrt(),
    }
}

fn agrees(c: &Comparison) -> bool {
    // Gaussian z: 99.7 % of blocks within 3 sigma; allow 2 % of blocks (heavy-tailed glints), no
    // block beyond 5 sigma, and the image's total within 4 sigma.
    c.blocks > 300 && c.within_3 >= 0.98 && c.max_abs_z < 5.0 && c.overall_z.abs() < 4.0
}

#[test]
fn veach_converges_to_the_mitsuba_reference() {
    converges(&scenes::load(Some("veach_mis")).unwrap(), "veach_mis");
}

/// The scene Mitsuba rendered, imported from its own XML (`picomis-sim import`; rectangles as
/// `matrix` transforms), converges to the same reference.
#[test]
fn the_imported_mitsuba_xml_converges_to_the_reference_too() {
    let xml = concat!(env!("CARGO_MANIFEST_DIR"), "/../format/tests/data/veach_mis.xml");
    let json = picomis_format::mitsuba::import_file(std::path::Path::new(xml)).unwrap();
    let file = picomis_format::SceneFile::parse(&json, "veach_mis.xml").unwrap();
    converges(&scenes::Loaded { file, builtin: None }, "veach_mis.xml imported");
}

fn converges(loaded: &scenes::Loaded, label: &str) {
    let (channels, emitter) = render(loaded);
    let mut failures = Vec::new();
    for (name, r) in CHANNELS.iter().zip(&channels) {
        let c = compare(r, &emitter, 1.0);
        println!(
            "{label} vs Mitsuba 3, channel {name} ({K} x {SPP} spp, {} 16x16 blocks without emitter \
             pixels): mean |relative difference| per block {:.4}, whole image {:+.5} (z {:+.2}), max |z| \
             {:.2}, |z| < 3 in {:.1} % of blocks; reference noise per pixel: measured variance {:.2e} +- \
             {:.1e} (RMS {:.4}), modelled {:.2e} (RMS {:.4}); ours (mean of {} spp) RMS {:.4}",
            c.blocks,
            c.mean_rel_diff,
            c.overall_rel_diff,
            c.overall_z,
            c.max_abs_z,
            100.0 * c.within_3,
            c.ref_rms_noise * c.ref_rms_noise,
            c.ref_var_se,
            c.ref_rms_noise,
            c.ref_var_model,
            c.ref_var_model.sqrt(),
            K * SPP,
            c.ours_rms_noise
        );
        if !agrees(&c) {
            failures.push(format!("channel {name}: {c:?}"));
        }
        // The model of the reference's noise must agree with the measurement (within 4 of the
        // measurement's standard errors; the measurement is loose: it subtracts our own noise).
        let model_z = (c.ref_rms_noise * c.ref_rms_noise - c.ref_var_model) / c.ref_var_se;
        if model_z.abs() >= 4.0 {
            failures.push(format!(
                "channel {name}: the reference's noise model is off the measurement (z {model_z:.1})"
            ));
        }
        // The test can fail: the same renders off by 5 % are rejected.
        for scale in [0.95, 1.05] {
            let off = compare(r, &emitter, scale);
            println!(
                "  channel {name} scaled by {scale}: whole image z {:+.1}, max |z| {:.1}, |z| < 3 in {:.1} % -> {}",
                off.overall_z,
                off.max_abs_z,
                100.0 * off.within_3,
                if agrees(&off) { "accepted" } else { "rejected" }
            );
            if agrees(&off) {
                failures.push(format!("channel {name}: a {scale}x image was accepted: {off:?}"));
            }
        }
    }
    assert!(failures.is_empty(), "picomis disagrees with the reference:\n{}", failures.join("\n"));
}
