//! Where the error of a Veach render is: relative MSE (mean of (I - R)^2 / (R^2 + 0.01) over
//! pixels and channels, pixels that see an emitter left out) against the Mitsuba reference
//! `host-sim/tests/data/veach_mis.ref.exr`, per region (the shape a pixel's centre sees), and the
//! share of it from each technique (the across-seed variance of the light part, of the BSDF part,
//! and twice their covariance). Writes `target/err_regions.pfm`, the per-pixel relative MSE.
//!
//! `cargo run --release -p picomis-sim --example err_regions`; environment: `SPP` (64), `SEEDS`
//! (4), `SELECTION` (contribution), `SAMPLER` (sobol), `BETA` (the scene's).

use picomis::{Estimate, LightSelection, Method, RenderSettings, Rgb, SamplerKind, Vec2};
use picomis_sim::render::{progress_bar, render_estimates};
use picomis_sim::scenes::{self, HostScene};
use picomis_sim::study::reference;

fn env<T: std::str::FromStr>(name: &str, default: T) -> T {
    std::env::var(name).ok().and_then(|v| v.parse().ok()).unwrap_or(default)
}

const NAMES: [&str; 11] =
    ["plate1", "plate2", "plate3", "plate4", "floor", "wall", "l0", "l1", "l2", "l3", "fill"];

struct Job {
    settings: RenderSettings,
    seeds: u32,
}

impl Job {
    fn run(self, scene: &HostScene) {
        let film = scene.film();
        let (w, h) = (film.width(), film.height());
        let reference = reference::mitsuba(None, w, h).expect("reference");
        let n = (w * h) as usize;
        // Region of each pixel: the shape its centre sees (12: nothing).
        let region: Vec<usize> = (0..n)
            .map(|i| {
                let (x, y) = ((i as u32 % w) as f32 + 0.5, (i as u32 / w) as f32 + 0.5);
                let (ray, t) = scene.camera().ray(Vec2::new(x / w as f32, y / h as f32));
                scene.intersect(&ray, t, f32::INFINITY, None).map_or(11, |hit| hit.object.index().min(11))
            })
            .collect();
        let bar = progress_bar(u64::from(self.seeds) * u64::from(h) * u64::from(self.settings.spp()), "err");
        let images: Vec<Vec<Estimate>> = (0..self.seeds)
            .map(|s| render_estimates(scene, &self.settings.with_seed(s), &bar).expect("settings").pixels)
            .collect();
        bar.finish_and_clear();
        let k = f64::from(self.seeds);
        // Per region: pixels, rel MSE sum, var light, var bsdf, 2 cov, bias^2 (all relative).
        let mut acc = [[0.0f64; 6]; 12];
        let mut map = vec![Rgb::ZERO; n];
        let ch = |c: Rgb, j: usize| f64::from([c.x, c.y, c.z][j]);
        for i in 0..n {
            if images.iter().any(|img| img[i].emitted != Rgb::ZERO) {
                continue;
            }
            let r = region[i];
            acc[r][0] += 1.0;
            let mut px = 0.0;
            let mut bias_px = 0.0;
            for j in 0..3 {
                let refv = ch(reference[i], j);
                let denom = refv * refv + 0.01;
                let (mut ml, mut mb, mut sll, mut sbb, mut slb, mut se) = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
                for img in &images {
                    let (l, b) = (ch(img[i].light.contribution, j), ch(img[i].bsdf.contribution, j));
                    ml += l;
                    mb += b;
                    sll += l * l;
                    sbb += b * b;
                    slb += l * b;
                    se += (l + b - refv).powi(2);
                }
                ml /= k;
                mb /= k;
                let vl = (sll / k - ml * ml) * k / (k - 1.0);
                let vb = (sbb / k - mb * mb) * k / (k - 1.0);
                let cv = (slb / k - ml * mb) * k / (k - 1.0);
                let e = se / k / denom / 3.0;
                px += e;
                acc[r][1] += e;
                acc[r][2] += vl / denom / 3.0;
                acc[r][3] += vb / denom / 3.0;
                acc[r][4] += 2.0 * cv / denom / 3.0;
                acc[r][5] += (ml + mb - refv).powi(2) / denom / 3.0;
                bias_px += (ml + mb - refv).powi(2) / denom / 3.0;
            }
            map[i] = Rgb::splat(if std::env::var("BIASMAP").is_ok() { bias_px as f32 } else { px as f32 });
        }
        let total_px: f64 = acc.iter().map(|a| a[0]).sum();
        let total: f64 = acc.iter().map(|a| a[1]).sum();
        println!(
            "{} / {} / {}, {} spp, {} seeds: rel MSE {:.3e} over {} pixels",
            self.settings.sampler().name(),
            self.settings.light_selection().name(),
            self.settings.method(),
            self.settings.spp(),
            self.seeds,
            total / total_px,
            total_px
        );
        println!(
            "| region | pixels | share of error | region rel MSE | var light | var bsdf | 2 cov | bias^2 (of mean) |"
        );
        println!("|---|---:|---:|---:|---:|---:|---:|---:|");
        for (r, a) in acc.iter().enumerate() {
            if a[0] == 0.0 {
                continue;
            }
            let name = NAMES.get(r).copied().unwrap_or("none");
            println!(
                "| {name} | {} | {:.1} % | {:.3e} | {:.3e} | {:.3e} | {:.3e} | {:.3e} |",
                a[0],
                100.0 * a[1] / total,
                a[1] / a[0],
                a[2] / a[0],
                a[3] / a[0],
                a[4] / a[0],
                a[5] / a[0]
            );
        }
        let img = picomis_sim::output::Image { width: w, height: h, data: map };
        let bytes = picomis_sim::output::encode(&img, picomis_sim::output::Format::Pfm).expect("pfm");
        std::fs::write(concat!(env!("CARGO_MANIFEST_DIR"), "/../target/err_regions.pfm"), bytes)
            .expect("write");
        // log10 of the per-pixel rel MSE from 1e-5 (black) to 1e-1 (white).
        let grey: Vec<u8> = img
            .data
            .iter()
            .flat_map(|c| {
                let v = ((c.x.max(1e-9).log10() + 5.0) / 4.0).clamp(0.0, 1.0);
                [(v * 255.0) as u8; 3]
            })
            .collect();
        let png = picomis_sim::output::encode_png(w, h, &grey).expect("png");
        std::fs::write(concat!(env!("CARGO_MANIFEST_DIR"), "/../target/err_regions.png"), png)
            .expect("write");
    }
}

fn main() {
    let loaded = scenes::load(Some("veach_mis")).expect("veach");
    let mut settings = loaded.file.default_settings();
    let spp = env("SPP", 64u32);
    let selection =
        LightSelection::from_name(&env("SELECTION", "contribution".to_string())).expect("selection");
    let sampler = SamplerKind::from_name(&env("SAMPLER", "sobol".to_string())).expect("sampler");
    if let Ok(beta) = std::env::var("BETA") {
        let (nl, nb) = settings.sample_counts();
        let m = Method::from_name("power")
            .expect("power")
            .with_parameters(beta.parse().ok(), None)
            .expect("beta");
        settings = RenderSettings::new(m, nl, nb, spp, 0)
            .expect("settings")
            .with_sphere_sampling(settings.sphere_sampling())
            .with_quad_sampling(settings.quad_sampling());
    }
    let settings = settings.with_spp(spp).expect("spp").with_light_selection(selection).with_sampler(sampler);
    let job = Job { settings, seeds: env("SEEDS", 4u32).max(2) };
    job.run(&loaded.build(loaded.file.film()).expect("scene"));
}
