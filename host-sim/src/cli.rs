//! The command line: `render`, `figure`, `scenes`, `study`, `serve`, `import`, `export` and
//! `view`. The flag names are a contract. The integrator's flags are one argument group,
//! [`IntegratorDesc`] (picomis-format), whose keys are those of a scene file's integrator block.

use std::path::{Path, PathBuf};

use picomis::{Film, Preset, RenderSettings};
use picomis_format::IntegratorDesc;

use clap::{Parser, Subcommand};

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

/// `picomis-sim render`.
#[derive(Debug, clap::Args)]
pub struct RenderArgs {
    /// A picomis-scene/1 JSON file (at most 64 shapes, 32 lights, 32 materials) or the name of
    /// a built-in scene, see `picomis-sim scenes` (default: veach_mis).
    pub scene: Option<String>,
    /// Camera samples per pixel.
    #[arg(long, default_value_t = 16, value_parser = clap::value_parser!(u32).range(1..), help_heading = "Sampling")]
    pub spp: u32,
    /// The integrator: every key of a scene file's integrator block, as a flag.
    #[command(flatten)]
    pub integrator: IntegratorDesc,
    /// Seed: the same seed gives the same image, on any number of threads.
    #[arg(long, default_value_t = 0, help_heading = "Sampling")]
    pub seed: u32,
    /// Image width (default: the scene's; with only --height, keeps the aspect ratio).
    #[arg(long, value_name = "W", value_parser = clap::value_parser!(u32).range(1..=16384), help_heading = "Scene")]
    pub width: Option<u32>,
    /// Image height (default: the scene's; with only --width, keeps the aspect ratio).
    #[arg(long, value_name = "H", value_parser = clap::value_parser!(u32).range(1..=16384), help_heading = "Scene")]
    pub height: Option<u32>,
    /// Arithmetic of the ray queries: f32, or fixed (integers at a scale chosen from the scene's
    /// extent, as on FPU-less cores; a scene it cannot represent is rejected).
    #[arg(long, value_name = "A", default_value = "f32", value_parser = picomis_format::choice_parser::<picomis::Arith>(), help_heading = "Scene")]
    pub arith: picomis::Arith,
    /// Output file; the extension picks the format (default: `<scene name>.png` here).
    #[arg(short = 'o', long, value_name = "FILE", help_heading = "Output")]
    pub out: Option<PathBuf>,
    /// Also print `hdr-digest N`: the digest of every pixel's HDR estimate (`picomis::Digest`,
    /// the one the firmware logs), to compare two machines bit for bit.
    #[arg(long, help_heading = "Output")]
    pub digest: bool,
}

/// `picomis-sim figure`.
#[derive(Debug, clap::Args)]
pub struct FigureArgs {
    /// A picomis-scene/1 JSON file or the name of a built-in scene (default: veach_mis).
    pub scene: Option<String>,
    /// Camera samples per pixel of each render.
    #[arg(long, default_value_t = 32, value_parser = clap::value_parser!(u32).range(1..), help_heading = "Sampling")]
    pub spp: u32,
    /// Seed.
    #[arg(long, default_value_t = 0, help_heading = "Sampling")]
    pub seed: u32,
    /// The integrator of every render (each panel its own method): the scene file's block over
    /// the lecture's preset, and these flags over both.
    #[command(flatten)]
    pub integrator: IntegratorDesc,
    /// Output PNG (default: `<scene name>_figure.png` here).
    #[arg(short = 'o', long, value_name = "FILE.png", help_heading = "Output")]
    pub out: Option<PathBuf>,
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

/// The method with its parameter, as the render line shows it.
fn describe(m: picomis::Method) -> String {
    match (m.beta(), m.alpha()) {
        (Some(beta), _) => format!("{m} (beta {beta})"),
        (_, Some(alpha)) => format!("{m} (alpha {alpha})"),
        _ => m.to_string(),
    }
}

/// The settings that differ from the defaults' (the best preset), for the summary line.
fn extras_note(s: &RenderSettings) -> String {
    IntegratorDesc::differences(s, Preset::Best).iter().map(|(k, v)| format!(", {k} {v}")).collect()
}

/// The render settings from the scene's integrator block overridden by the flags.
pub fn settings(loaded: &Loaded, args: &RenderArgs) -> Result<RenderSettings, SimError> {
    crate::integrator::integrator(loaded, &args.integrator, None, args.spp, args.seed)
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

    let mut scene = loaded.build(film)?;
    scene.enable_arith(args.arith).map_err(|e| {
        let e = crate::render::scene_error(&loaded.file, &e);
        SimError::Usage(format!("{}: --arith {}: {e}", loaded.file.name(), args.arith.name()))
    })?;
    let batch = RenderBatch { settings: &[settings], message: loaded.file.name() }
        .run(&scene)
        .map_err(|e| SimError::Usage(format!("{}: {e}", loaded.file.name())))?;
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
    let (canvas, batch) = render_figure(&loaded, args.spp, args.seed, &args.integrator)?;
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
