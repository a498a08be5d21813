//! What the study writes besides the region outputs (`region_report.rs`): `results.csv`,
//! `equal_time.csv`, per scene the charts (`<scene>_error_time.{png,svg}`,
//! `<scene>_error_spp.{png,svg}`) and the equal-time grid (`<scene>_equal_time.png`), and
//! `summary.md` with the efficiency tables.

use std::fmt::Write as _;
use std::path::Path;

use super::methods::methods;

use super::args::StudyArgs;
use super::chart::{self, COLORS, Chart, Point, Series};
use super::grid;
use super::results::{SceneStudy, balance_index, convergence_slope, over_seeds, rungs, top_rung};
use crate::SimError;
use crate::output::{encode_png, write_atomic};
use crate::text::Canvas;

/// Writes `bytes` to `path` (atomically).
pub fn write(path: &Path, bytes: &[u8]) -> Result<(), SimError> {
    write_atomic(path, bytes).map_err(SimError::Io)
}

/// Writes `c` to `path` as PNG.
pub fn write_png(path: &Path, c: &Canvas) -> Result<(), SimError> {
    write(path, &encode_png(c.width, c.height, &c.bytes()).map_err(SimError::Io)?)
}

fn measured_on(args_include_emitted: bool) -> &'static str {
    if args_include_emitted { "full radiance" } else { "reflected light" }
}

/// Writes the charts and the equal-time grid of one scene.
pub fn write_scene(out: &Path, study: &SceneStudy, include_emitted: bool) -> Result<(), SimError> {
    let methods = methods();
    let what = measured_on(include_emitted);
    let rungs = rungs(&study.records);
    let top = rungs.last().copied().unwrap_or(1);
    let seeds = study.records.iter().filter(|r| r.method == balance_index() && r.spp == top).count();
    let time_desc = "seconds per image (all cores; fastest of the seeds)";
    for (kind, x_desc) in [("time", time_desc), ("spp", "samples per pixel")] {
        let series = methods
            .iter()
            .enumerate()
            .filter(|(mi, _)| study.rejection(*mi).is_none())
            .map(|(mi, m)| Series {
                label: match kind {
                    "spp" => format!("{} (slope {:.2})", m.title, convergence_slope(&study.records, mi)),
                    _ => m.title.to_string(),
                },
                color: COLORS[mi % COLORS.len()],
                dashed: mi < 3,
                points: rungs
                    .iter()
                    .map(|&spp| {
                        let (y, lo, hi) = over_seeds(&study.records, mi, spp, |r| r.error.rel_mse);
                        let x = if kind == "time" {
                            over_seeds(&study.records, mi, spp, |r| r.seconds).1
                        } else {
                            f64::from(spp)
                        };
                        Point { x, y, lo, hi }
                    })
                    .collect(),
            })
            .collect();
        let c = Chart {
            title: format!(
                "{}: error against {kind}, {}x{}, {seeds} seed{} (band: min-max)",
                study.name,
                study.width,
                study.height,
                if seeds == 1 { "" } else { "s" }
            ),
            x_desc: x_desc.to_string(),
            y_desc: format!("relative MSE of the {what}"),
            series,
            floor: Some(("noise of the reference".to_string(), study.reference.noise.rel_mse)),
        };
        let (png, svg) = chart::render(&c)?;
        write(&out.join(format!("{}_error_{kind}.png", study.name)), &png)?;
        write(&out.join(format!("{}_error_{kind}.svg", study.name)), svg.as_bytes())?;
    }
    write_png(&out.join(format!("{}_equal_time.png", study.name)), &grid::compose(study, what))
}

/// A CSV field: quoted, its quotes doubled.
fn csv_field(s: &str) -> String {
    format!("\"{}\"", s.replace('"', "\"\""))
}

/// An optional error's MSE and relative MSE as two CSV fields (both empty without it).
fn error_fields(e: Option<super::metrics::ErrorStats>) -> (String, String) {
    e.map_or((String::new(), String::new()), |m| (format!("{:e}", m.mse), format!("{:e}", m.rel_mse)))
}

/// `results.csv` (every ladder render, and one row per rejected method with only its reason) and
/// `equal_time.csv`.
pub fn write_results(out: &Path, studies: &[SceneStudy]) -> Result<(), SimError> {
    let methods = methods();
    let mut csv = String::from(
        "scene,method,spp,seed,width,height,seconds,mse,rel_mse,efficiency,rel_efficiency,mse_mitsuba,rel_mse_mitsuba,mse_vs_f32,rel_mse_vs_f32,rejected\n",
    );
    for s in studies {
        for r in &s.records {
            let (mm, rm) = error_fields(r.mitsuba);
            let (mf, rf) = error_fields(r.vs_f32);
            let _ = writeln!(
                csv,
                "{},{},{},{},{},{},{:.6},{:e},{:e},{:e},{:e},{mm},{rm},{mf},{rf},",
                s.name,
                methods[r.method].label,
                r.spp,
                r.seed,
                s.width,
                s.height,
                r.seconds,
                r.error.mse,
                r.error.rel_mse,
                1.0 / (r.error.mse * r.seconds),
                1.0 / (r.error.rel_mse * r.seconds),
            );
        }
        for r in &s.rejected {
            let _ = writeln!(
                csv,
                "{},{},,,{},{},,,,,,,,,,{}",
                s.name,
                methods[r.method].label,
                s.width,
                s.height,
                csv_field(&r.reason)
            );
        }
    }
    write(&out.join("results.csv"), csv.as_bytes())?;
    let mut eq = String::from("scene,method,spp,seconds,mse,rel_mse,budget_seconds\n");
    for s in studies {
        for e in &s.equal_time {
            let _ = writeln!(
                eq,
                "{},{},{},{:.6},{:e},{:e},{:.6}",
                s.name, methods[e.method].label, e.spp, e.seconds, e.error.mse, e.error.rel_mse, s.budget
            );
        }
    }
    write(&out.join("equal_time.csv"), eq.as_bytes())
}

/// Efficiency numbers of one method at the top rung.
#[derive(Clone, Copy, Debug)]
pub struct Efficiency {
    /// Seconds per image at the top rung (the fastest of the seeds' renders).
    pub seconds: f64,
    /// Camera samples per second.
    pub samples_per_second: f64,
    /// Mean MSE.
    pub mse: f64,
    /// Mean relative MSE.
    pub rel_mse: f64,
    /// 1 / (MSE x seconds).
    pub efficiency: f64,
    /// 1 / (relative MSE x seconds).
    pub rel_efficiency: f64,
}

/// The efficiency of every method at the top rung of `study`.
pub fn efficiencies(study: &SceneStudy) -> Vec<Efficiency> {
    let top = top_rung(&study.records);
    let pixels = f64::from(study.width) * f64::from(study.height);
    (0..methods().len())
        .map(|mi| {
            // The fastest seed's render: robust against other processes on the machine.
            let seconds = over_seeds(&study.records, mi, top, |r| r.seconds).1;
            let mse = over_seeds(&study.records, mi, top, |r| r.error.mse).0;
            let rel_mse = over_seeds(&study.records, mi, top, |r| r.error.rel_mse).0;
            Efficiency {
                seconds,
                samples_per_second: pixels * f64::from(top) / seconds,
                mse,
                rel_mse,
                efficiency: 1.0 / (mse * seconds),
                rel_efficiency: 1.0 / (rel_mse * seconds),
            }
        })
        .collect()
}

/// The 1, 5 and 15 minute load averages (other processes competing for the cores).
pub fn load_average() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .map(|l| l.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
        .unwrap_or_else(|_| "unknown".into())
}

fn cpu_model() -> String {
    std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|t| {
            t.lines()
                .find_map(|l| l.strip_prefix("model name")?.split(':').nth(1).map(|s| s.trim().to_string()))
        })
        .unwrap_or_else(|| "unknown CPU".into())
}

/// `summary.md`: the machine, the command, and per scene the efficiency table.
pub fn write_summary(
    out: &Path,
    studies: &[SceneStudy],
    args: &StudyArgs,
    ref_spp: u32,
    seconds: f64,
) -> Result<(), SimError> {
    let methods = methods();
    let what = measured_on(args.include_emitted);
    let mut md = String::from("# Speed against accuracy: study summary\n\n");
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let command: Vec<String> = std::env::args().skip(1).collect();
    let _ = writeln!(md, "- Command: `picomis-sim {}`", command.join(" "));
    let _ = writeln!(
        md,
        "- Machine: {cores} cores available, {} threads used, {}; load average at the end: {}",
        rayon::current_num_threads(),
        cpu_model(),
        load_average()
    );
    let _ = writeln!(
        md,
        "- Ladder: spp up to {}, {} seed(s); reference: balance heuristic, cone sampling, at least {ref_spp} spp; \
         errors of the {what}; whole study {seconds:.0} s.",
        args.max_spp, args.seeds
    );
    let _ = writeln!(
        md,
        "- Efficiency = 1 / (error x seconds) at the top rung (error: mean over seeds; seconds: the fastest \
         seed's render, robust against other processes), relative to the balance heuristic: 2.0 means half \
         the time for the same error. The slope is that of a least-squares fit of log relative MSE against \
         log spp over the ladder: -1 for independent samples, steeper where stratification helps. \
         \"rel. MSE vs f32\": for a method whose ray queries are not f32, its error against the f32 \
         method of the same options (power heuristic), rendered with the same seed and spp (the same \
         random numbers), mean over seeds at the top rung; a scene that its arithmetic cannot \
         represent shows the method as rejected, with the reason.\n"
    );
    for s in studies {
        let eff = efficiencies(s);
        let b = eff[balance_index()];
        let top = top_rung(&s.records);
        let _ = writeln!(
            md,
            "## {}\n\n{}x{}, top rung {top} spp, reference {} spp (its own noise: rel. MSE {:.2e}){}.\n",
            s.name,
            s.width,
            s.height,
            s.reference.spp,
            s.reference.noise.rel_mse,
            if s.reference.cached { ", cached" } else { "" }
        );
        let _ = writeln!(
            md,
            "| method | ms per image | camera samples/s | MSE | rel. MSE | rel. MSE slope vs spp | efficiency vs balance (rel. MSE) | efficiency vs balance (MSE) | equal-time spp | equal-time rel. MSE | rel. MSE vs f32 |"
        );
        let _ = writeln!(md, "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
        for (mi, m) in methods.iter().enumerate() {
            if let Some(reason) = s.rejection(mi) {
                let _ = writeln!(
                    md,
                    "| {} | rejected: {} | | | | | | | | | |",
                    m.title,
                    reason.replace('|', "\\|")
                );
                continue;
            }
            let e = eff[mi];
            let vs_f32 = over_seeds(&s.records, mi, top, |r| r.vs_f32.map_or(f64::NAN, |v| v.rel_mse)).0;
            let eq = s.equal_time.iter().find(|q| q.method == mi);
            let _ = writeln!(
                md,
                "| {} | {:.1} | {:.2} M | {:.3e} | {:.3e} | {:.2} | {} | {} | {} | {} | {} |",
                m.title,
                e.seconds * 1e3,
                e.samples_per_second / 1e6,
                e.mse,
                e.rel_mse,
                convergence_slope(&s.records, mi),
                ratio(e.rel_efficiency / b.rel_efficiency),
                ratio(e.efficiency / b.efficiency),
                eq.map_or(String::new(), |q| q.spp.to_string()),
                eq.map_or(String::new(), |q| format!("{:.3e}", q.error.rel_mse)),
                if vs_f32.is_nan() { String::new() } else { format!("{vs_f32:.3e}") },
            );
        }
        if let Some(m) = &s.reference_vs_mitsuba {
            let _ = writeln!(
                md,
                "\nAgainst the Mitsuba 3 reference (full radiance, box-filtered to {}x{}): our converged reference \
                 differs by rel. MSE {:.3e} (MSE {:.3e}); at the top rung the methods reach:\n",
                s.width, s.height, m.rel_mse, m.mse
            );
            let _ = writeln!(md, "| method | rel. MSE vs Mitsuba | MSE vs Mitsuba |\n|---|---:|---:|");
            for (mi, meth) in methods.iter().enumerate().filter(|(mi, _)| s.rejection(*mi).is_none()) {
                let rel = over_seeds(&s.records, mi, top, |r| r.mitsuba.map_or(f64::NAN, |m| m.rel_mse)).0;
                let mse = over_seeds(&s.records, mi, top, |r| r.mitsuba.map_or(f64::NAN, |m| m.mse)).0;
                let _ = writeln!(md, "| {} | {rel:.3e} | {mse:.3e} |", meth.title);
            }
        } else if let Some(note) = &s.mitsuba_note {
            let _ = writeln!(md, "\nNo comparison with the Mitsuba 3 reference: {note}.");
        }
        md.push('\n');
    }
    write(&out.join("summary.md"), md.as_bytes())
}

/// A ratio with about three significant digits (one for ratios below 0.1, which only say "far
/// worse").
pub fn ratio(v: f64) -> String {
    if v < 0.095 {
        format!("{v:.0e}")
    } else if v >= 100.0 {
        format!("{v:.0}")
    } else if v >= 10.0 {
        format!("{v:.1}")
    } else {
        format!("{v:.2}")
    }
}
