//! Which settings measure best: every set of strategy flags against the defaults, scene by scene.
//!
//! For each scene (every built-in scene, the files of `tests/scenes/`, and any file given), the
//! study's film (at most 192 x 128 pixels' worth) is rendered with every combination of light
//! selection, sphere sampling, quad sampling, lobe mixing, control variate, MIS model (multi,
//! or one-sample with c = 0.5) and method (the scene file's, and balance) that can change the
//! image of that scene (a strategy for lights or receivers the scene does not have changes no
//! bit, and is left at the defaults' value), `--spp` samples per pixel, `--seeds` seeds each. The
//! error is the study's: the relative MSE of the reflected light against a converged reference
//! (cached under `target/defaults/`); time is the fastest seed's wall-clock time on all cores (seeds
//! are rounds over every set, so the machine's slow moments fall on every set alike);
//! efficiency is 1 / (relative MSE x time). Each scene's table lists the defaults and every set
//! whose error or efficiency beats them, and the verdict: whether a set beats the defaults'
//! error by more than 5 % or their efficiency by more than 10 %.
//!
//! ```text
//! cargo run --release -p picomis-sim --example defaults -- [--spp 64] [--seeds 3] [--ref-spp 4096] [--scenes a,b] [FILE.json ...]
//! ```
//!
//! Run it on a quiet machine: times are wall-clock.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::Instant;

use indicatif::ProgressBar;
use picomis::{
    ControlVariate, Film, Heuristic, LightSelection, LobeMixing, Method, MisModel, Preset, QuadSampling,
    RenderSettings, Rgb, SphereSampling,
};
use picomis_format::{IntegratorDesc, SceneFile};
use picomis_host::HostScene;
use picomis_sim::render::render_estimates;
use picomis_sim::study::{metrics, study_film};

/// What a flag set measured.
#[derive(Clone, Debug)]
struct Measured {
    flags: String,
    rel_mse: f64,
    seconds: f64,
}

impl Measured {
    fn efficiency(&self) -> f64 {
        1.0 / (self.rel_mse * self.seconds).max(1e-300)
    }
}

fn arg<T: std::str::FromStr>(args: &[String], name: &str, default: T) -> T {
    args.iter()
        .position(|a| a == name)
        .and_then(|i| args.get(i + 1))
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let spp: u32 = arg(&args, "--spp", 64);
    let seeds: u32 = arg(&args, "--seeds", 3);
    let ref_spp: u32 = arg(&args, "--ref-spp", 4096);
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut files: Vec<(String, SceneFile)> = picomis_builtins::BUILTINS
        .iter()
        .map(|b| (b.name.to_string(), SceneFile::parse(b.json, b.name).expect("built-in scene")))
        .collect();
    let mut paths: Vec<PathBuf> = std::fs::read_dir(root.join("tests/scenes"))
        .map(|d| {
            d.filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| p.extension().is_some_and(|x| x == "json"))
                .collect()
        })
        .unwrap_or_default();
    paths.sort();
    let named = args
        .iter()
        .enumerate()
        .filter(|(i, a)| a.ends_with(".json") && !args[..*i].last().is_some_and(|p| p.starts_with("--")));
    paths.extend(named.map(|(_, a)| PathBuf::from(a)));
    for p in paths {
        match SceneFile::load(&p) {
            Ok(f) => files.push((f.name().to_string(), f)),
            Err(e) => eprintln!("skipped: {e}"),
        }
    }
    // `--scenes a,b`: only those scenes.
    if let Some(only) = args.iter().position(|a| a == "--scenes").and_then(|i| args.get(i + 1)) {
        let only: Vec<&str> = only.split(',').collect();
        files.retain(|(name, _)| only.contains(&name.as_str()));
    }
    let cache = root.join("target/defaults");
    std::fs::create_dir_all(&cache).expect("cache folder");
    println!("# Defaults against every flag set ({spp} spp, {seeds} seeds, reference {ref_spp} spp)\n");
    let mut verdicts = Vec::new();
    for (name, file) in &files {
        // A file whose scene the fixed-point queries cannot represent and the like: skip nothing;
        // every file here renders in f32.
        let film = study_film(file.film(), None).expect("study film");
        let scene: HostScene = file.build_with_film(film).expect("scene");
        let reference = reference(&cache, name, file, &scene, film, ref_spp);
        let mut results: BTreeMap<String, Measured> = BTreeMap::new();
        let mut sets = flag_sets(file);
        // `--only "FLAGS;FLAGS"`: only those sets (and the defaults).
        if let Some(only) = args.iter().position(|a| a == "--only").and_then(|i| args.get(i + 1)) {
            let only: Vec<&str> = only.split(';').map(str::trim).collect();
            sets.retain(|k| {
                let f = describe(k, file);
                f.is_empty() || only.contains(&f.as_str())
            });
        }
        eprintln!("{name}: {}x{}, {} flag sets", film.width(), film.height(), sets.len());
        // Seeds outermost, sets inside: every set is timed once per round, so a slow moment of
        // the machine falls on every set alike rather than on one.
        let runs: Vec<(String, RenderSettings)> = sets
            .iter()
            .filter_map(|keys| {
                Some((describe(keys, file), keys.over(file.integrator()).settings(spp, 0).ok()?))
            })
            .collect();
        let mut sums: Vec<Option<(f64, f64)>> = vec![Some((0.0, f64::INFINITY)); runs.len()];
        for s in 0..seeds {
            for ((_, base), sum) in runs.iter().zip(&mut sums) {
                let Some((rel, best_time)) = sum else { continue };
                let settings = base.with_seed(1 + s);
                let start = Instant::now();
                let Ok(img) = render_estimates(&scene, &settings, &ProgressBar::hidden()) else {
                    *sum = None;
                    continue;
                };
                *best_time = best_time.min(start.elapsed().as_secs_f64());
                let image: Vec<Rgb> =
                    img.pixels.iter().map(|e| e.light.contribution + e.bsdf.contribution).collect();
                *rel += metrics::error(&image, &reference).rel_mse / f64::from(seeds);
            }
        }
        for ((flags, _), sum) in runs.into_iter().zip(sums) {
            if let Some((rel_mse, seconds)) = sum {
                results.insert(flags.clone(), Measured { flags, rel_mse, seconds });
            }
        }
        let def_flags = describe(&IntegratorDesc::default(), file);
        let Some(def) = results.get(&def_flags).cloned() else {
            eprintln!("{name}: the defaults did not render");
            continue;
        };
        let mut rows: Vec<&Measured> = results.values().collect();
        rows.sort_by(|a, b| b.efficiency().total_cmp(&a.efficiency()));
        // Every set, for a closer look: target/defaults/<scene>.csv.
        let csv: String = std::iter::once("flags,rel_mse,seconds\n".to_string())
            .chain(rows.iter().map(|m| format!("{},{:e},{}\n", m.flags, m.rel_mse, m.seconds)))
            .collect();
        let _ = std::fs::write(cache.join(format!("{name}.csv")), csv);
        println!("## {name} ({}x{})\n", film.width(), film.height());
        println!("| flags | relative MSE | vs defaults | seconds | efficiency vs defaults |");
        println!("|---|---:|---:|---:|---:|");
        let lowest = rows.iter().map(|m| m.rel_mse).fold(f64::INFINITY, f64::min);
        for m in rows
            .iter()
            .filter(|m| m.flags == def_flags || m.rel_mse < def.rel_mse || m.efficiency() > def.efficiency())
            .take(12)
        {
            println!(
                "| {} | {:.3e} | {:.2}x | {:.3} | {:.2}x |",
                if m.flags.is_empty() { "(defaults)" } else { &m.flags },
                m.rel_mse,
                m.rel_mse / def.rel_mse,
                m.seconds,
                m.efficiency() / def.efficiency()
            );
        }
        let best_eff = rows.first().map_or(1.0, |m| m.efficiency() / def.efficiency());
        let error_ok = def.rel_mse <= 1.05 * lowest;
        let eff_ok = best_eff <= 1.10;
        println!(
            "\nDefaults: relative MSE {:.3e} ({:.3}x the lowest of {} sets), efficiency {:.2}x below the best. Within 5 % of the lowest error: {}; within 10 % of the best efficiency: {}.\n",
            def.rel_mse,
            def.rel_mse / lowest,
            rows.len(),
            best_eff,
            if error_ok { "yes" } else { "NO" },
            if eff_ok { "yes" } else { "NO" },
        );
        verdicts.push((name.clone(), error_ok, eff_ok));
    }
    println!(
        "## Verdict\n\n| scene | defaults within 5 % of the lowest error | within 10 % of the best efficiency |\n|---|---|---|"
    );
    for (name, e, f) in verdicts {
        println!("| {name} | {} | {} |", if e { "yes" } else { "no" }, if f { "yes" } else { "no" });
    }
}

/// Every option of `all` where it is `relevant`, else only `default`.
fn pick<T: Copy>(relevant: bool, all: &[T], default: T) -> Vec<T> {
    if relevant { all.to_vec() } else { vec![default] }
}

/// Every flag set that can change `file`'s image (see the module docs), as keys over the file's.
fn flag_sets(file: &SceneFile) -> Vec<IntegratorDesc> {
    let lights = file.light_kinds();
    let materials = file.material_kinds();
    let area = lights.spheres || lights.quads;
    let many = file.counts().lights > 1;
    let d = Preset::Best.settings();
    let selections = pick(many, &LightSelection::ALL, d.light_selection());
    let spheres = pick(lights.spheres, &SphereSampling::ALL, d.sphere_sampling());
    let quads = pick(lights.quads, &QuadSampling::ALL, d.quad_sampling());
    let lobes = pick(materials.ggx && area, &LobeMixing::ALL, d.lobe_mixing());
    let variates = pick(materials.lambertian && area, &ControlVariate::ALL, d.control_variate());
    let scene_method = file.default_settings().method();
    let methods = [scene_method, Method::Mis(Heuristic::Balance)];
    let models = [MisModel::Multi, MisModel::One { c_light: 0.5 }];
    let mut out = Vec::new();
    for &sel in &selections {
        for &sp in &spheres {
            for &q in &quads {
                for &lb in &lobes {
                    for &cv in &variates {
                        for (mi, &m) in methods.iter().enumerate() {
                            if mi > 0 && m == scene_method {
                                continue;
                            }
                            for &md in &models {
                                out.push(IntegratorDesc {
                                    light_selection: (sel != d.light_selection()).then_some(sel),
                                    sphere_sampling: (sp != d.sphere_sampling()).then_some(sp),
                                    quad_sampling: (q != d.quad_sampling()).then_some(q),
                                    lobe_mixing: (lb != d.lobe_mixing()).then_some(lb),
                                    control_variate: (cv != d.control_variate()).then_some(cv),
                                    mis: (m != scene_method).then_some(m),
                                    mis_model: (md != MisModel::Multi).then_some(md),
                                    ..IntegratorDesc::default()
                                });
                            }
                        }
                    }
                }
            }
        }
    }
    out
}

/// The flags of `keys` that differ from the defaults of `file`, as a command line would write them.
fn describe(keys: &IntegratorDesc, file: &SceneFile) -> String {
    let s = keys.over(file.integrator()).settings(1, 0).unwrap_or_else(|_| file.default_settings());
    let mut out: Vec<String> = IntegratorDesc::differences(&s, Preset::Best)
        .into_iter()
        .filter(|(k, v)| {
            let d = file.default_settings();
            let base: BTreeMap<_, _> = IntegratorDesc::differences(&d, Preset::Best).into_iter().collect();
            base.get(k) != Some(v)
        })
        .map(|(k, v)| format!("--{} {v}", k.replace('_', "-")))
        .collect();
    let (m, dm) = (s.method(), file.default_settings().method());
    if m != dm {
        out.insert(0, format!("--mis {m}"));
    }
    out.join(" ")
}

/// The converged reference of `file`'s scene (cached).
fn reference(
    cache: &Path,
    name: &str,
    file: &SceneFile,
    scene: &HostScene,
    film: Film,
    spp: u32,
) -> Vec<Rgb> {
    let path = cache.join(format!("{name}-{}x{}-{spp}.f32", film.width(), film.height()));
    if let Ok(bytes) = std::fs::read(&path) {
        if bytes.len() == film.pixels() as usize * 12 {
            let f: Vec<f32> =
                bytes.chunks_exact(4).map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]])).collect();
            return f.chunks_exact(3).map(|c| Rgb::new(c[0], c[1], c[2])).collect();
        }
    }
    eprintln!("{name}: reference at {spp} spp ...");
    // Any unbiased settings converge to the same image; these converge fastest on most scenes.
    let keys = IntegratorDesc {
        light_selection: Some(LightSelection::Contribution),
        lobe_mixing: Some(LobeMixing::On),
        quad_sampling: Some(QuadSampling::SolidAngle),
        sphere_sampling: Some(SphereSampling::Cone),
        ..IntegratorDesc::default()
    };
    let settings = keys.over(file.integrator()).settings(spp, 0x0dea_f001).expect("reference settings");
    let img = render_estimates(scene, &settings, &ProgressBar::hidden()).expect("reference render");
    let rgb: Vec<Rgb> = img.pixels.iter().map(|e| e.light.contribution + e.bsdf.contribution).collect();
    let bytes: Vec<u8> = rgb.iter().flat_map(|c| [c.x, c.y, c.z]).flat_map(f32::to_le_bytes).collect();
    let _ = std::fs::write(&path, bytes);
    rgb
}
