//! The command line: `render`, `figure`, `scenes`, `study`, `serve`, `import`, `export` and
//! `view`. The flag names are a contract. The integrator's flags are one argument group,
//! [`IntegratorDesc`] (picomis-format), whose keys are those of a scene file's integrator block.
//! Every command that renders takes `-j N` ([`Threads`]); `render` and `figure` refuse a film
//! whose buffers would not fit in memory ([`crate::memory`]) before they allocate.

use std::path::{Path, PathBuf};

use picomis::geometry::MAX_FILM_SIDE;
use picomis::{Film, Preset, RenderSettings};
use picomis_format::IntegratorDesc;

use clap::{Parser, Subcommand};

use crate::SimError;
use crate::figure::{METHODS, render_figure};
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
    #[command(allow_negative_numbers = true)]
    Render(RenderArgs),
    /// Draw the lecture's MIS figure: each technique, average, balance, power, maximum, weights and
    /// contributions, as one labelled PNG.
    #[command(allow_negative_numbers = true)]
    Figure(FigureArgs),
    /// List the built-in scenes.
    Scenes,
    /// Speed against accuracy: error against time and spp per method, equal-time grids,
    /// efficiency tables (see `study` module docs).
    #[command(allow_negative_numbers = true)]
    Study {
        /// What to study.
        #[command(flatten)]
        args: crate::study::StudyArgs,
        /// Threads.
        #[command(flatten)]
        threads: Threads,
    },
    /// Serve the browser page (the kernel as WebAssembly, live MIS; built into picomis-sim) on a
    /// local port.
    Serve(crate::serve::ServeArgs),
    /// Convert a Mitsuba 3 XML scene into a picomis-scene/1 file.
    Import(crate::interop::ImportArgs),
    /// Write a scene as Mitsuba 3 XML.
    Export(crate::interop::ExportArgs),
    /// Show a scene in an embedded-graphics-simulator window, refining pass by pass (needs the
    /// `window` feature).
    #[command(allow_negative_numbers = true)]
    View {
        /// What to show.
        #[command(flatten)]
        args: crate::view::ViewArgs,
        /// Threads.
        #[command(flatten)]
        threads: Threads,
    },
}

impl Command {
    /// The threads of a command that renders.
    pub fn threads(&self) -> Option<Threads> {
        match self {
            Command::Render(a) => Some(a.threads),
            Command::Figure(a) => Some(a.threads),
            Command::Study { threads, .. } | Command::View { threads, .. } => Some(*threads),
            Command::Scenes | Command::Serve(_) | Command::Import(_) | Command::Export(_) => None,
        }
    }
}

/// The threads of a command that renders (`-j N`): the image does not depend on them.
#[derive(Clone, Copy, Debug, clap::Args)]
pub struct Threads {
    /// Threads that render (0: one per core, or RAYON_NUM_THREADS). The images are the same on
    /// any number of threads.
    #[arg(short = 'j', long = "threads", value_name = "N", default_value_t = 0,
          value_parser = clap::value_parser!(u32).range(0..=1024), help_heading = "Performance")]
    pub threads: u32,
}

impl Threads {
    /// Makes rayon's global pool `N` threads (leaves rayon's default for 0); once per process.
    pub fn install(self) -> Result<(), SimError> {
        if self.threads == 0 {
            return Ok(());
        }
        rayon::ThreadPoolBuilder::new()
            .num_threads(self.threads as usize)
            .build_global()
            .map_err(|e| SimError::Usage(format!("--threads {}: {e}", self.threads)))
    }
}

/// `picomis-sim render`.
#[derive(Debug, clap::Args)]
pub struct RenderArgs {
    /// A picomis-scene/1 JSON file (at most 64 shapes, 32 lights, 32 materials) or the name of
    /// a built-in scene, see `picomis-sim scenes` (default: veach_mis).
    pub scene: Option<String>,
    /// Image width (default: the scene's; with only --height, keeps the aspect ratio).
    #[arg(long, value_name = "W", value_parser = clap::value_parser!(u32).range(1..=i64::from(MAX_FILM_SIDE)), help_heading = "Scene")]
    pub width: Option<u32>,
    /// Image height (default: the scene's; with only --width, keeps the aspect ratio).
    #[arg(long, value_name = "H", value_parser = clap::value_parser!(u32).range(1..=i64::from(MAX_FILM_SIDE)), help_heading = "Scene")]
    pub height: Option<u32>,
    /// Arithmetic of the ray queries: f32, or fixed (integers at a scale chosen from the scene's
    /// extent, as on FPU-less cores; a scene it cannot represent is rejected).
    #[arg(long, value_name = "A", default_value = "f32", value_parser = picomis_format::choice_parser::<picomis::Arith>(), help_heading = "Scene")]
    pub arith: picomis::Arith,
    /// Camera samples per pixel.
    #[arg(long, default_value_t = 16, value_parser = clap::value_parser!(u32).range(1..), help_heading = "Sampling")]
    pub spp: u32,
    /// Seed: the same seed gives the same image, on any number of threads.
    #[arg(long, default_value_t = 0, help_heading = "Sampling")]
    pub seed: u32,
    /// The integrator: every key of a scene file's integrator block, as a flag.
    #[command(flatten)]
    pub integrator: IntegratorDesc,
    /// Output file; the extension picks the format (default: `<scene name>.png` here).
    #[arg(short = 'o', long, value_name = "FILE", help_heading = "Output")]
    pub out: Option<PathBuf>,
    /// Also print `hdr-digest N`: the digest of every pixel's HDR estimate (`picomis::Digest`,
    /// the one the firmware logs), to compare two machines bit for bit.
    #[arg(long, help_heading = "Output")]
    pub digest: bool,
    /// Instead of an image, print pixel (X, Y)'s estimate split by technique: what it emits,
    /// each technique's contribution, samples that found light and their mean MIS weight (the
    /// value the image would hold there).
    #[arg(long, value_name = "X,Y", value_parser = crate::pixel::parse, allow_hyphen_values = true, conflicts_with_all = ["out", "digest"], help_heading = "Output")]
    pub pixel: Option<(u32, u32)>,
    /// Threads.
    #[command(flatten)]
    pub threads: Threads,
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
    /// Threads.
    #[command(flatten)]
    pub threads: Threads,
}

/// Panels of the figure's canvas: the renders, and the weights and contributions of two
/// techniques (four columns of three rows at most).
const FIGURE_PANELS: u64 = 12;

/// Runs a parsed command line.
pub fn run(cli: Cli) -> Result<(), SimError> {
    if let Some(threads) = cli.command.threads() {
        threads.install()?;
    }
    match cli.command {
        Command::Render(args) => render(&args),
        Command::Figure(args) => figure(&args),
        Command::Study { args, .. } => crate::study::run(&args),
        Command::Serve(args) => crate::serve::run(&args),
        Command::Import(args) => crate::interop::import(&args),
        Command::Export(args) => crate::interop::export(&args),
        Command::View { args, .. } => crate::view::run(&args),
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
        (Some(w), None) => (w, scaled(w, f.height(), f.width()).min(u64::from(MAX_FILM_SIDE)) as u32),
        (None, Some(h)) => (scaled(h, f.width(), f.height()).min(u64::from(MAX_FILM_SIDE)) as u32, h),
        (None, None) => (f.width(), f.height()),
    };
    Film::new(w, h).map_err(|e| SimError::Usage(format!("--width {w} --height {h}: {e}")))
}

fn render(args: &RenderArgs) -> Result<(), SimError> {
    let loaded = scenes::load(args.scene.as_deref())?;
    let name = loaded.file.name();
    let settings = settings(&loaded, args)?;
    let film = film(&loaded, args)?;
    if let Some((x, y)) = args.pixel {
        return pixel(&loaded, args, &settings, film, (x, y));
    }
    let out = args.out.clone().unwrap_or_else(|| default_out(name, ".png"));
    let format = check_output(&out).map_err(SimError::Usage)?;
    let what = format!("{name}: a {}x{} render to {}", film.width(), film.height(), out.display());
    crate::memory::check(&what, crate::memory::render_bytes(film, format))?;

    let scene = build(&loaded, args, film)?;
    let batch = RenderBatch { settings: &[settings], message: name }
        .run(&scene)
        .map_err(|e| SimError::Usage(format!("{name}: {e}")))?;
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
    eprintln!(
        "{}, {:.3} s, {} camera samples/s on {} -> {}",
        summary(name, film, &settings),
        secs,
        rate(batch.camera_samples, secs),
        threads(),
        out.display()
    );
    Ok(())
}

/// The scene of `render` at `film`, with `--arith`.
fn build(loaded: &Loaded, args: &RenderArgs, film: Film) -> Result<picomis_host::HostScene, SimError> {
    let mut scene = loaded.build(film)?;
    scene.enable_arith(args.arith).map_err(|e| {
        let e = crate::render::scene_error(&loaded.file, &e);
        SimError::Usage(format!("{}: --arith {}: {e}", loaded.file.name(), args.arith.name()))
    })?;
    Ok(scene)
}

/// What a render is: `name: WxH, N spp, method (parameter)[, keys away from the best preset],
/// L light + B bsdf samples`.
fn summary(name: &str, film: Film, settings: &RenderSettings) -> String {
    let (n_light, n_bsdf) = settings.technique_samples();
    format!(
        "{name}: {}x{}, {} spp, {}, {n_light} light + {n_bsdf} bsdf samples",
        film.width(),
        film.height(),
        settings.spp(),
        describe(settings.method()) + &extras_note(settings),
    )
}

/// `render --pixel X,Y`: the breakdown of that pixel's estimate ([`crate::pixel`]), no image.
fn pixel(
    loaded: &Loaded,
    args: &RenderArgs,
    settings: &RenderSettings,
    film: Film,
    (x, y): (u32, u32),
) -> Result<(), SimError> {
    let name = loaded.file.name();
    if x >= film.width() || y >= film.height() {
        return Err(SimError::Usage(format!(
            "--pixel {x},{y}: outside the {}x{} film (X from 0 to {}, Y from 0 to {})",
            film.width(),
            film.height(),
            film.width() - 1,
            film.height() - 1
        )));
    }
    let scene = build(loaded, args, film)?;
    let renderer =
        picomis_host::renderer(&scene, settings).map_err(|e| SimError::Usage(format!("{name}: {e}")))?;
    let estimate = renderer.render_pixel(x, y);
    let title = format!("{}; pixel ({x}, {y})", summary(name, film, settings));
    print!("{}", crate::pixel::table(&title, settings, scene.lights().len(), &estimate));
    Ok(())
}

/// The threads rendering, in words.
fn threads() -> String {
    match rayon::current_num_threads() {
        1 => "1 thread".to_string(),
        n => format!("{n} threads"),
    }
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
    let film = loaded.file.film();
    let what = format!(
        "{}: a figure of {} {}x{} renders",
        loaded.file.name(),
        METHODS.len(),
        film.width(),
        film.height()
    );
    crate::memory::check(&what, crate::memory::figure_bytes(film, METHODS.len() as u64, FIGURE_PANELS))?;
    let (canvas, batch) = render_figure(&loaded, args.spp, args.seed, &args.integrator)?;
    let bytes = encode_png(canvas.width, canvas.height, &canvas.bytes()).map_err(SimError::Io)?;
    write_atomic(&out, &bytes).map_err(SimError::Io)?;
    let secs = batch.elapsed.as_secs_f64();
    eprintln!(
        "{}: figure of {} renders at {} spp, {:.3} s, {} camera samples/s on {} -> {}",
        loaded.file.name(),
        METHODS.len(),
        args.spp,
        secs,
        rate(batch.camera_samples, secs),
        threads(),
        Path::new(&out).display()
    );
    Ok(())
}
