//! Instructions per camera sample, counted with SysTick under `qemu -icount shift=0`.
//!
//! SysTick runs on the core clock, and with `-icount shift=0` every instruction takes 1 ns of
//! virtual time, so ticks = instructions * f_cpu / 1 GHz. Rather than trusting f_cpu, a loop of
//! known length calibrates ticks per instruction. Each figure renders the whole film
//! `MEASURE_REPEAT` times and subtracts the same loop with an empty body.

use core::hint::black_box;

use crate::board::{Fb, IntegratorT, config};
use crate::clock;
use embedded_graphics::prelude::*;
use embedded_graphics::primitives::Rectangle;

use crate::arch::{SPIN_INSTRUCTIONS, spin};

/// Iterations of the calibration loop (`SPIN_INSTRUCTIONS` instructions each).
const CALIBRATION_LOOPS: u32 = 8_000_000;

fn time(f: impl FnOnce()) -> u64 {
    let t0 = clock::ticks();
    f();
    clock::ticks() - t0
}

/// Ticks to instructions with the calibration (instructions, ticks).
fn instructions(ticks: u64, cal: (u64, u64)) -> u64 {
    (ticks * cal.0 + cal.1 / 2) / cal.1
}

/// Prints `num / den` with one decimal.
fn per(what: &str, num: u64, den: u64) {
    let tenths = (num * 10 + den / 2) / den.max(1);
    info!("measure: {} {}.{} instructions ({} / {})", what, tenths / 10, tenths % 10, num, den);
}

pub fn run(integrator: &IntegratorT<'_>, fb: &mut Fb) {
    let (scene, settings) = (integrator.scene(), integrator.settings());
    let cal_ticks = time(|| spin(black_box(CALIBRATION_LOOPS)));
    let cal = (SPIN_INSTRUCTIONS * u64::from(CALIBRATION_LOOPS), cal_ticks.max(1));
    info!(
        "measure: calibration {} instructions = {} ticks (f_cpu ~ {} kHz)",
        cal.0,
        cal.1,
        cal.1 * 1_000_000 / cal.0
    );
    let film = scene.film();
    let (w, h, spp, repeat) = (film.width(), film.height(), settings.spp(), config::MEASURE_REPEAT);
    let samples = u64::from(w * h * spp) * u64::from(repeat);

    // Camera samples alone (trace of camera ray, light sample, BSDF sample, MIS weights).
    let base = time(|| {
        for _ in 0..repeat {
            for y in 0..h {
                for x in 0..w {
                    for s in 0..spp {
                        black_box((x, y, s));
                    }
                }
            }
        }
    });
    let full = time(|| {
        for _ in 0..repeat {
            for y in 0..h {
                for x in 0..w {
                    for s in 0..spp {
                        black_box(integrator.camera_sample(x, y, s));
                    }
                }
            }
        }
    });
    let sample_instr = instructions(full.saturating_sub(base), cal);
    info!("measure: film {}x{}, {} spp, {} repeats: {} camera samples", w, h, spp, repeat, samples);
    per("camera_sample: per camera sample", sample_instr, samples);

    // Whole tiles: camera samples plus averaging, tone mapping and the Rgb565 store.
    let area = picomis::film_rect(film);
    let empty = Rectangle::new(Point::zero(), Size::zero());
    let base = time(|| {
        for _ in 0..repeat {
            let _ = integrator.render_tile(black_box(&empty), fb);
        }
    });
    let full = time(|| {
        for _ in 0..repeat {
            let _ = integrator.render_tile(black_box(&area), fb);
        }
    });
    let tile_instr = instructions(full.saturating_sub(base), cal);
    per("render_tile: per camera sample", tile_instr, samples);
    let pixels = u64::from(w * h) * u64::from(repeat);
    let overhead = tile_instr.saturating_sub(sample_instr);
    per("render_tile: per-pixel overhead (average, tone map, store)", overhead, pixels);
}
