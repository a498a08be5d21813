//! The command line: `render`, `figure` and `scenes`. The flag names are a contract.

use std::path::{Path, PathBuf};

use clap::{Parser, Subcommand, ValueEnum};
use picomis::{Film, Heuristic, LightSelection, Method, RenderSettings, SamplerKind, SphereSampling};
use picomis_format::parse_method;

use crate::SimError;
use crate::figure::render_figure;
use crate::output::{Format, Image, check_output, encode, encode_png, write_atomic};
use crate::render::RenderBatch;
use crate::scenes::{self, BUILTINS, Loaded};

/// picomis-sim: render picomis scenes on the host.
#[derive(Debug, Parser)]
#[command(name = "picomis-sim", version, about)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// Commands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Render a scene to an image (.png, .exr, .pfm or .rgb565).
    Render(RenderArgs),
    /// Draw the seed's MIS figure: each technique, average, balance, power, maximum, weights and
    /// contributions, as one labelled PNG.
    Figure(FigureArgs),
    /// List the built-in scenes.
    Scenes,
    /// Speed against accuracy: error against time and spp per method, equal-time grids,
    /// efficiency tables (see `study` module docs).
    Study(crate::study::StudyArgs),
}

/// How sphere lights are sampled.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum SphereSamplingArg {
    /// Uniformly by area (the seed's formulation).
    Area,
    /// Uniformly in the cone the sphere subtends.
    Cone,
}

/// How a light is chosen among several.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum LightSelectionArg {
    /// Every light equally likely.
    Uniform,
    /// Proportional to emitted power.
    Power,
}

/// `picomis-sim render`.
#[derive(Debug, clap::Args)]
pub struct RenderArgs {
    /// A picomis-scene/1 JSON file (at most 64 shapes, 32 lights, 32 materials) or the name of
    /// a built-in scene, see `picomis-sim scenes` (default: veach_mis).
    pub scene: Option<String>,
    /// Camera samples per pixel.
    #[arg(long, default_value_t = 16, value_parser = clap::value_parser!(u32).range(1..))]
    pub spp: u32,
    /// Combination: bsdf, light, average, balance, power, maximum or cutoff (default: the
    /// scene's integrator block).
    #[arg(long, value_name = "M")]
    pub mis: Option<String>,
    /// Power-heuristic exponent (default: the scene's, else 2).
    #[arg(long, value_name = "B", allow_negative_numbers = true)]
    pub beta: Option<f32>,
    /// Cutoff-heuristic threshold (default: the scene's, else 0.1).
    #[arg(long, value_name = "A", allow_negative_numbers = true)]
    pub alpha: Option<f32>,
    /// Light samples per camera sample (default: the scene's emitter_samples).
    #[arg(long, value_name = "N")]
    pub light_samples: Option<u16>,
    /// BSDF samples per camera sample (default: the scene's bsdf_samples).
    #[arg(long, value_name = "N")]
    pub bsdf_samples: Option<u16>,
    /// How sphere lights are sampled.
    #[arg(long, value_enum, default_value_t = SphereSamplingArg::Cone)]
    pub sphere_sampling: SphereSamplingArg,
    /// How a light is chosen among several.
    #[arg(long, value_enum, default_value_t = LightSelectionArg::Uniform)]
    pub light_selection: LightSelectionArg,
    /// Sample stream: sobol (padded Owen-scrambled Sobol) or independent (default: the scene's
    /// integrator block, else sobol).
    #[arg(long, value_name = "S", value_parser = parse_sampler)]
    pub sampler: Option<SamplerKind>,
    /// Seed: the same seed gives the same image, on any number of threads.
    #[arg(long, default_value_t = 0)]
    pub seed: u32,
    /// Image width (default: the scene's; with only --height, keeps the aspect ratio).
    #[arg(long, value_name = "W", value_parser = clap::value_parser!(u32).range(1..=16384))]
    pub width: Option<u32>,
    /// Image height (default: the scene's; with only --width, keeps the aspect ratio).
    #[arg(long, value_name = "H", value_parser = clap::value_parser!(u32).range(1..=16384))]
    pub height: Option<u32>,
    /// Output file; the extension picks the format (default: `<scene name>.png` here).
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
}

/// `picomis-sim figure`.
#[derive(Debug, clap::Args)]
pub struct FigureArgs {
    /// A picomis-scene/1 JSON file or the name of a built-in scene (default: veach_mis).
    pub scene: Option<String>,
    /// Camera samples per pixel of each render.
    #[arg(long, default_value_t = 32, value_parser = clap::value_parser!(u32).range(1..))]
    pub spp: u32,
    /// Seed.
    #[arg(long, default_value_t = 0)]
    pub seed: u32,
    /// Output PNG (default: `<scene name>_figure.png` here).
    #[arg(long, value_name = "FILE.png")]
    pub out: Option<PathBuf>,
}

/// Runs a parsed command line.
pub fn run(cli: Cli) -> Result<(), SimError> {
    match cli.command {
        Command::Render(args) => render(&args),
        Command::Figure(args) => figure(&args),
        Command::Study(args) => crate::study::run(&args),
        Command::Scenes => {
            for b in BUILTINS {
                let film = picomis_format::SceneFile::parse(b.json, b.name)?.film();
                println!(
                    "{:<16} {:>4}x{:<4} {:>2} shapes {:>2} lights {:>2} materials  {}",
                    b.name,
                    film.width(),
                    film.height(),
                    b.shapes,
                    b.lights,
                    b.materials,
                    b.description
                );
            }
            Ok(())
        }
    }
}

/// The default output file for scene `name`: `<name><suffix>` in the current folder, with any
/// character that is not alphanumeric, `-` or `_` replaced by `_`.
fn default_out(name: &str, suffix: &str) -> PathBuf {
    let mut stem: String = name
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() || c == '-' || c == '_' { c } else { '_' })
        .collect();
    if stem.is_empty() {
        stem = "scene".into();
    }
    PathBuf::from(format!("{stem}{suffix}"))
}

/// A sample stream by name ([`SamplerKind::name`]).
pub fn parse_sampler(name: &str) -> Result<SamplerKind, String> {
    SamplerKind::from_name(name).ok_or_else(|| {
        let names: Vec<&str> = SamplerKind::ALL.iter().map(|k| k.name()).collect();
        format!("unknown sampler {name:?} (expected {})", names.join(" or "))
    })
}

/// The CLI name of a method.
pub fn method_name(m: Method) -> &'static str {
    match m {
        Method::BsdfOnly => "bsdf",
        Method::LightOnly => "light",
        Method::Mis(Heuristic::Average) => "average",
        Method::Mis(Heuristic::Balance) => "balance",
        Method::Mis(Heuristic::Power { .. }) => "power",
        Method::Mis(Heuristic::Maximum) => "maximum",
        Method::Mis(Heuristic::Cutoff { .. }) => "cutoff",
    }
}

fn describe(m: Method) -> String {
    match m {
        Method::Mis(Heuristic::Power { beta }) => format!("power (beta {beta})"),
        Method::Mis(Heuristic::Cutoff { alpha }) => format!("cutoff (alpha {alpha})"),
        other => method_name(other).to_string(),
    }
}

/// The render settings from the scene's integrator block overridden by the flags.
pub fn settings(loaded: &Loaded, args: &RenderArgs) -> Result<RenderSettings, SimError> {
    let usage = SimError::Usage;
    let scene_method = loaded.file.default_method();
    let (scene_beta, scene_alpha) = match scene_method {
        Method::Mis(Heuristic::Power { beta }) => (beta, 0.1),
        Method::Mis(Heuristic::Cutoff { alpha }) => (2.0, alpha),
        _ => (2.0, 0.1),
    };
    let name = args.mis.as_deref().unwrap_or(method_name(scene_method));
    let mut flags = format!("--mis {name}");
    if let Some(beta) = args.beta {
        flags += &format!(" --beta {beta}");
    }
    if let Some(alpha) = args.alpha {
        flags += &format!(" --alpha {alpha}");
    }
    let method = parse_method(name, args.beta.unwrap_or(scene_beta), args.alpha.unwrap_or(scene_alpha))
        .map_err(|e| usage(format!("{flags}: {e}")))?;
    if let Some(beta) = args.beta {
        if !matches!(method, Method::Mis(Heuristic::Power { .. })) {
            return Err(usage(format!(
                "--beta {beta}: only the power heuristic has a beta (method is {name})"
            )));
        }
    }
    if let Some(alpha) = args.alpha {
        if !matches!(method, Method::Mis(Heuristic::Cutoff { .. })) {
            return Err(usage(format!(
                "--alpha {alpha}: only the cutoff heuristic has an alpha (method is {name})"
            )));
        }
    }
    let (scene_light, scene_bsdf) = loaded.file.default_samples();
    let n_light = args.light_samples.unwrap_or(scene_light);
    let n_bsdf = args.bsdf_samples.unwrap_or(scene_bsdf);
    let settings = RenderSettings::new(method, n_light, n_bsdf, args.spp, args.seed).map_err(|e| {
        usage(format!(
            "--mis {name} --light-samples {n_light} --bsdf-samples {n_bsdf} --spp {}: {e}",
            args.spp
        ))
    })?;
    let spheres = match args.sphere_sampling {
        SphereSamplingArg::Area => SphereSampling::Area,
        SphereSamplingArg::Cone => SphereSampling::Cone,
    };
    let selection = match args.light_selection {
        LightSelectionArg::Uniform => LightSelection::Uniform,
        LightSelectionArg::Power => LightSelection::Power,
    };
    let sampler = args.sampler.unwrap_or(loaded.file.default_sampler());
    Ok(settings.with_sphere_sampling(spheres).with_light_selection(selection).with_sampler(sampler))
}

/// The film from the scene and `--width` / `--height`.
fn film(loaded: &Loaded, args: &RenderArgs) -> Result<Film, SimError> {
    let f = loaded.file.film();
    let scaled =
        |num: u32, a: u32, b: u32| ((u64::from(num) * u64::from(a) + u64::from(b) / 2) / u64::from(b)).max(1);
    let (w, h) = match (args.width, args.height) {
        (Some(w), Some(h)) => (w, h),
        (Some(w), None) => (w, scaled(w, f.height(), f.width()).min(16384) as u32),
        (None, Some(h)) => (scaled(h, f.width(), f.height()).min(16384) as u32, h),
        (None, None) => (f.width(), f.height()),
    };
    Film::new(w, h).map_err(|e| SimError::Usage(format!("--width {w} --height {h}: {e}")))
}

fn render(args: &RenderArgs) -> Result<(), SimError> {
    let loaded = scenes::load(args.scene.as_deref())?;
    let settings = settings(&loaded, args)?;
    let film = film(&loaded, args)?;
    let out = args.out.clone().unwrap_or_else(|| default_out(loaded.file.name(), ".png"));
    let format = check_output(&out).map_err(SimError::Usage)?;

    let batch = loaded.visit(film, RenderBatch { settings: &[settings], message: loaded.file.name() })?;
    let estimates = &batch.images[0];
    let image = Image {
        width: estimates.width,
        height: estimates.height,
        data: estimates.pixels.iter().map(|e| e.radiance()).collect(),
    };
    let bytes = encode(&image, format).map_err(SimError::Io)?;
    write_atomic(&out, &bytes).map_err(SimError::Io)?;

    let secs = batch.elapsed.as_secs_f64();
    let (n_light, n_bsdf) = settings.technique_samples();
    eprintln!(
        "{}: {}x{}, {} spp, {}, {n_light} light + {n_bsdf} bsdf samples, {:.3} s, {} camera samples/s -> {}",
        loaded.file.name(),
        film.width(),
        film.height(),
        settings.spp(),
        describe(settings.method()),
        secs,
        rate(batch.camera_samples, secs),
        out.display()
    );
    Ok(())
}

fn rate(samples: u64, secs: f64) -> String {
    let r = samples as f64 / secs.max(1e-9);
    if r >= 1e6 { format!("{:.2} M", r / 1e6) } else { format!("{:.1} k", r / 1e3) }
}

fn figure(args: &FigureArgs) -> Result<(), SimError> {
    let loaded = scenes::load(args.scene.as_deref())?;
    let out = args.out.clone().unwrap_or_else(|| default_out(loaded.file.name(), "_figure.png"));
    if check_output(&out).map_err(SimError::Usage)? != Format::Png {
        return Err(SimError::Usage(format!("{}: the figure is written as PNG (.png)", out.display())));
    }
    let (canvas, batch) = render_figure(&loaded, args.spp, args.seed)?;
    let bytes = encode_png(canvas.width, canvas.height, &canvas.bytes()).map_err(SimError::Io)?;
    write_atomic(&out, &bytes).map_err(SimError::Io)?;
    let secs = batch.elapsed.as_secs_f64();
    eprintln!(
        "{}: figure of 6 renders at {} spp, {:.3} s, {} camera samples/s -> {}",
        loaded.file.name(),
        args.spp,
        secs,
        rate(batch.camera_samples, secs),
        Path::new(&out).display()
    );
    Ok(())
}
