//! The Veach scene rendered by picomis converges to an independent renderer's image: Mitsuba 3.9.1
//! (`direct` integrator, power heuristic, ~37,000 spp), `tests/data/veach_mis.ref.exr`, a copy of
//! `shared/scenes/veach_mis.ref.exr` (see scenes/FORMAT.md).
//!
//! Both images carry Monte Carlo noise, so the comparison is statistical, on 16x16-pixel blocks:
//! - picomis renders the scene K times with independent seeds. Pixels are independent in picomis
//!   (each has its own random stream), so a block mean's variance is the sum of its pixels'
//!   variances over n^2, each estimated from the K sub-renders: a well-determined standard error.
//! - Pixels that see an emitter (any camera sample hit one) are left out of the block means: their
//!   values are the emitters' radiance, not the estimator under test, with huge variance at the
//!   silhouettes.
//! - The reference's own standard error per block: FORMAT.md gives its RMS noise as ~0.015 per
//!   pixel (0.015/sqrt(n) per block if spread evenly), but most of it sits in the glints, where
//!   it scales like ours: Mitsuba ran the same kind of estimator (1 light + 1 BSDF sample, power
//!   heuristic) with ~37,000 spp, so its block error is taken as the larger of
//!   0.015/sqrt(n) and our block error times sqrt(our spp / 37,000).
//! - z = (ours - ref) / sqrt(se_ours^2 + se_ref^2) per block.

use picomis::{Heuristic, Method, RenderSettings};
use picomis_sim::output::read_exr;
use picomis_sim::render::RenderBatch;
use picomis_sim::scenes;

const BLOCK: u32 = 16;
const REFERENCE_SPP: f64 = 37_000.0;
/// Independent sub-renders (seeds 1..=K).
const K: u32 = 8;

/// Camera samples per sub-render: 32 in release builds (about 25 M camera samples in all, a few
/// seconds on 2 cores); 8 in debug builds, where the kernel is ~10x slower (~30 s). The z-scores
/// account for the noise either way. Measured (release, 8 x 32 spp): mean |relative difference|
/// per block 0.0058, overall +0.0005 (z +0.26), max |z| 2.64, all 370 blocks within |z| < 3; a 1 %
/// error of the whole image would show as |z| ~ 5 overall.
const SPP: u32 = if cfg!(debug_assertions) { 8 } else { 32 };

#[derive(Debug)]
struct Comparison {
    blocks: usize,
    max_abs_z: f64,
    within_3: f64,
    mean_rel_diff: f64,
    overall_rel_diff: f64,
    overall_z: f64,
}

/// Per-pixel statistics of picomis' K sub-renders (mean luminance, variance of that mean,
/// whether a camera sample saw an emitter) and the reference's luminance.
struct Renders {
    width: usize,
    height: usize,
    mean: Vec<f64>,
    var_of_mean: Vec<f64>,
    emitter: Vec<bool>,
    reference: Vec<f64>,
}

fn lum(c: picomis::Rgb) -> f64 {
    (f64::from(c.x) + f64::from(c.y) + f64::from(c.z)) / 3.0
}

fn render(loaded: &scenes::Loaded) -> Renders {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/veach_mis.ref.exr");
    let reference = read_exr(std::path::Path::new(path)).expect("reading the reference");
    let film = loaded.file.film();
    assert_eq!((reference.width, reference.height), (film.width(), film.height()));
    // The reference's settings: power heuristic (beta 2), 1 light + 1 BSDF sample.
    let method = Method::Mis(Heuristic::Power { beta: 2.0 });
    let settings: Vec<RenderSettings> =
        (1..=K).map(|seed| RenderSettings::new(method, 1, 1, SPP, seed).unwrap()).collect();
    let batch = loaded.visit(film, RenderBatch { settings: &settings, message: "veach_mis" }).unwrap();
    let (width, height) = (film.width() as usize, film.height() as usize);
    let k = f64::from(K);
    let mut r = Renders {
        width,
        height,
        mean: vec![0.0; width * height],
        var_of_mean: vec![0.0; width * height],
        emitter: vec![false; width * height],
        reference: reference.data.iter().map(|&c| lum(c)).collect(),
    };
    for p in 0..width * height {
        let v: Vec<f64> = batch.images.iter().map(|img| lum(img.pixels[p].radiance())).collect();
        let m = v.iter().sum::<f64>() / k;
        r.mean[p] = m;
        r.var_of_mean[p] = v.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / (k - 1.0) / k;
        r.emitter[p] = batch.images.iter().any(|img| img.pixels[p].emitted != picomis::Rgb::ZERO);
    }
    r
}

/// Compares `scale` times picomis' image with the reference.
fn compare(r: &Renders, scale: f64) -> Comparison {
    let ours_spp = f64::from(K * SPP);
    let b = BLOCK as usize;
    let (mut zs, mut rel) = (Vec::new(), Vec::new());
    let (mut sum_ours, mut sum_ref, mut sum_var) = (0.0, 0.0, 0.0);
    for by in 0..r.height / b {
        for bx in 0..r.width / b {
            let (mut o, mut re, mut v, mut n) = (0.0, 0.0, 0.0, 0.0);
            for y in by * b..(by + 1) * b {
                for x in bx * b..(bx + 1) * b {
                    let p = y * r.width + x;
                    if !r.emitter[p] {
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
            sum_ours += o;
            sum_ref += re;
            sum_var += v;
            let (o, re, se_ours) = (o / n, re / n, v.sqrt() / n);
            let se_ref = (0.015 / n.sqrt()).max(se_ours * (ours_spp / REFERENCE_SPP).sqrt());
            zs.push((o - re) / (se_ours * se_ours + se_ref * se_ref).sqrt());
            rel.push((o - re).abs() / re.max(1e-3));
        }
    }
    let blocks = zs.len();
    Comparison {
        blocks,
        max_abs_z: zs.iter().fold(0.0f64, |m, z| m.max(z.abs())),
        within_3: zs.iter().filter(|z| z.abs() < 3.0).count() as f64 / blocks as f64,
        mean_rel_diff: rel.iter().sum::<f64>() / blocks as f64,
        overall_rel_diff: (sum_ours - sum_ref) / sum_ref,
        // Over all blocks, with our error only (the reference's is ~12x smaller).
        overall_z: (sum_ours - sum_ref) / sum_var.sqrt(),
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
    let r = render(loaded);
    let c = compare(&r, 1.0);
    eprintln!(
        "{label} vs Mitsuba 3 reference ({K} x {SPP} spp, {} 16x16 blocks without emitter pixels): \
         mean |relative difference| per block {:.4}, overall relative difference {:+.5} (z {:+.2}), \
         max |z| {:.2}, |z| < 3 in {:.1} % of blocks",
        c.blocks,
        c.mean_rel_diff,
        c.overall_rel_diff,
        c.overall_z,
        c.max_abs_z,
        100.0 * c.within_3
    );
    assert!(agrees(&c), "picomis disagrees with the reference: {c:?}");
    // The test can fail: the same renders off by 5 % are rejected.
    for scale in [0.95, 1.05] {
        let off = compare(&r, scale);
        assert!(!agrees(&off), "a {scale}x image was accepted: {off:?}");
    }
}
