//! Renders a small scene and prints it as ASCII art: each pixel's HDR estimate from
//! `Integrator::render_pixel`, tone-mapped to sRGB with `tone_map`.
//!
//! `cargo run --release --example ascii [SPP]`

mod common;

use std::error::Error;

use embedded_graphics_core::pixelcolor::RgbColor;
use picomis::{Preset, tone_map};

/// Characters from dark to bright.
const RAMP: &[u8] = b" .:-=+*#%@";

fn main() -> Result<(), Box<dyn Error>> {
    let spp = match std::env::args().nth(1) {
        Some(a) => a.parse().map_err(|e| format!("SPP {a:?}: {e}"))?,
        None => 16,
    };
    // A terminal's characters are about twice as tall as wide: two film rows per line.
    let (width, height) = (72, 48);
    let scene = common::scene(width, height)?;
    let settings = Preset::Best.settings().with_spp(spp)?;
    // The estimator for the scene, compiled for the strategies `Best` (`new` checks that the
    // settings name the same ones).
    let integrator = common::DemoIntegrator::new(&scene, &settings)?;
    for y in (0..height).step_by(2) {
        let line: String = (0..width)
            .map(|x| {
                let radiance = (integrator.render_pixel(x, y).radiance()
                    + integrator.render_pixel(x, y + 1).radiance())
                    * 0.5;
                let c = tone_map(radiance);
                // Luma of the sRGB codes, 0..=255.
                let luma =
                    (2126 * u32::from(c.r()) + 7152 * u32::from(c.g()) + 722 * u32::from(c.b())) / 10_000;
                char::from(RAMP[luma as usize * (RAMP.len() - 1) / 255])
            })
            .collect();
        println!("{line}");
    }
    Ok(())
}
