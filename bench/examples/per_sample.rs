//! Cost of a camera sample, in nanoseconds, per scene and thread count: a table for the README.
//!
//! With no scene named, every built-in scene (the list of `picomis-builtins`) is rendered at its
//! own film with its defaults (the integrator `picomis-sim render` would use: the flags over the
//! scene file's integrator block over the best preset), on 1 thread and on 2 threads, by the
//! simulator's own parallel render (`picomis_sim::render::render_with`: one rayon task per row)
//! in a rayon pool of that many threads. The renders are interleaved over `--rounds` rounds
//! (every scene and thread count once per round); the table gives the median time per camera
//! sample, the camera samples per second on the last thread count, the scaling (time on the
//! first thread count over time on the last) and a checksum of the image's bits, which must be the
//! same on every thread count and round (the program stops otherwise: the threads do the same
//! arithmetic). The table comes under a line naming the command, the CPU (`model name` of
//! /proc/cpuinfo), its core count, the date and the load average after the runs (other processes
//! competing for the cores); `--out FILE` writes both to FILE too.
//!
//! ```sh
//! cargo run --release -p picomis-bench --example per_sample -- --out per_sample.md
//! ```
//!
//! Naming scenes (built-in names or scene files) measures those only, on one thread unless
//! `--threads` says otherwise: small enough to run under `valgrind --tool=callgrind` for
//! instructions per camera sample (the difference between two spp, over the camera samples
//! between them). Every integrator flag of `picomis-sim render` (`--mis`, `--sampler`,
//! `--light-selection`, `--quad-sampling`, `--preset`, ...) applies over each scene's block:
//!
//! ```sh
//! cargo build --release -p picomis-bench --example per_sample
//! valgrind --tool=callgrind target/release/examples/per_sample veach_mis --sampler sobol --spp 2 --rounds 1
//! ```

use std::fmt::Write as _;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::{Instant, SystemTime, UNIX_EPOCH};

use clap::Parser;
use indicatif::ProgressBar;
use picomis::{Choice, Estimate, Film, Preset, RenderSettings};
use picomis_format::IntegratorDesc;
use picomis_host::{HostScene, Renderer};
use picomis_sim::SimError;
use picomis_sim::scenes::{BUILTINS, Loaded};

/// Nanoseconds per camera sample on 1 and 2 threads, per scene.
#[derive(Debug, Parser)]
#[command(name = "per_sample")]
struct Args {
    /// Built-in scene names or picomis-scene/1 files (default: every built-in scene).
    scenes: Vec<String>,
    /// Camera samples per pixel.
    #[arg(long, default_value_t = 64, value_parser = clap::value_parser!(u32).range(1..))]
    spp: u32,
    /// Seed of the renders.
    #[arg(long, default_value_t = 0)]
    seed: u32,
    /// Thread counts, comma-separated (default: 1,2 for every built-in scene; 1 for named scenes,
    /// e.g. under callgrind).
    #[arg(short = 'j', long, value_name = "N,...", value_delimiter = ',',
          value_parser = clap::value_parser!(u32).range(1..=1024))]
    threads: Vec<u32>,
    /// Rounds: every scene on every thread count once per round; the table gives the medians.
    #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u32).range(1..))]
    rounds: u32,
    /// Also write the table to FILE, under a line naming the command, the CPU and the date.
    #[arg(short = 'o', long, value_name = "FILE")]
    out: Option<PathBuf>,
    /// The integrator: every key of a scene file's integrator block, as a flag (over each
    /// scene's block).
    #[command(flatten)]
    integrator: IntegratorDesc,
}

/// One scene to measure: its name, its host scene at its own film and its settings.
struct Case {
    name: String,
    scene: HostScene,
    settings: RenderSettings,
}

impl Case {
    fn new(loaded: &Loaded, args: &Args) -> Result<Self, SimError> {
        let name = loaded.file.name().to_string();
        let settings =
            picomis_sim::integrator::integrator(loaded, &args.integrator, None, args.spp, args.seed)?;
        let scene = loaded.build(loaded.file.film())?;
        Ok(Case { name, scene, settings })
    }

    /// Camera samples in one render.
    fn camera_samples(&self) -> f64 {
        f64::from(self.scene.film().pixels()) * f64::from(self.settings.spp())
    }

    /// The method, its parameter, the samples per technique and the keys away from the best
    /// preset.
    fn settings_text(&self) -> String {
        let s = &self.settings;
        let m = s.method();
        let mut text = m.name().to_string();
        if let Some(beta) = m.beta() {
            let _ = write!(text, " (beta {beta})");
        }
        if let Some(alpha) = m.alpha() {
            let _ = write!(text, " (alpha {alpha})");
        }
        let (n_light, n_bsdf) = s.technique_samples();
        let _ = write!(text, ", {n_light} light + {n_bsdf} BSDF");
        for (key, value) in IntegratorDesc::differences(s, Preset::Best) {
            let _ = write!(text, ", {key} {value}");
        }
        text
    }
}

/// A checksum of the bits of every pixel's radiance, in order.
fn checksum(pixels: &[Estimate]) -> u32 {
    pixels.iter().fold(0u32, |sum, e| {
        let r = e.radiance();
        sum.rotate_left(5) ^ r.x.to_bits() ^ r.y.to_bits() ^ r.z.to_bits()
    })
}

/// Renders `film` once with `renderer` in `pool`: seconds and the image's checksum.
fn time_render(pool: &rayon::ThreadPool, renderer: &dyn Renderer, film: Film) -> (f64, u32) {
    let hidden = ProgressBar::hidden();
    let start = Instant::now();
    let image = pool.install(|| picomis_sim::render::render_with(renderer, film, &hidden));
    let secs = start.elapsed().as_secs_f64();
    (secs, checksum(&image.pixels))
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 { v[n / 2] } else { (v[n / 2 - 1] + v[n / 2]) / 2.0 }
}

/// `threads` threads, in words.
fn threads_text(threads: u32) -> String {
    if threads == 1 { "1 thread".into() } else { format!("{threads} threads") }
}

/// The CPU's model name (the first `model name` of /proc/cpuinfo) and its logical cores.
fn cpu() -> String {
    let info = std::fs::read_to_string("/proc/cpuinfo").unwrap_or_default();
    let model = info
        .lines()
        .find_map(|l| l.strip_prefix("model name").and_then(|r| r.split_once(':')).map(|(_, m)| m.trim()))
        .unwrap_or("unknown CPU");
    let listed = info.lines().filter(|l| l.starts_with("processor")).count();
    let available = std::thread::available_parallelism().map_or(0, |n| n.get());
    let cores = if listed == 0 { available } else { listed };
    if available != cores && available != 0 {
        format!("{model}, {cores} logical cores ({available} available to this process)")
    } else {
        format!("{model}, {cores} logical cores")
    }
}

/// Today's date (UTC), `YYYY-MM-DD` (the civil calendar from days since 1970, H. Hinnant's
/// algorithm).
fn today() -> String {
    let days = SystemTime::now().duration_since(UNIX_EPOCH).map_or(0, |d| d.as_secs() / 86_400) as i64;
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!("{year:04}-{month:02}-{day:02}")
}

/// The line above the table: command, CPU, date, rounds, load average.
fn header(args: &Args) -> String {
    let argv: Vec<String> = std::env::args().skip(1).collect();
    let tail = if argv.is_empty() { String::new() } else { format!(" -- {}", argv.join(" ")) };
    format!(
        "`cargo run --release -p picomis-bench --example per_sample{tail}` on {}, {} (UTC); {}; load average at the end: {}.",
        cpu(),
        today(),
        match args.rounds {
            1 => "one round".to_string(),
            n => format!("median of {n} interleaved rounds"),
        },
        picomis_sim::study::load_average()
    )
}

/// The medians of one scene: nanoseconds per camera sample per thread count, and the checksum.
struct Row {
    ns: Vec<f64>,
    checksum: u32,
}

fn table(cases: &[Case], threads: &[u32], rows: &[Row]) -> String {
    let last = threads[threads.len() - 1];
    let mut head = "| scene | film | spp | integrator (keys away from the best preset) |".to_string();
    let mut rule = "|---|---|---:|---|".to_string();
    for &t in threads {
        let _ = write!(head, " ns/sample, {} |", threads_text(t));
        rule.push_str("---:|");
    }
    let _ = write!(head, " M samples/s, {} |", threads_text(last));
    rule.push_str("---:|");
    if threads.len() > 1 {
        let _ = write!(head, " scaling {}->{} |", threads[0], last);
        rule.push_str("---:|");
    }
    head.push_str(" checksum |");
    rule.push_str("---|");
    let mut out = format!("{head}\n{rule}\n");
    for (case, row) in cases.iter().zip(rows) {
        let film = case.scene.film();
        let _ = write!(
            out,
            "| {} | {}x{} | {} | {} |",
            case.name,
            film.width(),
            film.height(),
            case.settings.spp(),
            case.settings_text()
        );
        for ns in &row.ns {
            let _ = write!(out, " {ns:.1} |");
        }
        let last = row.ns[row.ns.len() - 1];
        let _ = write!(out, " {:.2} |", 1e3 / last);
        if threads.len() > 1 {
            let _ = write!(out, " {:.2}x |", row.ns[0] / last);
        }
        let _ = writeln!(out, " {:08x} |", row.checksum);
    }
    out
}

fn run(args: &Args) -> Result<(), SimError> {
    let loaded: Vec<Loaded> = if args.scenes.is_empty() {
        BUILTINS.iter().map(|b| picomis_sim::scenes::load(Some(b.name))).collect::<Result<_, _>>()?
    } else {
        args.scenes.iter().map(|s| picomis_sim::scenes::load(Some(s))).collect::<Result<_, _>>()?
    };
    let threads = match (&args.threads[..], args.scenes.is_empty()) {
        ([], true) => vec![1, 2],
        ([], false) => vec![1],
        (t, _) => t.to_vec(),
    };
    let pools = threads
        .iter()
        .map(|&t| rayon::ThreadPoolBuilder::new().num_threads(t as usize).build())
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| SimError::Usage(format!("--threads: {e}")))?;
    let cases = loaded.iter().map(|l| Case::new(l, args)).collect::<Result<Vec<_>, _>>()?;
    let renderers = cases
        .iter()
        .map(|c| picomis_host::renderer(&c.scene, &c.settings))
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| SimError::Usage(e.to_string()))?;
    // secs[case][thread count]: one time per round.
    let mut secs = vec![vec![Vec::new(); threads.len()]; cases.len()];
    let mut sums: Vec<Option<u32>> = vec![None; cases.len()];
    for round in 1..=args.rounds {
        for (i, (case, renderer)) in cases.iter().zip(&renderers).enumerate() {
            let samples = case.camera_samples();
            let mut line = format!("round {round}/{}: {}:", args.rounds, case.name);
            for (j, (pool, &t)) in pools.iter().zip(&threads).enumerate() {
                let (s, sum) = time_render(pool, &**renderer, case.scene.film());
                let first = *sums[i].get_or_insert(sum);
                assert_eq!(
                    sum,
                    first,
                    "{}: the image's bits differ on {} (round {round})",
                    case.name,
                    threads_text(t)
                );
                secs[i][j].push(s);
                let _ = write!(line, " {:.1} ns ({})", s * 1e9 / samples, threads_text(t));
            }
            eprintln!("{line}");
        }
    }
    let rows: Vec<Row> = cases
        .iter()
        .zip(secs)
        .zip(&sums)
        .map(|((case, per_thread), sum)| {
            let samples = case.camera_samples();
            let ns = per_thread.into_iter().map(|v| median(v) * 1e9 / samples).collect();
            Row { ns, checksum: sum.unwrap_or(0) }
        })
        .collect();
    let text = format!("{}\n\n{}", header(args), table(&cases, &threads, &rows));
    print!("{text}");
    if let Some(path) = &args.out {
        std::fs::write(path, &text).map_err(|e| SimError::Io(format!("{}: {e}", path.display())))?;
    }
    Ok(())
}

fn main() -> ExitCode {
    let args = Args::parse();
    match run(&args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(u8::try_from(e.exit_code()).unwrap_or(1))
        }
    }
}
