//! The equal-time image grid: every method rendered for the same time budget (its spp chosen from
//! its measured cost), each tile labelled with the method, spp, seconds and relative MSE, next to
//! the reference.

use super::methods::methods;
use embedded_graphics_core::pixelcolor::RgbColor;
use picomis::{Rgb, tone_map};

use super::results::SceneStudy;
use crate::text::{Canvas, draw_text};

const BACKGROUND: [u8; 3] = [255, 255, 255];
const INK: [u8; 3] = [20, 20, 20];
const MUTED: [u8; 3] = [80, 80, 80];
const MARGIN: u32 = 12;
const LABEL: u32 = 42;
const COLUMNS: u32 = 3;
const MIN_TILE_WIDTH: u32 = 300;

fn tile(image: &[Rgb], w: u32, h: u32, k: u32) -> Vec<[u8; 3]> {
    let mut out = Vec::with_capacity((w * h * k * k) as usize);
    for y in 0..h * k {
        for x in 0..w * k {
            let t = tone_map(image[((y / k) * w + x / k) as usize]);
            out.push([t.r(), t.g(), t.b()]);
        }
    }
    out
}

/// The grid of `study`'s equal-time renders and its reference.
pub fn compose(study: &SceneStudy, measured_on: &str) -> Canvas {
    let (w, h) = (study.width, study.height);
    let k = MIN_TILE_WIDTH.div_ceil(w).max(1);
    let (tw, th) = (w * k, h * k);
    let tiles = study.equal_time.len() as u32 + 1;
    let rows = tiles.div_ceil(COLUMNS);
    let title_h = 60;
    let width = COLUMNS * tw + (COLUMNS + 1) * MARGIN;
    let height = title_h + rows * (LABEL + th + MARGIN);
    let mut canvas = Canvas::new(width, height, BACKGROUND);
    let title =
        format!("{}: equal time, {:.3} s per image (balance at the top rung)", study.name, study.budget);
    draw_text(&mut canvas, MARGIN as f32, 10.0, 20.0, &title, INK);
    let sub = format!("{w}x{h}; rel. MSE of the {measured_on} against the reference (bottom right)");
    draw_text(&mut canvas, MARGIN as f32, 36.0, 14.0, &sub, MUTED);
    let methods = methods();
    let mut place = |i: u32, name: &str, detail: &str, image: &[Rgb]| {
        let (col, row) = (i % COLUMNS, i / COLUMNS);
        let x = MARGIN + col * (tw + MARGIN);
        let y = title_h + row * (LABEL + th + MARGIN);
        draw_text(&mut canvas, x as f32, y as f32, 17.0, name, INK);
        draw_text(&mut canvas, x as f32, y as f32 + 21.0, 13.5, detail, MUTED);
        canvas.blit(i64::from(x), i64::from(y + LABEL), tw, th, &tile(image, w, h, k));
    };
    for (i, e) in study.equal_time.iter().enumerate() {
        let detail = format!("{} spp, {:.3} s, rel. MSE {:.3e}", e.spp, e.seconds, e.error.rel_mse);
        place(i as u32, methods[e.method].title, &detail, &e.image);
    }
    let r = &study.reference;
    place(tiles - 1, "reference", &format!("balance, cone sampling, {} spp", r.spp), &r.full);
    canvas
}
