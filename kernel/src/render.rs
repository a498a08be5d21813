//! Rendering: one pixel as an HDR estimate, or a tile or whole image into any
//! `embedded-graphics` [`DrawTarget`]. Pixel (x, y), camera sample s draws its random numbers
//! from `Sampler::new(seed, y * width + x, s)`: images are independent of tile order and threads.

use embedded_graphics_core::draw_target::DrawTarget;
use embedded_graphics_core::geometry::{Point, Size};
use embedded_graphics_core::pixelcolor::Rgb888;
use embedded_graphics_core::primitives::Rectangle;

use crate::camera::Film;
use crate::estimator::{Estimate, trace};
use crate::math::{Rgb, Vec2, powf};
use crate::rng::Sampler;
use crate::scene::Scene;
use crate::settings::RenderSettings;

/// What a render did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct RenderStats {
    /// Pixels rendered.
    pub pixels: u32,
    /// Camera samples taken.
    pub camera_samples: u32,
}

/// One camera sample of pixel `(x, y)`: box filter over the pixel's footprint.
#[inline]
pub fn camera_sample<const S: usize, const L: usize, const M: usize>(
    scene: &Scene<S, L, M>,
    settings: &RenderSettings,
    x: u32,
    y: u32,
    index: u32,
) -> Estimate {
    let film = scene.film();
    let mut sampler = Sampler::new(settings.seed(), y.wrapping_mul(film.width()).wrapping_add(x), index);
    let jitter = sampler.next_2d();
    let uv =
        Vec2::new((x as f32 + jitter.x) / film.width() as f32, (y as f32 + jitter.y) / film.height() as f32);
    let (ray, t_near) = scene.camera().ray(uv);
    trace(scene, settings, &ray, t_near, &mut sampler)
}

/// The HDR estimate of pixel `(x, y)`: the mean of `spp` camera samples (weights and counts of
/// the technique parts are sums over the samples).
pub fn render_pixel<const S: usize, const L: usize, const M: usize>(
    scene: &Scene<S, L, M>,
    settings: &RenderSettings,
    x: u32,
    y: u32,
) -> Estimate {
    let mut sum = Estimate::default();
    for s in 0..settings.spp() {
        sum.merge(&camera_sample(scene, settings, x, y, s));
    }
    sum.scale(1.0 / settings.spp() as f32);
    sum
}

/// Linear radiance to 8-bit sRGB: clamp to [0, 1], sRGB transfer curve, round.
pub fn tone_map(c: Rgb) -> Rgb888 {
    let encode = |v: f32| {
        let v = if v > 0.0 { v.min(1.0) } else { 0.0 }; // also maps NaN to 0
        let s = if v <= 0.003_130_8 { 12.92 * v } else { 1.055 * powf(v, 1.0 / 2.4) - 0.055 };
        (s * 255.0 + 0.5) as u8
    };
    Rgb888::new(encode(c.x), encode(c.y), encode(c.z))
}

/// Renders the pixels of `area` (clipped to the film) into `target`, row by row through
/// `fill_contiguous`, and passes the target's error through.
pub fn render_tile<D, const S: usize, const L: usize, const M: usize>(
    scene: &Scene<S, L, M>,
    settings: &RenderSettings,
    area: &Rectangle,
    target: &mut D,
) -> Result<RenderStats, D::Error>
where
    D: DrawTarget,
    D::Color: From<Rgb888>,
{
    let film = scene.film();
    let area = area.intersection(&film_rect(film));
    // `area` lies inside the film, so its corner is non-negative.
    let (x0, y0) = (area.top_left.x as u32, area.top_left.y as u32);
    let (w, h) = (area.size.width, area.size.height);
    let colors = (y0..y0 + h).flat_map(|y| {
        (x0..x0 + w).map(move |x| D::Color::from(tone_map(render_pixel(scene, settings, x, y).radiance())))
    });
    target.fill_contiguous(&area, colors)?;
    let pixels = area.size.width * area.size.height;
    Ok(RenderStats { pixels, camera_samples: pixels * settings.spp() })
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

/// Renders the whole image tile by tile, calling `on_tile` after each tile (for progress).
pub fn render<D, const S: usize, const L: usize, const M: usize>(
    scene: &Scene<S, L, M>,
    settings: &RenderSettings,
    tile: Size,
    target: &mut D,
    mut on_tile: impl FnMut(&Rectangle, &RenderStats),
) -> Result<RenderStats, D::Error>
where
    D: DrawTarget,
    D::Color: From<Rgb888>,
{
    let mut total = RenderStats::default();
    for area in tiles(scene.film(), tile) {
        let s = render_tile(scene, settings, &area, target)?;
        total.pixels += s.pixels;
        total.camera_samples += s.camera_samples;
        on_tile(&area, &total);
    }
    Ok(total)
}
