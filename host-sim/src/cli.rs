//! The command line: `render`, `figure` and `scenes`. The flag names are a contract.

use std::path::{Path, PathBuf};

use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
use clap::{Parser, Subcommand, ValueEnum};
use picomis::{
    ControlVariate, Film, Heuristic, LightSelection, LobeMixing, Method, MisModel, QuadSampling,
    RenderSettings, SamplerKind, SphereSampling,
};
use picomis_format::parse_mis_model;

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
    /// Draw the lecture's MIS figure: each technique, average, balance, power, maximum, weights and
    /// contributions, as one labelled PNG.
    Figure(FigureArgs),
    /// List the built-in scenes.
    Scenes,
    /// Speed against accuracy: error against time and spp per method, equal-time grids,
    /// efficiency tables (see `study` module docs).
    Study(crate::study::StudyArgs),
    /// Serve the browser page (web/: the kernel as WebAssembly, live MIS) on a local port.
    Serve(crate::serve::ServeArgs),
    /// Convert a Mitsuba 3 XML scene into a picomis-scene/1 file.
    Import(crate::interop::ImportArgs),
    /// Write a scene as Mitsuba 3 XML.
    Export(crate::interop::ExportArgs),
    /// Show a scene in an embedded-graphics-simulator window, refining pass by pass (needs the
    /// `window` feature).
    View(crate::view::ViewArgs),
}

/// The MIS sampling model.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum MisModelArg {
    /// Every technique draws its samples (light and BSDF sample counts).
    Multi,
    /// One sample per camera sample: light with probability --c-light, else BSDF.
    One,
}

/// Whether unoccluded light is computed in closed form (Lambertian receivers).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum OnOff {
    /// On.
    On,
    /// Off.
    Off,
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
    #[arg(long, value_name = "S", value_parser = sphere_sampling_parser(), default_value_t = SphereSampling::DEFAULT)]
    pub sphere_sampling: SphereSampling,
    /// How a light is chosen among several (default: the scene's integrator block, else the
    /// kernel's default).
    #[arg(long, value_name = "S", value_parser = selection_parser())]
    pub light_selection: Option<LightSelection>,
    /// How quad lights are sampled (default: the scene's integrator block, else area).
    #[arg(long, value_name = "Q", value_parser = quad_sampling_parser())]
    pub quad_sampling: Option<QuadSampling>,
    /// MIS model: multi-sample or one-sample (default: the scene's integrator block, else multi).
    #[arg(long, value_enum)]
    pub mis_model: Option<MisModelArg>,
    /// Probability of the light technique in the one-sample model, in [0, 1] (default: the
    /// scene's, else 0.5).
    #[arg(long, value_name = "C", allow_negative_numbers = true)]
    pub c_light: Option<f32>,
    /// Unoccluded light of quad and sphere lights on Lambertian surfaces in closed form, Monte
    /// Carlo for the shadows only.
    #[arg(long, value_enum, default_value_t = OnOff::Off)]
    pub control_variate: OnOff,
    /// Light samples also from a glossy receiver's lobe, where the lobe is narrower than the
    /// light (the rim and the glow of a light's reflection in a near-mirror).
    #[arg(long, value_enum, default_value_t = OnOff::Off)]
    pub lobe_mixing: OnOff,
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
    /// Also print `hdr-digest N`: the digest of every pixel's HDR estimate (`picomis::Digest`,
    /// the one the firmware logs), to compare two machines bit for bit.
    #[arg(long)]
    pub digest: bool,
    /// Arithmetic of the ray queries: f32, or fixed (integers at a scale chosen from the scene's
    /// extent, as on FPU-less cores; a scene it cannot represent is rejected).
    #[arg(long, value_name = "A", default_value = "f32", value_parser = arith_parser())]
    pub arith: picomis::Arith,
}

fn arith_parser() -> impl clap::builder::TypedValueParser<Value = picomis::Arith> {
    clap::builder::PossibleValuesParser::new(["f32", "fixed"])
        .map(|s| picomis::Arith::parse(&s).unwrap_or_default())
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
    /// Beyond the lecture: applied to every render of the figure.
    #[command(flatten)]
    pub extras: ExtrasArgs,
    /// Output PNG (default: `<scene name>_figure.png` here).
    #[arg(long, value_name = "FILE.png")]
    pub out: Option<PathBuf>,
}

/// The options beyond the lecture, for commands that apply them to several renders.
#[derive(Debug, Clone, clap::Args)]
pub struct ExtrasArgs {
    /// MIS model: multi-sample or one-sample.
    #[arg(long, value_enum, default_value_t = MisModelArg::Multi)]
    pub mis_model: MisModelArg,
    /// Probability of the light technique in the one-sample model, in [0, 1].
    #[arg(long, value_name = "C", default_value_t = picomis::integrator::model::DEFAULT_C_LIGHT, allow_negative_numbers = true)]
    pub c_light: f32,
    /// How quad lights are sampled.
    #[arg(long, value_name = "Q", value_parser = quad_sampling_parser(), default_value_t = QuadSampling::default())]
    pub quad_sampling: QuadSampling,
    /// Unoccluded light of quad and sphere lights on Lambertian surfaces in closed form.
    #[arg(long, value_enum, default_value_t = OnOff::Off)]
    pub control_variate: OnOff,
}

impl ExtrasArgs {
    /// The study's form of these options (validated: `c_light` in [0, 1]).
    pub fn extras(&self) -> Result<picomis_host::study::Extras, SimError> {
        let name = match self.mis_model {
            MisModelArg::Multi => "multi",
            MisModelArg::One => "one",
        };
        let model = parse_mis_model(name, self.c_light)
            .map_err(|e| SimError::Usage(format!("--mis-model {name} --c-light {}: {e}", self.c_light)))?;
        Ok(picomis_host::study::Extras {
            model,
            quads: self.quad_sampling,
            control_variate: match self.control_variate {
                OnOff::On => ControlVariate::On,
                OnOff::Off => ControlVariate::Off,
            },
            ..picomis_host::study::Extras::default()
        })
    }
}

/// Runs a parsed command line.
pub fn run(cli: Cli) -> Result<(), SimError> {
    match cli.command {
        Command::Render(args) => render(&args),
        Command::Figure(args) => figure(&args),
        Command::Study(args) => crate::study::run(&args),
        Command::Serve(args) => crate::serve::run(&args),
        Command::Import(args) => crate::interop::import(&args),
        Command::Export(args) => crate::interop::export(&args),
        Command::View(args) => crate::view::run(&args),
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

/// The `--quad-sampling` value parser: the kernel's quad-light strategies (with their summaries).
fn quad_sampling_parser() -> impl TypedValueParser<Value = QuadSampling> {
    let names = QuadSampling::ALL.map(|q| PossibleValue::new(q.name()).help(q.summary()));
    PossibleValuesParser::new(names).try_map(|name| {
        QuadSampling::from_name(&name).ok_or_else(|| format!("unknown quad sampling {name:?}"))
    })
}

/// The `--sphere-sampling` value parser: the kernel's strategies (with their summaries in the
/// help).
pub fn sphere_sampling_parser() -> impl TypedValueParser<Value = SphereSampling> {
    let names = SphereSampling::ALL.map(|s| PossibleValue::new(s.name()).help(s.summary()));
    PossibleValuesParser::new(names).try_map(|name| {
        SphereSampling::from_name(&name).ok_or_else(|| format!("unknown sphere sampling {name:?}"))
    })
}

/// The `--sampler` value parser: the kernel's sample streams.
fn sampler_parser() -> impl TypedValueParser<Value = SamplerKind> {
    let names = SamplerKind::ALL.map(|k| PossibleValue::new(k.name()));
    PossibleValuesParser::new(names)
        .try_map(|name| SamplerKind::from_name(&name).ok_or_else(|| format!("unknown sampler {name:?}")))
}

/// The `--light-selection` value parser: the kernel's strategies (with their summaries in the
/// help).
pub fn selection_parser() -> impl TypedValueParser<Value = LightSelection> {
    let names = LightSelection::ALL.map(|s| PossibleValue::new(s.name()).help(s.summary()));
    PossibleValuesParser::new(names).try_map(|name| {
        LightSelection::from_name(&name).ok_or_else(|| format!("unknown light selection {name:?}"))
    })
}

/// The method with its parameter, as the render line shows it.
fn describe(m: Method) -> String {
    match (m.beta(), m.alpha()) {
        (Some(beta), _) => format!("{m} (beta {beta})"),
        (_, Some(alpha)) => format!("{m} (alpha {alpha})"),
        _ => m.to_string(),
    }
}

/// The options beyond the lecture that differ from their defaults, for the summary line.
fn extras_note(s: &RenderSettings) -> String {
    let mut note = String::new();
    if s.light_selection() != LightSelection::default() {
        note += &format!(", light selection {}", s.light_selection().name());
    }
    if s.sampler() != SamplerKind::default() {
        note += &format!(", {} sampler", s.sampler().name());
    }
    if let MisModel::One { c_light } = s.mis_model() {
        note += &format!(", one-sample model (c_light {c_light})");
    }
    match s.quad_sampling() {
        QuadSampling::Area => {}
        QuadSampling::SolidAngle => note += ", quads by solid angle",
        QuadSampling::SolidAngleCosine => note += ", quads by solid angle x cosine",
    }
    if s.control_variate() == ControlVariate::On {
        note += ", control variate";
    }
    if s.lobe_mixing() == LobeMixing::On {
        note += ", lobe mixing";
    }
    note
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
    let spheres = args.sphere_sampling;
    let control_variate = match args.control_variate {
        OnOff::On => ControlVariate::On,
        OnOff::Off => ControlVariate::Off,
    };
    let scene_model = loaded.file.default_model();
    let scene_c = match scene_model {
        MisModel::One { c_light } => c_light,
        MisModel::Multi => picomis::integrator::model::DEFAULT_C_LIGHT,
    };
    let model_name = match (args.mis_model, scene_model) {
        (Some(MisModelArg::One), _) | (None, MisModel::One { .. }) => "one",
        (Some(MisModelArg::Multi), _) | (None, MisModel::Multi) => "multi",
    };
    if let (Some(c), "multi") = (args.c_light, model_name) {
        return Err(usage(format!("--c-light {c}: only the one-sample model (--mis-model one) has a c")));
    }
    let c_light = args.c_light.unwrap_or(scene_c);
    let model = parse_mis_model(model_name, c_light)
        .map_err(|e| usage(format!("--mis-model {model_name} --c-light {c_light}: {e}")))?;
    let settings = settings.with_mis_model(model).map_err(|e| usage(format!("--c-light {c_light}: {e}")))?;
    let lobe = match args.lobe_mixing {
        OnOff::On => LobeMixing::On,
        OnOff::Off => LobeMixing::Off,
    };
    let settings = settings.with_lobe_mixing(lobe).map_err(|e| usage(format!("--lobe-mixing: {e}")))?;
    let sampler = args.sampler.unwrap_or(loaded.file.default_sampler());
    Ok(settings
        .with_sphere_sampling(spheres)
        .with_light_selection(args.light_selection.unwrap_or(loaded.file.default_light_selection()))
        .with_quad_sampling(args.quad_sampling.unwrap_or(loaded.file.default_quad_sampling()))
        .with_control_variate(control_variate)
        .with_sampler(sampler))
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

    let batch = RenderBatch { settings: &[settings], message: loaded.file.name() };
    let batch = loaded.visit(film, crate::render::ArithBatch { arith: args.arith, batch })?.map_err(|e| {
        let e = crate::render::scene_error(&loaded.file, &e);
        SimError::Usage(format!("{}: --arith {}: {e}", loaded.file.name(), args.arith.name()))
    })?;
    let estimates = &batch.images[0];
    let image = Image {
        width: estimates.width,
        height: estimates.height,
        data: estimates.pixels.iter().map(|e| e.radiance()).collect(),
    };
    let bytes = encode(&image, format).map_err(SimError::Io)?;
    write_atomic(&out, &bytes).map_err(SimError::Io)?;
    if args.digest {
        let mut digest = picomis::Digest::new();
        estimates.pixels.iter().for_each(|e| digest.push(e));
        println!("hdr-digest {}", digest.value());
    }

    let secs = batch.elapsed.as_secs_f64();
    let (n_light, n_bsdf) = settings.technique_samples();
    eprintln!(
        "{}: {}x{}, {} spp, {}, {n_light} light + {n_bsdf} bsdf samples, {:.3} s, {} camera samples/s -> {}",
        loaded.file.name(),
        film.width(),
        film.height(),
        settings.spp(),
        describe(settings.method()) + &extras_note(&settings),
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
    let (canvas, batch) = render_figure(&loaded, args.spp, args.seed, &args.extras.extras()?)?;
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
