//! `picomis-sim study`: speed against accuracy (MIS-NOTES section 6).
//!
//! For each scene and each method (BSDF sampling alone; light sampling alone with sphere lights
//! sampled by area and by cone; the average, balance, power, maximum and cutoff heuristics; all
//! with the default sample stream, and the power heuristic again with independent numbers), the
//! study renders a ladder of samples per pixel (1, 2, 4, ... up to `--max-spp`) with several
//! seeds, times each render on all cores, and measures its error against a converged reference
//! (balance heuristic, cone sampling, many samples; cached as EXR under `DIR/cache`). It writes
//! `results.csv`, log-log charts of error against time and against spp, an equal-time image grid
//! per scene, efficiency tables (`summary.md`) and, for the Veach scene, the error per
//! plate x light region (`veach_regions.md` and heat maps).
//!
//! Time is wall-clock time on all cores; where a method's time enters a ratio (efficiency,
//! equal time, the time axis of the charts) the fastest of its seeds' renders is used, which is
//! robust against other processes on the machine. The error is measured on the reflected (direct) light, the part the techniques estimate: the
//! radiance of lights seen directly comes from the camera ray alone, is the same for every method
//! (the same seed gives the same camera rays), and its pixel-edge noise would otherwise add the
//! same floor to every method. `--include-emitted` measures the full radiance instead.

mod chart;
mod grid;
mod metrics;
mod reference;
mod regions;
mod report;

use std::path::{Path, PathBuf};
use std::time::Instant;

use indicatif::ProgressBar;
use picomis::{
    ControlVariate, Estimate, Film, Heuristic, LightSelection, Method, MisModel, QuadSampling,
    RenderSettings, Rgb, SamplerKind, Scene, SphereSampling, render_pixel,
};
use rayon::prelude::*;

use crate::SimError;
use crate::render::progress_bar;
use crate::scenes::{self, BUILTINS, Loaded, SceneVisitor};

use metrics::ErrorStats;
use reference::Reference;
use regions::{RegionMap, RegionStudy};

/// `picomis-sim study`.
#[derive(Debug, Clone, clap::Args)]
pub struct StudyArgs {
    /// A picomis-scene/1 JSON file or the name of a built-in scene (default: every built-in scene).
    pub scene: Option<String>,
    /// Output folder (created if missing); the reference cache goes to DIR/cache.
    #[arg(long, value_name = "DIR", default_value = "study-out")]
    pub out: PathBuf,
    /// Largest samples per pixel of the ladder 1, 2, 4, ... (a last rung at N if N is not a power of two).
    #[arg(long, value_name = "N", default_value_t = 64, value_parser = clap::value_parser!(u32).range(1..=1_000_000))]
    pub max_spp: u32,
    /// Seeds per rung (the spread across seeds is drawn as a band).
    #[arg(long, value_name = "K", default_value_t = 3, value_parser = clap::value_parser!(u32).range(1..=1000))]
    pub seeds: u32,
    /// Film scale (default: each scene's film scaled down to at most 192 x 128 pixels' worth).
    #[arg(long, value_name = "F")]
    pub scale: Option<f32>,
    /// Samples per pixel of the reference (default: the larger of 1024 and 32 x --max-spp).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(2..=10_000_000))]
    pub ref_spp: Option<u32>,
    /// Mitsuba 3 reference of the Veach scene (default: the copy in the repository, if any).
    #[arg(long, value_name = "FILE.exr")]
    pub mitsuba_ref: Option<PathBuf>,
    /// Measure the error of the full radiance (lights seen directly included).
    #[arg(long)]
    pub include_emitted: bool,
}

/// Pixels of the default study film: 192 x 128 (the Veach film at half size).
const STUDY_PIXELS: f64 = 192.0 * 128.0;

/// A method of the study.
#[derive(Clone, Copy, Debug)]
pub struct StudyMethod {
    /// Short name (CSV, file names).
    pub label: &'static str,
    /// Name in charts and tables.
    pub title: &'static str,
    /// The combination.
    pub method: Method,
    /// How sphere lights are sampled.
    pub spheres: SphereSampling,
    /// Everything else: sample stream, light selection, and what goes beyond the lecture.
    pub extras: Extras,
}

/// What a study method sets besides its combination and sphere sampling.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Extras {
    /// The sample stream.
    pub sampler: SamplerKind,
    /// How a light is chosen among several.
    pub selection: LightSelection,
    /// The MIS model.
    pub model: MisModel,
    /// How quad lights are sampled.
    pub quads: QuadSampling,
    /// The analytic control variate.
    pub control_variate: ControlVariate,
}

impl Default for Extras {
    /// The default sample stream, uniform light selection (the Veach region study needs it),
    /// and the lecture's estimator.
    fn default() -> Self {
        Extras {
            sampler: SamplerKind::default(),
            selection: LightSelection::Uniform,
            model: MisModel::default(),
            quads: QuadSampling::default(),
            control_variate: ControlVariate::default(),
        }
    }
}

impl Extras {
    /// `settings` with these options.
    pub fn apply(&self, settings: RenderSettings) -> Result<RenderSettings, picomis::SceneError> {
        Ok(settings
            .with_sampler(self.sampler)
            .with_light_selection(self.selection)
            .with_mis_model(self.model)?
            .with_quad_sampling(self.quads)
            .with_control_variate(self.control_variate))
    }
}

/// The methods of the study, in the seed's order, with the default sample stream (sobol) and
/// uniform light selection; then the power heuristic with independent random numbers (what the
/// stratified stream gains). The heuristics sample sphere lights by cone. (Every method keeps
/// uniform selection: the Veach region study renders each light alone, which leaves the
/// selection probabilities unchanged only under uniform selection.)
pub fn study_methods() -> Vec<StudyMethod> {
    let m = |name: &str| Method::from_name(name).expect("the kernel's method names");
    let (cone, area) = (SphereSampling::Cone, SphereSampling::Area);
    let study = |label, title, method, spheres| StudyMethod {
        label,
        title,
        method,
        spheres,
        extras: Extras::default(),
    };
    vec![
        study("bsdf", "BSDF sampling", m("bsdf"), cone),
        study("light_area", "light sampling (area)", m("light"), area),
        study("light_cone", "light sampling (cone)", m("light"), cone),
        study("average", "average", m("average"), cone),
        study("balance", "balance", m("balance"), cone),
        study("power", "power (\u{3b2} = 2)", m("power"), cone),
        study("maximum", "maximum", m("maximum"), cone),
        study("cutoff", "cutoff (\u{3b1} = 0.1)", m("cutoff"), cone),
        // The sample stream: what the stratified default gains over independent numbers.
        StudyMethod {
            extras: Extras { sampler: SamplerKind::Independent, ..Extras::default() },
            ..study("power_independent", "power, independent numbers", m("power"), cone)
        },
        // Beyond the lecture, each against balance.
        StudyMethod {
            extras: Extras { model: MisModel::One { c_light: 0.5 }, ..Extras::default() },
            ..study("one_balance", "one-sample balance (c = 0.5)", m("balance"), cone)
        },
        StudyMethod {
            extras: Extras { quads: QuadSampling::SolidAngle, ..Extras::default() },
            ..study("balance_sa", "balance, quads by solid angle", m("balance"), cone)
        },
        StudyMethod {
            extras: Extras { quads: QuadSampling::SolidAngleCosine, ..Extras::default() },
            ..study("balance_sac", "balance, quads by solid angle x cosine", m("balance"), cone)
        },
        StudyMethod {
            extras: Extras { control_variate: ControlVariate::On, ..Extras::default() },
            ..study("balance_cv", "balance + control variate", m("balance"), cone)
        },
    ]
}

/// Index in [`study_methods`] of `method` with sphere lights sampled by `spheres`, the default
/// sample stream and uniform light selection (0 if absent).
pub fn index_of(method: Method, spheres: SphereSampling) -> usize {
    study_methods()
        .iter()
        .position(|m| m.method == method && m.spheres == spheres && m.extras == Extras::default())
        .unwrap_or(0)
}

/// Index of the balance heuristic in [`study_methods`] (the baseline of every ratio).
pub fn balance_index() -> usize {
    index_of(Method::Mis(Heuristic::Balance), SphereSampling::Cone)
}

/// Seeds of the ladder renders are `LADDER_SEED + k`; the reference and the equal-time renders
/// use other seeds, so no render shares random numbers with the reference.
const LADDER_SEED: u32 = 1;
const EQUAL_TIME_SEED: u32 = 0x00e9_0000;

/// One timed render of the ladder.
#[derive(Clone, Debug)]
pub struct Record {
    /// Index in [`study_methods`].
    pub method: usize,
    /// Samples per pixel.
    pub spp: u32,
    /// Seed.
    pub seed: u32,
    /// Wall-clock seconds on all cores.
    pub seconds: f64,
    /// Error against the study's reference.
    pub error: ErrorStats,
    /// Error of the full radiance against the Mitsuba 3 reference (Veach scene).
    pub mitsuba: Option<ErrorStats>,
}

/// One render of the equal-time comparison.
#[derive(Clone, Debug)]
pub struct EqualTime {
    /// Index in [`study_methods`].
    pub method: usize,
    /// Samples per pixel chosen from the method's measured cost.
    pub spp: u32,
    /// Wall-clock seconds.
    pub seconds: f64,
    /// Error against the study's reference.
    pub error: ErrorStats,
    /// The image (full radiance).
    pub image: Vec<Rgb>,
}

/// Everything measured on one scene.
#[derive(Clone, Debug)]
pub struct SceneStudy {
    /// Scene name.
    pub name: String,
    /// Study film.
    pub width: u32,
    /// Study film.
    pub height: u32,
    /// Ladder renders.
    pub records: Vec<Record>,
    /// Equal-time renders.
    pub equal_time: Vec<EqualTime>,
    /// The time budget of the equal-time renders.
    pub budget: f64,
    /// The reference.
    pub reference: Reference,
    /// Plate x light regions, when the scene has them (the Veach scene).
    pub regions: Option<RegionMap>,
    /// Errors per region, each light rendered alone at the top rung.
    pub region_study: RegionStudy,
    /// Why there is no Mitsuba comparison (Veach scene only), if there is none.
    pub mitsuba_note: Option<String>,
    /// Error of the reference's full radiance against the Mitsuba 3 reference (Veach scene).
    pub reference_vs_mitsuba: Option<ErrorStats>,
}

/// Runs the study.
pub fn run(args: &StudyArgs) -> Result<(), SimError> {
    let started = Instant::now();
    if let Some(s) = args.scale {
        if !(s.is_finite() && s > 0.0 && s <= 4.0) {
            return Err(SimError::Usage(format!("--scale {s}: expected a number in (0, 4]")));
        }
    }
    let loaded: Vec<Loaded> = match &args.scene {
        Some(s) => vec![scenes::load(Some(s))?],
        None => BUILTINS.iter().map(|b| scenes::load(Some(b.name))).collect::<Result<_, _>>()?,
    };
    let cache = args.out.join("cache");
    std::fs::create_dir_all(&cache).map_err(|e| SimError::Io(format!("{}: {e}", cache.display())))?;
    chart::register_font_once()?;
    let ladder = ladder(args.max_spp);
    let ref_spp = args.ref_spp.unwrap_or_else(|| (32 * args.max_spp).max(1024));
    eprintln!(
        "study: {} scene(s), {} methods, spp {:?}, {} seed(s), reference {} spp, {} threads -> {}",
        loaded.len(),
        study_methods().len(),
        ladder,
        args.seeds,
        ref_spp,
        rayon::current_num_threads(),
        args.out.display()
    );

    let mut studies = Vec::new();
    for l in &loaded {
        let film = study_film(l.file.film(), args.scale)?;
        let job = SceneJob { loaded: l, args, ladder: &ladder, ref_spp, cache: &cache };
        let study = l.visit(film, job)??;
        report::write_scene(&args.out, &study, args.include_emitted)?;
        studies.push(study);
    }
    report::write_results(&args.out, &studies)?;
    report::write_summary(&args.out, &studies, args, ref_spp, started.elapsed().as_secs_f64())?;
    eprintln!("study: done in {:.1} s -> {}", started.elapsed().as_secs_f64(), args.out.display());
    Ok(())
}

/// 1, 2, 4, ... up to `max` (and `max` itself).
pub fn ladder(max: u32) -> Vec<u32> {
    let mut v: Vec<u32> =
        std::iter::successors(Some(1u32), |&s| s.checked_mul(2)).take_while(|&s| s <= max).collect();
    if v.last() != Some(&max) {
        v.push(max);
    }
    v
}

/// The study film: `scale` times the scene's film, or by default the film scaled down to at most
/// [`STUDY_PIXELS`] pixels.
pub fn study_film(film: Film, scale: Option<f32>) -> Result<Film, SimError> {
    let (w, h) = (f64::from(film.width()), f64::from(film.height()));
    let s = match scale {
        Some(s) => f64::from(s),
        None => (STUDY_PIXELS / (w * h)).sqrt().min(1.0),
    };
    let (sw, sh) = (((w * s).round() as u32).max(1), ((h * s).round() as u32).max(1));
    Film::new(sw, sh).map_err(|e| SimError::Usage(format!("--scale: film {sw}x{sh}: {e}")))
}

/// Renders every pixel of `scene` on all cores, advancing `bar` by `spp` per row; returns the
/// estimates and the wall-clock seconds.
pub fn render<const S: usize, const L: usize, const M: usize>(
    scene: &Scene<S, L, M>,
    settings: &RenderSettings,
    bar: &ProgressBar,
) -> (Vec<Estimate>, f64) {
    let film = scene.film();
    let width = film.width() as usize;
    let mut pixels = vec![Estimate::default(); film.pixels() as usize];
    let start = Instant::now();
    pixels.par_chunks_mut(width).enumerate().for_each(|(y, row)| {
        for (x, px) in row.iter_mut().enumerate() {
            *px = render_pixel(scene, settings, x as u32, y as u32);
        }
        bar.inc(u64::from(settings.spp()));
    });
    (pixels, start.elapsed().as_secs_f64())
}

/// The radiance that errors are measured on.
fn measured(e: &Estimate, include_emitted: bool) -> Rgb {
    if include_emitted { e.radiance() } else { e.light.contribution + e.bsdf.contribution }
}

/// The render settings of method `m` with `n` = (light, BSDF) samples per camera sample.
pub fn settings(m: &StudyMethod, n: (u16, u16), spp: u32, seed: u32) -> Result<RenderSettings, SimError> {
    RenderSettings::new(m.method, n.0.max(1), n.1.max(1), spp, seed)
        .and_then(|s| m.extras.apply(s.with_sphere_sampling(m.spheres)))
        .map_err(|e| SimError::Usage(format!("{}: {e}", m.label)))
}

/// The study of one scene, run with its kernel scene (capacities chosen by the dispatch).
struct SceneJob<'a> {
    loaded: &'a Loaded,
    args: &'a StudyArgs,
    ladder: &'a [u32],
    ref_spp: u32,
    cache: &'a Path,
}

impl SceneVisitor for SceneJob<'_> {
    type Output = Result<SceneStudy, SimError>;

    fn visit<const S: usize, const L: usize, const M: usize>(self, scene: Scene<S, L, M>) -> Self::Output {
        let name = self.loaded.file.name().to_string();
        let film = scene.film();
        let (w, h) = (film.width(), film.height());
        let samples = self.loaded.file.default_samples();
        let include_emitted = self.args.include_emitted;

        let reference = reference::get(&scene, self.loaded, self.cache, self.ref_spp, samples, "")?;
        let target: &[Rgb] = if include_emitted { &reference.full } else { &reference.reflected };
        eprintln!(
            "{name}: {w}x{h}, reference {} spp ({}), its own noise: rel. MSE {:.2e}",
            reference.spp,
            if reference.cached {
                "cached".to_string()
            } else {
                format!("rendered in {:.1} s", reference.seconds)
            },
            reference.noise.rel_mse
        );
        let (mitsuba, mitsuba_note) = if name == "veach_mis" {
            match reference::mitsuba(self.args.mitsuba_ref.as_deref(), w, h) {
                Ok(img) => (Some(img), None),
                Err(note) => {
                    eprintln!("{name}: no Mitsuba comparison: {note}");
                    (None, Some(note))
                }
            }
        } else {
            (None, None)
        };
        let regions = RegionMap::find(&scene);
        if let Some(r) = &regions {
            eprintln!("{name}: {} plate x light regions", r.regions.len());
        }

        // The ladder, methods interleaved so that any change of machine load hits all alike.
        let methods = study_methods();
        let seeds: Vec<u32> = (0..self.args.seeds).map(|k| LADDER_SEED + k).collect();
        let per_method: u64 = self.ladder.iter().map(|&s| u64::from(s)).sum::<u64>() * seeds.len() as u64;
        let bar = progress_bar(per_method * methods.len() as u64 * u64::from(h), &format!("{name}: ladder"));
        let mut records = Vec::new();
        for &spp in self.ladder {
            for &seed in &seeds {
                for (mi, m) in methods.iter().enumerate() {
                    let s = settings(m, samples, spp, seed)?;
                    let (img, seconds) = render(&scene, &s, &bar);
                    let values: Vec<Rgb> = img.iter().map(|e| measured(e, include_emitted)).collect();
                    let error = metrics::error(&values, target);
                    let mitsuba = mitsuba.as_ref().map(|r| {
                        let full: Vec<Rgb> = img.iter().map(Estimate::radiance).collect();
                        metrics::error(&full, r)
                    });
                    records.push(Record { method: mi, spp, seed, seconds, error, mitsuba });
                }
            }
        }
        bar.finish_and_clear();

        // Each light alone, for the error per plate x light region.
        let top = *self.ladder.last().unwrap_or(&1);
        let region_study = match &regions {
            Some(map) => {
                let ref_spp = (self.ref_spp / 4).max(256);
                let (scene, loaded, cache) = (&scene, self.loaded, self.cache);
                regions::study(scene, map, loaded, cache, ref_spp, samples, &methods, top, &seeds)?
            }
            None => RegionStudy::default(),
        };

        // Equal time: every method gets the time balance took at the top rung.
        let budget = f64::from(top) * cost_per_spp(&records, balance_index(), top);
        let spps: Vec<u32> = (0..methods.len())
            .map(|mi| {
                let cost = cost_per_spp(&records, mi, top);
                ((budget / cost).round() as u32).clamp(1, 1 << 20)
            })
            .collect();
        let total: u64 = spps.iter().map(|&s| u64::from(s)).sum();
        let bar = progress_bar(total * u64::from(h), &format!("{name}: equal time"));
        let mut equal_time = Vec::new();
        for (mi, m) in methods.iter().enumerate() {
            let s = settings(m, samples, spps[mi], EQUAL_TIME_SEED)?;
            let (img, seconds) = render(&scene, &s, &bar);
            let values: Vec<Rgb> = img.iter().map(|e| measured(e, include_emitted)).collect();
            let error = metrics::error(&values, target);
            let image = img.iter().map(Estimate::radiance).collect();
            equal_time.push(EqualTime { method: mi, spp: spps[mi], seconds, error, image });
        }
        bar.finish_and_clear();
        let reference_vs_mitsuba = mitsuba.as_ref().map(|m| metrics::error(&reference.full, m));
        Ok(SceneStudy {
            name,
            width: w,
            height: h,
            records,
            equal_time,
            budget,
            reference,
            regions,
            region_study,
            mitsuba_note,
            reference_vs_mitsuba,
        })
    }
}

/// Seconds per sample per pixel of method `mi`: the fastest render of its two top rungs, per spp.
/// Taking the fastest of several seeds' renders (methods interleaved) keeps other processes on
/// the machine from inflating one method's cost more than another's.
pub fn cost_per_spp(records: &[Record], mi: usize, top: u32) -> f64 {
    records
        .iter()
        .filter(|r| r.method == mi && 2 * r.spp >= top)
        .map(|r| r.seconds / f64::from(r.spp))
        .fold(f64::INFINITY, f64::min)
}

/// Mean of the values (NaN for none).
pub fn mean(values: impl Iterator<Item = f64>) -> f64 {
    let (mut sum, mut n) = (0.0, 0usize);
    for v in values {
        sum += v;
        n += 1;
    }
    sum / n as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ladders_and_films() {
        assert_eq!(ladder(1), vec![1]);
        assert_eq!(ladder(8), vec![1, 2, 4, 8]);
        assert_eq!(ladder(12), vec![1, 2, 4, 8, 12]);
        let f = study_film(Film::new(384, 256).unwrap(), None).unwrap();
        assert_eq!((f.width(), f.height()), (192, 128));
        let f = study_film(Film::new(64, 48).unwrap(), None).unwrap();
        assert_eq!((f.width(), f.height()), (64, 48));
        let f = study_film(Film::new(64, 48).unwrap(), Some(0.5)).unwrap();
        assert_eq!((f.width(), f.height()), (32, 24));
        assert_eq!(study_methods()[balance_index()].label, "balance");
    }

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
        assert_eq!(csv.lines().count(), 1 + study_methods().len() * 2 * 2);
        assert!(csv.lines().nth(1).unwrap().starts_with("lambert_sphere,bsdf,1,1,16,12,"));
        let cache: Vec<_> = std::fs::read_dir(dir.path().join("cache")).unwrap().collect();
        assert_eq!(cache.len(), 3, "reflected, full and info");
        // A second run takes the cached reference (8 spp) instead of rendering another.
        run(&args(dir.path())).unwrap();
        assert_eq!(std::fs::read_dir(dir.path().join("cache")).unwrap().count(), 3);
        let summary = std::fs::read_to_string(dir.path().join("summary.md")).unwrap();
        assert!(summary.contains("reference 8 spp") && summary.contains(", cached"), "{summary}");
    }

    #[test]
    fn bad_scales_are_usage_errors() {
        let dir = tempfile::tempdir().unwrap();
        let mut a = args(dir.path());
        a.scale = Some(0.0);
        assert!(matches!(run(&a), Err(SimError::Usage(_))));
    }
}
