//! What the study writes: `results.csv`, `equal_time.csv`, per scene the charts
//! (`<scene>_error_time.{png,svg}`, `<scene>_error_spp.{png,svg}`) and the equal-time grid
//! (`<scene>_equal_time.png`), the region table and heat maps of the Veach scene
//! (`veach_regions.md`, `veach_regions.png`, `veach_regions_map.png`), and `summary.md` with
//! the efficiency tables.

use std::fmt::Write as _;
use std::path::Path;

use embedded_graphics_core::pixelcolor::RgbColor;
use picomis::{Method, SphereSampling, tone_map};

use super::chart::{self, COLORS, Chart, Point, Series};
use super::{Record, SceneStudy, StudyArgs, balance_index, grid, index_of, mean, study_methods};
use crate::SimError;
use crate::figure::weight_color;
use crate::output::{encode_png, write_atomic};
use crate::text::{Canvas, draw_text, text_width};

fn write(path: &Path, bytes: &[u8]) -> Result<(), SimError> {
    write_atomic(path, bytes).map_err(SimError::Io)
}

fn write_png(path: &Path, c: &Canvas) -> Result<(), SimError> {
    write(path, &encode_png(c.width, c.height, &c.bytes()).map_err(SimError::Io)?)
}

/// The rungs (spp) of the ladder, in order.
pub fn rungs(records: &[Record]) -> Vec<u32> {
    let mut v: Vec<u32> = records.iter().map(|r| r.spp).collect();
    v.sort_unstable();
    v.dedup();
    v
}

/// Mean, min and max of `f` over the seeds of method `mi` at `spp`.
pub fn over_seeds(records: &[Record], mi: usize, spp: u32, f: impl Fn(&Record) -> f64) -> (f64, f64, f64) {
    let vals: Vec<f64> = records.iter().filter(|r| r.method == mi && r.spp == spp).map(f).collect();
    let lo = vals.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = vals.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    (mean(vals.into_iter()), lo, hi)
}

/// The least-squares slope of ln(relative MSE) against ln(spp) of method `mi` over the rungs
/// (the error mean over seeds); NaN with fewer than two rungs of positive error.
pub fn convergence_slope(records: &[Record], mi: usize) -> f64 {
    let points: Vec<(f64, f64)> = rungs(records)
        .into_iter()
        .map(|spp| (f64::from(spp).ln(), over_seeds(records, mi, spp, |r| r.error.rel_mse).0))
        .filter(|(_, e)| *e > 0.0 && e.is_finite())
        .map(|(x, e)| (x, e.ln()))
        .collect();
    let n = points.len() as f64;
    let (mx, my) = (mean(points.iter().map(|p| p.0)), mean(points.iter().map(|p| p.1)));
    let sxy: f64 = points.iter().map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = points.iter().map(|(x, _)| (x - mx) * (x - mx)).sum();
    if n >= 2.0 && sxx > 0.0 { sxy / sxx } else { f64::NAN }
}

fn measured_on(args_include_emitted: bool) -> &'static str {
    if args_include_emitted { "full radiance" } else { "reflected light" }
}

/// Writes the charts, the equal-time grid and (if any) the region outputs of one scene.
pub fn write_scene(out: &Path, study: &SceneStudy, include_emitted: bool) -> Result<(), SimError> {
    let methods = study_methods();
    let what = measured_on(include_emitted);
    let rungs = rungs(&study.records);
    let top = rungs.last().copied().unwrap_or(1);
    let seeds = study.records.iter().filter(|r| r.method == balance_index() && r.spp == top).count();
    let time_desc = "seconds per image (all cores; fastest of the seeds)";
    for (kind, x_desc) in [("time", time_desc), ("spp", "samples per pixel")] {
        let series = methods
            .iter()
            .enumerate()
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
    write_png(&out.join(format!("{}_equal_time.png", study.name)), &grid::compose(study, what))?;
    if study.regions.is_some() {
        let stem = if study.name == "veach_mis" { "veach".to_string() } else { study.name.clone() };
        write(&out.join(format!("{stem}_regions.md")), region_table(study).as_bytes())?;
        write_png(&out.join(format!("{stem}_regions.png")), &heat_map(study))?;
        write_png(&out.join(format!("{stem}_regions_map.png")), &region_map(study))?;
    }
    Ok(())
}

/// `results.csv` (every ladder render) and `equal_time.csv`.
pub fn write_results(out: &Path, studies: &[SceneStudy]) -> Result<(), SimError> {
    let methods = study_methods();
    let mut csv = String::from(
        "scene,method,spp,seed,width,height,seconds,mse,rel_mse,efficiency,rel_efficiency,mse_mitsuba,rel_mse_mitsuba\n",
    );
    for s in studies {
        for r in &s.records {
            let (mm, rm) = r.mitsuba.map_or((String::new(), String::new()), |m| {
                (format!("{:e}", m.mse), format!("{:e}", m.rel_mse))
            });
            let _ = writeln!(
                csv,
                "{},{},{},{},{},{},{:.6},{:e},{:e},{:e},{:e},{mm},{rm}",
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
    let top = rungs(&study.records).last().copied().unwrap_or(1);
    let pixels = f64::from(study.width) * f64::from(study.height);
    (0..study_methods().len())
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
    let methods = study_methods();
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
         log spp over the ladder: -1 for independent samples, steeper where stratification helps.\n"
    );
    for s in studies {
        let eff = efficiencies(s);
        let b = eff[balance_index()];
        let top = rungs(&s.records).last().copied().unwrap_or(1);
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
            "| method | ms per image | camera samples/s | MSE | rel. MSE | rel. MSE slope vs spp | efficiency vs balance (rel. MSE) | efficiency vs balance (MSE) | equal-time spp | equal-time rel. MSE |"
        );
        let _ = writeln!(md, "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
        for (mi, m) in methods.iter().enumerate() {
            let e = eff[mi];
            let eq = s.equal_time.iter().find(|q| q.method == mi);
            let _ = writeln!(
                md,
                "| {} | {:.1} | {:.2} M | {:.3e} | {:.3e} | {:.2} | {} | {} | {} | {} |",
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
            for (mi, meth) in methods.iter().enumerate() {
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
fn ratio(v: f64) -> String {
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

fn fmt_alpha(a: f32) -> String {
    format!("{a}")
}

/// Mean over seeds of the relative MSE of method `mi` in region `k` (its light alone).
fn region_error(study: &SceneStudy, mi: usize, k: usize) -> f64 {
    mean(study.region_study.records.iter().filter(|r| r.method == mi && r.region == k).map(|r| r.rel_mse))
}

/// The markdown table of the error per region.
fn region_table(study: &SceneStudy) -> String {
    let Some(map) = &study.regions else { return String::new() };
    let methods = study_methods();
    let top = rungs(&study.records).last().copied().unwrap_or(1);
    let rs = &study.region_study;
    let seeds = rs.records.iter().filter(|r| r.method == balance_index() && r.region == 0).count();
    let region = |mi: usize, k: usize| region_error(study, mi, k);
    let cost: Vec<f64> = (0..methods.len()).map(|mi| super::cost_per_spp(&study.records, mi, top)).collect();
    let bsdf = index_of(Method::BsdfOnly, SphereSampling::Cone);
    let light = index_of(Method::LightOnly, SphereSampling::Cone);
    let balance = balance_index();
    let mut md = format!(
        "# {}: error per plate x light region\n\n\
         Each glossy plate is cut into one region per light: a pixel whose camera ray hits a plate belongs to the \
         light whose glint (the light's centre mirrored in the plate, seen from the camera) is nearest \
         (`veach_regions_map.png`). In each region the error is that of the region's own light: the light is \
         rendered alone (every other emitter at zero radiance, light selection and random numbers unchanged, so \
         the render is exactly this light's part of the full render) and compared with a reference of that light \
         alone. Relative MSE of the reflected light at {} spp, mean of {seeds} seed(s), {}x{} pixels; plates from \
         smooth (GGX alpha {}) to rough ({}), lights from small (r {}) to big (r {}). References: balance \
         heuristic, {} spp, own noise (rel. MSE over the whole image) {}.\n\n",
        study.name,
        rs.spp,
        study.width,
        study.height,
        fmt_alpha(map.plates[0]),
        fmt_alpha(*map.plates.last().unwrap_or(&0.0)),
        map.lights[0],
        map.lights.last().unwrap_or(&0.0),
        rs.references.first().map_or(0, |r| r.spp),
        rs.references.iter().map(|r| format!("{:.1e}", r.noise.rel_mse)).collect::<Vec<_>>().join(", "),
    );
    let _ = write!(md, "| plate alpha | light r | pixels |");
    for m in &methods {
        let _ = write!(md, " {} |", m.title);
    }
    let _ = writeln!(md, " worse single technique | balance vs better single |");
    let _ = write!(md, "|---:|---:|---:|");
    for _ in &methods {
        let _ = write!(md, "---:|");
    }
    let _ = writeln!(md, "---|---:|");
    for (k, r) in map.regions.iter().enumerate() {
        let _ = write!(md, "| {} | {} | {} |", fmt_alpha(map.plates[r.plate]), map.lights[r.light], r.pixels);
        for mi in 0..methods.len() {
            let _ = write!(md, " {:.2e} |", region(mi, k));
        }
        let (b, l) = (region(bsdf, k), region(light, k));
        let worse =
            if b > l { format!("BSDF ({:.0}x light)", b / l) } else { format!("light ({:.0}x BSDF)", l / b) };
        let _ = writeln!(md, " {worse} | {} |", ratio(region(balance, k) / b.min(l)));
    }
    let _ = writeln!(
        md,
        "\n\"balance vs better single\" is the balance heuristic's relative MSE over that of the better of BSDF \
         sampling and light sampling (cone) in the region, at equal spp (below 1: MIS beats both).\n\n\
         At equal time (relative MSE x seconds per spp, relative to balance; above 1: worse than balance):\n"
    );
    let _ = write!(md, "| plate alpha | light r |");
    for m in &methods {
        let _ = write!(md, " {} |", m.title);
    }
    let _ = write!(md, "\n|---:|---:|");
    for _ in &methods {
        let _ = write!(md, "---:|");
    }
    md.push('\n');
    for (k, r) in map.regions.iter().enumerate() {
        let _ = write!(md, "| {} | {} |", fmt_alpha(map.plates[r.plate]), map.lights[r.light]);
        let base = region(balance, k) * cost[balance];
        for (mi, c) in cost.iter().enumerate() {
            let _ = write!(md, " {} |", ratio(region(mi, k) * c / base));
        }
        md.push('\n');
    }
    let _ = writeln!(md, "\nSeconds per sample per pixel (whole image, all cores):\n");
    for (mi, m) in methods.iter().enumerate() {
        let _ = writeln!(md, "- {}: {:.2} ms", m.title, cost[mi] * 1e3);
    }
    md
}

/// Heat maps of log10 relative MSE per region, one 4 x 4 (plates x lights) panel per method.
fn heat_map(study: &SceneStudy) -> Canvas {
    let Some(map) = &study.regions else { return Canvas::new(1, 1, [255; 3]) };
    let methods = study_methods();
    let top = study.region_study.spp;
    let values: Vec<Vec<f64>> = (0..methods.len())
        .map(|mi| (0..map.regions.len()).map(|k| region_error(study, mi, k)).collect())
        .collect();
    let logs = values.iter().flatten().filter(|v| v.is_finite() && **v > 0.0).map(|v| v.log10());
    let (lo, hi) = logs.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| (a.min(v), b.max(v)));
    let (lo, hi) = if lo < hi { (lo.floor(), hi.ceil()) } else { (lo - 1.0, lo + 1.0) };
    let (np, nl) = (map.plates.len() as u32, map.lights.len() as u32);
    let (cw, ch, left, head, title_h) = (70u32, 30u32, 76u32, 44u32, 64u32);
    let pw = left + nl * cw;
    let ph = head + np * ch;
    let cols = 4u32;
    let rows = (methods.len() as u32).div_ceil(cols);
    let margin = 16u32;
    let width = cols * pw + (cols + 1) * margin;
    let legend_h = 60u32;
    let height = title_h + rows * (ph + margin) + legend_h;
    let mut c = Canvas::new(width, height, [255; 3]);
    let ink = [20, 20, 20];
    let title = format!(
        "{}: relative MSE per plate x light region, its light alone, at {top} spp (log colour scale)",
        study.name
    );
    draw_text(&mut c, margin as f32, 10.0, 20.0, &title, ink);
    draw_text(
        &mut c,
        margin as f32,
        36.0,
        14.0,
        "rows: plates, smooth (top) to rough; columns: lights, small (left) to big",
        [80, 80, 80],
    );
    for (mi, m) in methods.iter().enumerate() {
        let (px, py) =
            (margin + (mi as u32 % cols) * (pw + margin), title_h + (mi as u32 / cols) * (ph + margin));
        draw_text(&mut c, px as f32, py as f32, 16.0, m.title, ink);
        for l in 0..nl {
            let label = format!("r {}", map.lights[l as usize]);
            draw_text(&mut c, (px + left + l * cw + 4) as f32, (py + 22) as f32, 12.0, &label, [80, 80, 80]);
        }
        for p in 0..np {
            let label = format!("\u{3b1} {}", map.plates[p as usize]);
            draw_text(&mut c, px as f32, (py + head + p * ch + 8) as f32, 12.0, &label, [80, 80, 80]);
            for l in 0..nl {
                let (x, y) = (px + left + l * cw, py + head + p * ch);
                let Some(k) = map.index(p as usize, l as usize) else {
                    c.fill(i64::from(x), i64::from(y), cw - 2, ch - 2, [230, 230, 230]);
                    continue;
                };
                let v = values[mi][k];
                let t = if v > 0.0 && v.is_finite() { ((v.log10() - lo) / (hi - lo)) as f32 } else { 0.0 };
                let color = weight_color(t);
                c.fill(i64::from(x), i64::from(y), cw - 2, ch - 2, color);
                let text = format!("{v:.1e}");
                let light_bg =
                    0.3 * f32::from(color[0]) + 0.6 * f32::from(color[1]) + 0.1 * f32::from(color[2]) > 140.0;
                let fg = if light_bg { [0, 0, 0] } else { [255, 255, 255] };
                let tw = text_width(&text, 12.0);
                draw_text(&mut c, x as f32 + (cw as f32 - 2.0 - tw) / 2.0, (y + 8) as f32, 12.0, &text, fg);
            }
        }
    }
    // Colour bar.
    let (bx, by, bw, bh) = (margin + 120, height - legend_h + 14, 400u32, 16u32);
    draw_text(&mut c, margin as f32, by as f32, 14.0, "relative MSE", ink);
    for i in 0..bw {
        c.fill(i64::from(bx + i), i64::from(by), 1, bh, weight_color(i as f32 / (bw - 1) as f32));
    }
    for d in 0..=((hi - lo) as i32) {
        let x = bx as f32 + d as f32 / (hi - lo) as f32 * (bw - 1) as f32;
        draw_text(&mut c, x - 12.0, (by + bh + 3) as f32, 12.0, &format!("1e{}", lo as i32 + d), ink);
    }
    c
}

/// The reference with each region tinted and labelled "plate.light" (1-based).
fn region_map(study: &SceneStudy) -> Canvas {
    let Some(map) = &study.regions else { return Canvas::new(1, 1, [255; 3]) };
    let (w, h) = (study.width, study.height);
    let k = 900u32.div_ceil(w).max(1);
    let title_h = 30;
    let mut c = Canvas::new(w * k, h * k + title_h, [255; 3]);
    let tints = [[230u8, 97, 1], [94, 60, 153], [27, 158, 119], [33, 102, 172], [200, 30, 120]];
    for y in 0..h * k {
        for x in 0..w * k {
            let i = ((y / k) * w + x / k) as usize;
            let t = tone_map(study.reference.full[i]);
            let mut px = [t.r(), t.g(), t.b()];
            if let Some(r) = map.pixel[i] {
                let tint = tints[map.regions[usize::from(r)].light % tints.len()];
                let a = if map.regions[usize::from(r)].plate % 2 == 0 { 0.45 } else { 0.3 };
                for (d, s) in px.iter_mut().zip(tint) {
                    *d = (f32::from(*d) * (1.0 - a) + f32::from(s) * a) as u8;
                }
            }
            c.put(i64::from(x), i64::from(y + title_h), px);
        }
    }
    draw_text(
        &mut c,
        8.0,
        6.0,
        16.0,
        &format!("{}: regions \"plate.light\" (plates smooth to rough, lights small to big)", study.name),
        [20, 20, 20],
    );
    for (n, r) in map.regions.iter().enumerate() {
        // Label at the region's top left, clear of the glint.
        let (mut x0, mut y0, mut cnt) = (f64::INFINITY, f64::INFINITY, 0.0f64);
        for (i, p) in map.pixel.iter().enumerate() {
            if *p == u16::try_from(n).ok() {
                x0 = x0.min((i as u32 % w) as f64);
                y0 = y0.min((i as u32 / w) as f64);
                cnt += 1.0;
            }
        }
        if cnt > 0.0 {
            let label = format!("{}.{}", r.plate + 1, r.light + 1);
            let tw0 = f64::from(text_width(&label, 15.0));
            let x = (x0 + 1.5) * f64::from(k) + tw0 / 2.0;
            let y = (y0 + 1.5) * f64::from(k) + f64::from(title_h) + 9.0;
            let tw = text_width(&label, 15.0);
            c.fill(x as i64 - tw as i64 / 2 - 2, y as i64 - 9, tw as u32 + 4, 18, [255, 255, 255]);
            draw_text(&mut c, x as f32 - tw / 2.0, y as f32 - 9.0, 15.0, &label, [0, 0, 0]);
        }
    }
    c
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::study::metrics::ErrorStats;

    #[test]
    fn the_convergence_slope_is_that_of_the_fitted_power_law() {
        let record = |method, spp: u32, seed, rel_mse| Record {
            method,
            spp,
            seed,
            seconds: 1.0,
            error: ErrorStats { mse: rel_mse, rel_mse },
            mitsuba: None,
        };
        let mut records = Vec::new();
        for spp in [1u32, 2, 4, 8, 16] {
            // Method 0: 1 / spp^1.5 on average over two seeds; method 1: one rung only.
            let e = 0.3 * f64::from(spp).powf(-1.5);
            records.push(record(0, spp, 1, 0.5 * e));
            records.push(record(0, spp, 2, 1.5 * e));
        }
        records.push(record(1, 4, 1, 0.1));
        assert!((convergence_slope(&records, 0) + 1.5).abs() < 1e-9, "{}", convergence_slope(&records, 0));
        assert!(convergence_slope(&records, 1).is_nan());
    }
}
