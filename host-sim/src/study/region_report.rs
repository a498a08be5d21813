//! The region outputs of the Veach scene (any scene with plate x light regions): the table of
//! the error per region (`veach_regions.md`), its heat maps, one panel per method
//! (`veach_regions.png`), and the reference with the regions tinted and labelled
//! (`veach_regions_map.png`).

use std::fmt::Write as _;
use std::path::Path;

use super::methods::methods;
use embedded_graphics_core::pixelcolor::RgbColor;
use picomis::{Method, SphereSampling, tone_map};

use super::report::{ratio, write, write_png};
use super::results::{SceneStudy, balance_index, cost_per_spp, index_of, mean, top_rung};
use crate::SimError;
use crate::figure::weight_color;
use crate::text::{Canvas, draw_text, text_width};

/// Writes the region outputs of `study` into `out` (nothing when it has no regions).
pub fn write_regions(out: &Path, study: &SceneStudy) -> Result<(), SimError> {
    if study.regions.is_none() {
        return Ok(());
    }
    let stem = if study.name == "veach_mis" { "veach".to_string() } else { study.name.clone() };
    write(&out.join(format!("{stem}_regions.md")), region_table(study).as_bytes())?;
    write_png(&out.join(format!("{stem}_regions.png")), &heat_map(study))?;
    write_png(&out.join(format!("{stem}_regions_map.png")), &region_map(study))
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
    let methods = methods();
    let top = top_rung(&study.records);
    let rs = &study.region_study;
    let seeds = rs.records.iter().filter(|r| r.method == balance_index() && r.region == 0).count();
    let region = |mi: usize, k: usize| region_error(study, mi, k);
    let cost: Vec<f64> = (0..methods.len()).map(|mi| cost_per_spp(&study.records, mi, top)).collect();
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
    let methods = methods();
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
