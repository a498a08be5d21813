//! Renders a small scene through an `embedded-graphics` `DrawTarget`, as a firmware draws into
//! its display, and writes the image as a binary PPM file.
//!
//! `cargo run --release --example ppm -- [OUT.ppm] [SPP]` (default `picomis.ppm`, 16 spp)

mod common;

use std::convert::Infallible;
use std::error::Error;

use embedded_graphics_core::Pixel;
use embedded_graphics_core::draw_target::DrawTarget;
use embedded_graphics_core::geometry::{OriginDimensions, Size};
use embedded_graphics_core::pixelcolor::{Rgb888, RgbColor};
use picomis::Preset;

/// An RGB image in memory: the `DrawTarget` a display driver would be.
struct Image {
    width: u32,
    height: u32,
    rgb: Vec<u8>,
}

impl OriginDimensions for Image {
    fn size(&self) -> Size {
        Size::new(self.width, self.height)
    }
}

impl DrawTarget for Image {
    type Color = Rgb888;
    type Error = Infallible;

    fn draw_iter<I: IntoIterator<Item = Pixel<Rgb888>>>(&mut self, pixels: I) -> Result<(), Infallible> {
        for Pixel(p, c) in pixels {
            let (Ok(x), Ok(y)) = (u32::try_from(p.x), u32::try_from(p.y)) else { continue };
            if x < self.width && y < self.height {
                let i = 3 * (y * self.width + x) as usize;
                self.rgb[i..i + 3].copy_from_slice(&[c.r(), c.g(), c.b()]);
            }
        }
        Ok(())
    }
}

fn main() -> Result<(), Box<dyn Error>> {
    let mut args = std::env::args().skip(1);
    let out = args.next().unwrap_or_else(|| "picomis.ppm".into());
    let spp = match args.next() {
        Some(a) => a.parse().map_err(|e| format!("SPP {a:?}: {e}"))?,
        None => 16,
    };
    let (width, height) = (160, 120);
    let scene = common::scene(width, height)?;
    let settings = Preset::Best.settings().with_spp(spp)?;
    // The estimator for the scene, compiled for the strategies `Best` (`new` checks that the
    // settings name the same ones).
    let integrator = common::DemoIntegrator::new(&scene, &settings)?;

    let mut image = Image { width, height, rgb: vec![0; (3 * width * height) as usize] };
    // Tile by tile, as on a device (where `on_tile` could report progress over defmt).
    let stats = integrator.render(Size::new(16, 16), &mut image, |_tile, _so_far| {})?;

    let mut ppm = format!("P6\n{width} {height}\n255\n").into_bytes();
    ppm.extend_from_slice(&image.rgb);
    std::fs::write(&out, ppm).map_err(|e| format!("{out}: {e}"))?;
    eprintln!("{out}: {width}x{height}, {} camera samples", stats.camera_samples);
    Ok(())
}
