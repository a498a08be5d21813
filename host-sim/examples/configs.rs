//! Relative MSE at equal spp, cost and efficiency of every sample stream x light selection on
//! every built-in scene: a quick stand-in for `picomis-sim study` when only these two choices
//! vary. Each scene renders at the study's film (at most 192 x 128 pixels) with its own method
//! and sample counts, against the study's converged reference (balance heuristic, cached under
//! `target/configs/cache`, shared with nothing else). The error is that of the reflected
//! light, as in the study; configurations are interleaved (spp, then seed, then configuration)
//! so that changes of machine load hit all alike, and a configuration's time is its fastest
//! seed's render. Prints one table per scene and spp.
//!
//! `cargo run --release -p picomis-sim --example configs`; environment: `CONFIGS_SPP` (default
//! "4,16,64"), `CONFIGS_SEEDS` (4), `CONFIGS_REF_SPP` (4096), `CONFIGS_SCENES` (every built-in
//! scene, comma-separated names).

use std::path::PathBuf;

use picomis::{Estimate, LightSelection, RenderSettings, Rgb, SamplerKind};
use picomis_sim::render::progress_bar;
use picomis_sim::scenes::{self, BUILTINS, HostScene, Loaded};
use picomis_sim::study::{load_average, metrics, reference, study_film, timed};

/// One configuration: a sample stream and a light selection.
#[derive(Clone, Copy, Debug)]
struct Config {
    sampler: SamplerKind,
    selection: LightSelection,
}

impl Config {
    fn label(&self) -> String {
        format!("{} / {}", self.sampler.name(), self.selection.name())
    }
}

fn configs() -> Vec<Config> {
    SamplerKind::ALL
        .into_iter()
        .flat_map(|sampler| LightSelection::ALL.map(|selection| Config { sampler, selection }))
        .collect()
}

fn env_list(name: &str, default: &str) -> Vec<String> {
    std::env::var(name)
        .unwrap_or_else(|_| default.to_string())
        .split(',')
        .map(|s| s.trim().to_string())
        .filter(|s| !s.is_empty())
        .collect()
}

fn env_u32(name: &str, default: u32) -> u32 {
    std::env::var(name).ok().and_then(|v| v.parse().ok()).unwrap_or(default)
}

struct Job<'a> {
    loaded: &'a Loaded,
    spps: &'a [u32],
    seeds: u32,
    ref_spp: u32,
    cache: PathBuf,
}

impl Job<'_> {
    fn run(self, scene: &HostScene) {
        let name = self.loaded.file.name();
        let samples = self.loaded.file.default_settings().sample_counts();
        let method = self.loaded.file.default_settings().method();
        let reference = reference::get(scene, self.loaded, &self.cache, self.ref_spp, samples, "")
            .unwrap_or_else(|e| panic!("{name}: reference: {e}"));
        let film = scene.film();
        println!(
            "\n## {name}: {}x{}, {method}, {} light + {} BSDF samples; reference {} spp (own rel. MSE {:.1e})",
            film.width(),
            film.height(),
            samples.0,
            samples.1,
            reference.spp,
            reference.noise.rel_mse
        );
        let configs = configs();
        for &spp in self.spps {
            // (sum of rel. MSE over seeds, fastest seconds) per configuration.
            let mut results = vec![(0.0f64, f64::INFINITY); configs.len()];
            let bar = progress_bar(
                u64::from(spp) * u64::from(self.seeds) * configs.len() as u64 * u64::from(film.height()),
                &format!("{name}: {spp} spp"),
            );
            for seed in 0..self.seeds {
                for (c, r) in configs.iter().zip(results.iter_mut()) {
                    let settings = RenderSettings::new(method, samples.0, samples.1, spp, 1 + seed)
                        .expect("the scene's settings")
                        .with_sampler(c.sampler)
                        .with_light_selection(c.selection);
                    let (img, seconds) =
                        timed(scene, &settings, &bar).unwrap_or_else(|e| panic!("{name}: {e}"));
                    let reflected: Vec<Rgb> =
                        img.iter().map(|e: &Estimate| e.light.contribution + e.bsdf.contribution).collect();
                    r.0 += metrics::error(&reflected, &reference.reflected).rel_mse;
                    r.1 = r.1.min(seconds);
                }
            }
            bar.finish_and_clear();
            let base = results[0];
            let base_err = base.0 / f64::from(self.seeds);
            println!(
                "\n{name} at {spp} spp ({} seeds); ratios against {}:\n",
                self.seeds,
                configs[0].label()
            );
            println!("| sampler / light selection | rel. MSE | ms | rel. MSE ratio | efficiency ratio |");
            println!("|---|---:|---:|---:|---:|");
            for (c, r) in configs.iter().zip(&results) {
                let err = r.0 / f64::from(self.seeds);
                println!(
                    "| {} | {err:.3e} | {:.1} | {:.2} | {:.2} |",
                    c.label(),
                    r.1 * 1e3,
                    err / base_err,
                    (base_err * base.1) / (err * r.1)
                );
            }
        }
    }
}

fn main() {
    let spps: Vec<u32> = env_list("CONFIGS_SPP", "4,16,64").iter().filter_map(|s| s.parse().ok()).collect();
    let seeds = env_u32("CONFIGS_SEEDS", 4).max(1);
    let ref_spp = env_u32("CONFIGS_REF_SPP", 4096).max(2);
    let all: Vec<String> = BUILTINS.iter().map(|b| b.name.to_string()).collect();
    let names = env_list("CONFIGS_SCENES", &all.join(","));
    let cache = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../target/configs/cache");
    std::fs::create_dir_all(&cache).expect("cache folder");
    println!("# Sample streams x light selections (machine load: {})", load_average());
    for name in &names {
        let loaded = scenes::load(Some(name)).unwrap_or_else(|e| panic!("{name}: {e}"));
        let film = study_film(loaded.file.film(), None).expect("study film");
        let job = Job { loaded: &loaded, spps: &spps, seeds, ref_spp, cache: cache.clone() };
        job.run(&loaded.build(film).unwrap_or_else(|e| panic!("{name}: {e}")));
    }
}
