//! `picomis-sim study`: speed against accuracy (efficiency = 1 / (error x time)).
//!
//! For each scene and each method (BSDF sampling alone; light sampling alone with sphere lights
//! sampled by area and by cone; the average, balance, power, maximum and cutoff heuristics; all
//! with the default sample stream and uniform light selection, and the power heuristic again
//! with independent numbers and with lights chosen by power and by contribution), the study renders a ladder of samples per pixel (1, 2, 4, ... up to `--max-spp`) with several
//! seeds, times each render on all cores, and measures its error against a converged reference
//! (balance heuristic, cone sampling, many samples; cached as EXR under `DIR/cache`). It writes
//! `results.csv`, log-log charts of error against time and against spp, an equal-time image grid
//! per scene, efficiency tables with the convergence slope of each method (`summary.md`: the
//! least-squares slope of log relative MSE against log spp; -1 is plain Monte Carlo, steeper is
//! what stratification gains) and, for the Veach scene, the error per
//! plate x light region (`veach_regions.md` and heat maps).
//!
//! Time is wall-clock time on all cores; where a method's time enters a ratio (efficiency,
//! equal time, the time axis of the charts) the fastest of its seeds' renders is used, which is
//! robust against other processes on the machine. The error is measured on the reflected (direct)
//! light, the part the techniques estimate: the radiance of lights seen directly comes from the
//! camera ray alone, is the same for every method (the same seed gives the same camera rays), and
//! its pixel-edge noise would otherwise add the same floor to every method. `--include-emitted`
//! measures the full radiance instead.
//!
//! The methods are the host's list ([`picomis_host::study::study_methods`]), then "defaults": the
//! scene's own integrator, as `picomis-sim render` would render it (the best preset, the scene
//! file's integrator block, and the integrator flags of the command line over both;
//! [`methods`]). The modules, none of which reads this one (each reads only modules further down
//! the list):
//! - `report` (charts with `chart`, the equal-time grid with `grid`, CSV, summary) and
//!   `region_report` (the region table and heat maps; it reads `report`'s writers) write the
//!   outputs;
//! - `job` runs the steps of one scene over one context;
//! - `results` holds what they measure;
//! - `regions` finds the plate x light regions and renders each light alone;
//! - `reference` makes (or reads from the cache) the converged references;
//! - `methods` lists the methods;
//! - `measure` does one render (through [`crate::render`]), `metrics` the errors, `args` the
//!   command line.

mod args;
mod chart;
mod grid;
mod job;
mod measure;
pub mod methods;
pub mod metrics;
pub mod reference;
mod region_report;
mod regions;
mod report;
mod results;

use std::time::Instant;

use crate::SimError;
use crate::scenes::{self, BUILTINS, Loaded};

pub use args::{StudyArgs, ladder, study_film};
pub use measure::timed;
pub use methods::{DEFAULTS, defaults_index, methods};
pub use picomis_host::study::{Extras, StudyMethod, study_methods};
pub use report::load_average;
pub use results::{EqualTime, Record, SceneStudy, balance_index, cost_per_spp, index_of};

/// Runs the study.
pub fn run(args: &StudyArgs) -> Result<(), SimError> {
    let started = Instant::now();
    args.check()?;
    let loaded: Vec<Loaded> = match &args.scene {
        Some(s) => vec![scenes::load(Some(s))?],
        None => BUILTINS.iter().map(|b| scenes::load(Some(b.name))).collect::<Result<_, _>>()?,
    };
    let cache = args.out.join("cache");
    std::fs::create_dir_all(&cache).map_err(|e| SimError::Io(format!("{}: {e}", cache.display())))?;
    chart::register_font_once()?;
    let ref_spp = args.reference_spp();
    eprintln!(
        "study: {} scene(s), {} methods, spp {:?}, {} seed(s), reference {} spp, {} threads -> {}",
        loaded.len(),
        methods().len(),
        args.ladder(),
        args.seeds,
        ref_spp,
        rayon::current_num_threads(),
        args.out.display()
    );

    let mut studies = Vec::new();
    for l in &loaded {
        let film = args.film(l.file.film())?;
        let scene = l.build(film)?;
        let study = job::SceneJob { loaded: l, args, cache: &cache }.run(&scene)?;
        report::write_scene(&args.out, &study, args.include_emitted)?;
        region_report::write_regions(&args.out, &study)?;
        studies.push(study);
    }
    report::write_results(&args.out, &studies)?;
    report::write_summary(&args.out, &studies, args, ref_spp, started.elapsed().as_secs_f64())?;
    eprintln!("study: done in {:.1} s -> {}", started.elapsed().as_secs_f64(), args.out.display());
    Ok(())
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::*;

    fn args(out: &Path) -> StudyArgs {
        StudyArgs {
            scene: Some("lambert_sphere".into()),
            out: out.to_path_buf(),
            max_spp: 2,
            seeds: 2,
            scale: Some(0.25),
            ref_spp: Some(8),
            mitsuba_ref: None,
            include_emitted: false,
            integrator: picomis_format::IntegratorDesc::default(),
        }
    }

    #[test]
    fn a_small_study_writes_every_output_and_reuses_its_reference() {
        let dir = tempfile::tempdir().unwrap();
        run(&args(dir.path())).unwrap();
        for f in [
            "results.csv",
            "equal_time.csv",
            "summary.md",
            "lambert_sphere_error_time.png",
            "lambert_sphere_error_time.svg",
            "lambert_sphere_error_spp.png",
            "lambert_sphere_error_spp.svg",
            "lambert_sphere_equal_time.png",
        ] {
            assert!(dir.path().join(f).is_file(), "{f} missing");
        }
        let csv = std::fs::read_to_string(dir.path().join("results.csv")).unwrap();
        // Header, then every method x 2 rungs x 2 seeds.
        assert_eq!(csv.lines().count(), 1 + methods().len() * 2 * 2);
        assert!(csv.lines().nth(1).unwrap().starts_with("lambert_sphere,bsdf,1,1,16,12,"));
        // The scene's own integrator is one of the methods.
        assert_eq!(csv.lines().filter(|l| l.starts_with("lambert_sphere,defaults,")).count(), 2 * 2);
        let cache: Vec<_> = std::fs::read_dir(dir.path().join("cache")).unwrap().collect();
        assert_eq!(cache.len(), 3, "reflected, full and info");
        // A second run takes the cached reference (8 spp) instead of rendering another.
        run(&args(dir.path())).unwrap();
        assert_eq!(std::fs::read_dir(dir.path().join("cache")).unwrap().count(), 3);
        let summary = std::fs::read_to_string(dir.path().join("summary.md")).unwrap();
        assert!(summary.contains("reference 8 spp") && summary.contains(", cached"), "{summary}");
        // The fixed-point method: measured against f32 power of the same seed and spp (a finite,
        // non-negative error), and only it.
        let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
        let col = header.iter().position(|h| *h == "rel_mse_vs_f32").unwrap();
        for line in csv.lines().skip(1) {
            let f: Vec<&str> = line.split(',').collect();
            assert_eq!(f.len(), header.len(), "{line}");
            if f[1] == "power_fixed" {
                let v: f64 = f[col].parse().unwrap();
                assert!(v.is_finite() && v >= 0.0, "{line}");
            } else {
                assert_eq!(f[col], "", "{line}");
            }
        }
        let row = summary.lines().find(|l| l.starts_with("| power, fixed-point ray queries |")).unwrap();
        let last = row.trim_end_matches('|').rsplit('|').next().unwrap().trim();
        assert!(last.parse::<f64>().is_ok_and(|v| v.is_finite()), "{row}");
    }

    #[test]
    fn a_scene_fixed_point_cannot_represent_shows_the_method_as_rejected() {
        let dir = tempfile::tempdir().unwrap();
        let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/../tests/scenes/tiny_light.json");
        let a = StudyArgs { scene: Some(scene.into()), max_spp: 1, seeds: 1, ..args(dir.path()) };
        run(&a).unwrap();
        let summary = std::fs::read_to_string(dir.path().join("summary.md")).unwrap();
        let row = summary.lines().find(|l| l.starts_with("| power, fixed-point ray queries |")).unwrap();
        assert!(
            row.contains("| rejected: fixed point cannot represent shape 1: ")
                && row.contains("(shapes[1] \"tiny_light\")"),
            "{row}"
        );
        // Every other method ran; the rejected one has one CSV row with its reason and no render.
        let csv = std::fs::read_to_string(dir.path().join("results.csv")).unwrap();
        assert_eq!(csv.lines().count(), 1 + (methods().len() - 1) + 1);
        let rejected: Vec<&str> = csv.lines().filter(|l| l.starts_with("tiny_light,power_fixed,")).collect();
        assert_eq!(rejected.len(), 1, "{csv}");
        assert!(rejected[0].starts_with("tiny_light,power_fixed,,,") && rejected[0].contains("too small"));
        assert!(dir.path().join("tiny_light_equal_time.png").is_file());
    }

    #[test]
    fn bad_scales_are_usage_errors() {
        let dir = tempfile::tempdir().unwrap();
        let mut a = args(dir.path());
        a.scale = Some(0.0);
        assert!(matches!(run(&a), Err(SimError::Usage(_))));
    }
}
