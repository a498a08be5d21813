//! The command line: `render`, `figure` and `scenes`. The flag names are a contract.

use std::path::{Path, PathBuf};

use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
use clap::{Parser, Subcommand, ValueEnum};
use picomis::{Film, Heuristic, LightSelection, Method, RenderSettings, SamplerKind, SphereSampling};

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
    /// Combination method (default: the scene's integrator block).
    #[arg(long, value_name = "M", value_parser = method_parser())]
    pub mis: Option<Method>,
    /// Power-heuristic exponent.
    #[arg(long, value_name = "B", allow_negative_numbers = true,
          help = format!("Power-heuristic exponent (default: the scene's, else {})", Heuristic::DEFAULT_BETA))]
    pub beta: Option<f32>,
    /// Cutoff-heuristic threshold.
    #[arg(long, value_name = "A", allow_negative_numbers = true,
          help = format!("Cutoff-heuristic threshold (default: the scene's, else {})", Heuristic::DEFAULT_ALPHA))]
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
    #[arg(long, value_name = "S", value_parser = sampler_parser())]
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

/// The `--mis` value parser: the kernel's method names (with their summaries in the help),
/// parsed by the kernel.
fn method_parser() -> impl TypedValueParser<Value = Method> {
    let names = Method::ALL.map(|m| PossibleValue::new(m.name()).help(m.summary()));
    PossibleValuesParser::new(names).try_map(|name| Method::from_name(&name).map_err(|e| e.to_string()))
}

/// The `--sampler` value parser: the kernel's sample streams.
fn sampler_parser() -> impl TypedValueParser<Value = SamplerKind> {
    let names = SamplerKind::ALL.map(|k| PossibleValue::new(k.name()));
    PossibleValuesParser::new(names)
        .try_map(|name| SamplerKind::from_name(&name).ok_or_else(|| format!("unknown sampler {name:?}")))
}

/// The method with its parameter, as the render line shows it.
fn describe(m: Method) -> String {
    match (m.beta(), m.alpha()) {
        (Some(beta), _) => format!("{m} (beta {beta})"),
        (_, Some(alpha)) => format!("{m} (alpha {alpha})"),
        _ => m.to_string(),
    }
}

/// The render settings from the scene's integrator block overridden by the flags.
pub fn settings(loaded: &Loaded, args: &RenderArgs) -> Result<RenderSettings, SimError> {
    let usage = SimError::Usage;
    let scene_method = loaded.file.default_method();
    // A method named on the command line comes with its defaults, unless it is the scene's own
    // method: then it keeps the scene's parameters.
    let method = match args.mis {
        Some(m) if m.name() != scene_method.name() => m,
        _ => scene_method,
    };
    let name = method.name();
    let mut flags = format!("--mis {name}");
    if let Some(beta) = args.beta {
        flags += &format!(" --beta {beta}");
    }
    if let Some(alpha) = args.alpha {
        flags += &format!(" --alpha {alpha}");
    }
    let method = method.with_parameters(args.beta, args.alpha).map_err(|e| usage(format!("{flags}: {e}")))?;
    if let (Some(beta), None) = (args.beta, method.beta()) {
        return Err(usage(format!("--beta {beta}: only the power heuristic has a beta (method is {name})")));
    }
    if let (Some(alpha), None) = (args.alpha, method.alpha()) {
        return Err(usage(format!(
            "--alpha {alpha}: only the cutoff heuristic has an alpha (method is {name})"
        )));
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
