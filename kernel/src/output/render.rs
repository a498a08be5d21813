//! Rendering: one pixel as an HDR estimate, or a tile or whole image into any
//! `embedded-graphics` [`DrawTarget`]. Pixel (x, y), camera sample s draws its random numbers
//! from `Sampler::with_kind(sampler, seed, y * width + x, s)`: images are independent of tile order and threads.

use embedded_graphics_core::draw_target::DrawTarget;
use embedded_graphics_core::geometry::{Point, Size};
use embedded_graphics_core::pixelcolor::Rgb888;
use embedded_graphics_core::primitives::Rectangle;

use crate::geometry::Film;
use crate::integrator::{Estimate, Integrator, Strategies};
use crate::num::Vec2;
use crate::output::pixel_sum::PixelSum;
use crate::output::tonemap::tone_map;
use crate::sampling::sampler::Sampler;

/// What a render did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct RenderStats {
    /// Pixels rendered.
    pub pixels: u32,
    /// Camera samples taken (u64: a 4096x4096 film at 256 spp takes 2^32 of them).
    pub camera_samples: u64,
}

impl RenderStats {
    /// The statistics of `pixels` pixels at `spp` camera samples each.
    pub fn new(pixels: u32, spp: u32) -> Self {
        RenderStats { pixels, camera_samples: u64::from(pixels) * u64::from(spp) }
    }

    /// Adds another render's statistics (saturating: never a panic, even in a debug build).
    pub fn add(&mut self, other: &Self) {
        self.pixels = self.pixels.saturating_add(other.pixels);
        self.camera_samples = self.camera_samples.saturating_add(other.camera_samples);
    }
}

impl<St: Strategies<L>, const S: usize, const L: usize, const M: usize> Integrator<'_, St, S, L, M> {
    /// One camera sample of pixel `(x, y)`: box filter over the pixel's footprint.
    #[inline]
    pub fn camera_sample(&self, x: u32, y: u32, index: u32) -> Estimate {
        let (scene, settings) = (self.scene(), self.settings());
        let film = scene.film();
        let pixel = y.wrapping_mul(film.width()).wrapping_add(x);
        let mut sampler = Sampler::with_kind(settings.sampler(), settings.seed(), pixel, index);
        let jitter = sampler.next_2d();
        let (ray, hit) = scene.camera_hit(Vec2::new(x as f32 + jitter.x, y as f32 + jitter.y), x, y);
        self.shade(hit, ray.dir, &mut sampler)
    }

    /// The HDR estimate of pixel `(x, y)`: the mean of `spp` camera samples, summed in order by a
    /// [`PixelSum`] (weights and counts of the technique parts are sums over the samples).
    pub fn render_pixel(&self, x: u32, y: u32) -> Estimate {
        PixelSum::mean_of(self.settings().spp(), |s| self.camera_sample(x, y, s))
    }

    /// Renders the pixels of `area` (clipped to the film) into `target`, row by row through
    /// `fill_contiguous`, and passes the target's error through.
    pub fn render_tile<D>(&self, area: &Rectangle, target: &mut D) -> Result<RenderStats, D::Error>
    where
        D: DrawTarget,
        D::Color: From<Rgb888>,
    {
        let film = self.scene().film();
        let area = area.intersection(&film_rect(film));
        // `area` lies inside the film, so its corner is non-negative.
        let (x0, y0) = (area.top_left.x as u32, area.top_left.y as u32);
        let (w, h) = (area.size.width, area.size.height);
        let colors = (y0..y0 + h).flat_map(|y| {
            (x0..x0 + w).map(move |x| D::Color::from(tone_map(self.render_pixel(x, y).radiance())))
        });
        target.fill_contiguous(&area, colors)?;
        Ok(RenderStats::new(area.size.width * area.size.height, self.settings().spp()))
    }

    /// Renders the whole image tile by tile, calling `on_tile` after each tile (for progress).
    pub fn render<D>(
        &self,
        tile: Size,
        target: &mut D,
        mut on_tile: impl FnMut(&Rectangle, &RenderStats),
    ) -> Result<RenderStats, D::Error>
    where
        D: DrawTarget,
        D::Color: From<Rgb888>,
    {
        let mut total = RenderStats::default();
        for area in tiles(self.scene().film(), tile) {
            let s = self.render_tile(&area, target)?;
            total.add(&s);
            on_tile(&area, &total);
        }
        Ok(total)
    }
}

/// The film as a rectangle.
pub fn film_rect(film: Film) -> Rectangle {
    Rectangle::new(Point::zero(), Size::new(film.width(), film.height()))
}

/// The film cut into tiles of `tile` pixels (row-major; edge tiles are smaller).
pub fn tiles(film: Film, tile: Size) -> impl Iterator<Item = Rectangle> {
    let (tw, th) = (tile.width.max(1), tile.height.max(1));
    let (w, h) = (film.width(), film.height());
    let across = w.div_ceil(tw);
    let down = h.div_ceil(th);
    (0..down).flat_map(move |ty| {
        (0..across).map(move |tx| {
            let (x, y) = (tx * tw, ty * th);
            Rectangle::new(Point::new(x as i32, y as i32), Size::new(tw.min(w - x), th.min(h - y)))
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stats_of_a_large_film_do_not_overflow() {
        // 4096 x 4096 pixels at 256 spp = 2^32 camera samples: a u32 product overflows (and
        // panics in a debug build, where this test also runs: scripts/test.sh).
        let side = 4096u32;
        let tile = RenderStats::new(side * side, 256);
        assert_eq!(tile.camera_samples, 1u64 << 32);
        let mut total = RenderStats::default();
        for _ in 0..4 {
            total.add(&RenderStats::new(side * side / 4, 256));
        }
        assert_eq!(total, tile);
        // The largest film (16384 x 16384) at the largest spp still fits.
        let max = RenderStats::new(16384 * 16384, u32::MAX);
        assert_eq!(max.camera_samples, (16384u64 * 16384) * u64::from(u32::MAX));
        let mut sum = max;
        sum.add(&max);
        assert_eq!(sum.pixels, 2 * 16384 * 16384);
    }
}
