//! Rendering: one pixel as an HDR estimate, or a tile or whole image into any
//! `embedded-graphics` [`DrawTarget`]. Pixel (x, y), camera sample s draws its random numbers
//! from `Sampler::with_kind(sampler, seed, y * width + x, s)`: images are independent of tile order and threads.

use embedded_graphics_core::draw_target::DrawTarget;
use embedded_graphics_core::geometry::{Point, Size};
use embedded_graphics_core::pixelcolor::Rgb888;
use embedded_graphics_core::primitives::Rectangle;

use crate::camera::Film;
use crate::estimator::{Estimate, trace};
use crate::math::{Rgb, Vec2};
use crate::rng::Sampler;
use crate::scene::Scene;
use crate::settings::RenderSettings;

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
    let pixel = y.wrapping_mul(film.width()).wrapping_add(x);
    let mut sampler = Sampler::with_kind(settings.sampler(), settings.seed(), pixel, index);
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

/// Linear values at which the 8-bit sRGB code steps up: entry `k - 1` is the sRGB decoding of
/// `(k - 0.5) / 255` (the sRGB transfer curve, IEC 61966-2-1), rounded to f32. Generated once by
/// evaluating the curve in double precision; a unit test checks it against `powf`.
const SRGB_STEPS: [f32; 255] = [
    0.0001517635,
    0.0004552905,
    0.0007588175,
    0.0010623444,
    0.0013658714,
    0.0016693984,
    0.0019729254,
    0.0022764525,
    0.0025799794,
    0.0028835062,
    0.0031883009,
    0.0035092593,
    0.003848315,
    0.004205748,
    0.004581833,
    0.0049768374,
    0.005391024,
    0.0058246506,
    0.0062779696,
    0.0067512277,
    0.0072446684,
    0.0077585303,
    0.0082930485,
    0.008848453,
    0.0094249705,
    0.010022826,
    0.010642237,
    0.011283421,
    0.0119465925,
    0.01263196,
    0.013339732,
    0.014070112,
    0.014823303,
    0.015599503,
    0.01639891,
    0.017221715,
    0.018068114,
    0.018938294,
    0.019832443,
    0.020750744,
    0.021693382,
    0.022660539,
    0.02365239,
    0.024669115,
    0.025710888,
    0.026777882,
    0.02787027,
    0.02898822,
    0.030131903,
    0.03130148,
    0.032497123,
    0.03371899,
    0.034967244,
    0.036242045,
    0.037543554,
    0.038871925,
    0.04022732,
    0.041609887,
    0.043019786,
    0.044457164,
    0.04592217,
    0.047414962,
    0.048935685,
    0.050484486,
    0.052061506,
    0.053666897,
    0.055300802,
    0.05696336,
    0.058654718,
    0.060375012,
    0.062124383,
    0.063902974,
    0.06571092,
    0.06754835,
    0.06941541,
    0.071312234,
    0.073238954,
    0.07519571,
    0.07718261,
    0.07919982,
    0.08124744,
    0.083325624,
    0.08543449,
    0.087574154,
    0.08974477,
    0.09194644,
    0.0941793,
    0.096443474,
    0.098739095,
    0.10106627,
    0.10342513,
    0.105815805,
    0.1082384,
    0.110693045,
    0.11317986,
    0.11569897,
    0.11825048,
    0.12083452,
    0.1234512,
    0.12610064,
    0.12878296,
    0.13149826,
    0.13424668,
    0.1370283,
    0.13984327,
    0.14269169,
    0.14557366,
    0.14848931,
    0.15143873,
    0.15442206,
    0.15743938,
    0.16049083,
    0.1635765,
    0.16669649,
    0.16985093,
    0.17303991,
    0.17626357,
    0.17952198,
    0.18281525,
    0.1861435,
    0.18950683,
    0.19290535,
    0.19633915,
    0.19980834,
    0.20331304,
    0.20685335,
    0.21042934,
    0.21404114,
    0.21768884,
    0.22137256,
    0.2250924,
    0.22884843,
    0.23264076,
    0.2364695,
    0.24033478,
    0.24423663,
    0.2481752,
    0.25215057,
    0.25616285,
    0.26021212,
    0.26429847,
    0.26842204,
    0.2725829,
    0.2767811,
    0.2810168,
    0.2852901,
    0.28960103,
    0.29394972,
    0.2983363,
    0.3027608,
    0.30722335,
    0.31172404,
    0.31626296,
    0.32084018,
    0.32545584,
    0.33010998,
    0.33480275,
    0.33953416,
    0.34430438,
    0.34911346,
    0.3539615,
    0.35884857,
    0.36377478,
    0.36874023,
    0.37374496,
    0.37878913,
    0.38387278,
    0.388996,
    0.3941589,
    0.39936152,
    0.40460402,
    0.40988642,
    0.41520882,
    0.42057136,
    0.42597404,
    0.43141702,
    0.43690035,
    0.44242412,
    0.44798842,
    0.4535933,
    0.45923892,
    0.4649253,
    0.47065252,
    0.4764207,
    0.48222992,
    0.48808023,
    0.49397177,
    0.49990454,
    0.5058787,
    0.5118943,
    0.5179514,
    0.5240501,
    0.5301905,
    0.5363727,
    0.54259676,
    0.5488627,
    0.55517066,
    0.5615207,
    0.5679129,
    0.5743473,
    0.58082414,
    0.58734334,
    0.593905,
    0.6005092,
    0.6071561,
    0.6138457,
    0.6205781,
    0.62735337,
    0.6341716,
    0.6410329,
    0.64793724,
    0.6548848,
    0.66187567,
    0.6689098,
    0.67598736,
    0.68310845,
    0.6902731,
    0.69748133,
    0.7047334,
    0.71202916,
    0.7193688,
    0.72675246,
    0.73418003,
    0.7416518,
    0.7491677,
    0.7567278,
    0.7643323,
    0.7719811,
    0.7796744,
    0.7874123,
    0.79519475,
    0.8030219,
    0.81089383,
    0.8188105,
    0.8267722,
    0.8347788,
    0.8428305,
    0.8509273,
    0.8590692,
    0.8672565,
    0.87548906,
    0.88376707,
    0.89209056,
    0.9004596,
    0.9088742,
    0.91733456,
    0.9258406,
    0.9343926,
    0.94299036,
    0.95163417,
    0.96032405,
    0.96906,
    0.97784215,
    0.98667055,
    0.99554527,
];

/// Linear radiance to 8-bit sRGB: clamp to [0, 1], sRGB transfer curve, round to the nearest
/// code. The code is found by a binary search over a table of the 255 steps (8 comparisons per channel
/// instead of a `powf`), so it costs the same on a Cortex-M0 as anywhere else.
pub fn tone_map(c: Rgb) -> Rgb888 {
    let encode = |v: f32| {
        // Number of steps at or below v; NaN compares false and maps to 0.
        let (mut lo, mut hi) = (0usize, SRGB_STEPS.len());
        while lo < hi {
            let mid = (lo + hi) / 2;
            match SRGB_STEPS.get(mid) {
                Some(&step) if v >= step => lo = mid + 1,
                _ => hi = mid,
            }
        }
        lo as u8 // lo <= 255
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
    Ok(RenderStats::new(area.size.width * area.size.height, settings.spp()))
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
        total.add(&s);
        on_tile(&area, &total);
    }
    Ok(total)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::powf;
    use embedded_graphics_core::pixelcolor::RgbColor;

    fn srgb_formula(v: f32) -> f32 {
        let v = v.clamp(0.0, 1.0);
        255.0 * if v <= 0.003_130_8 { 12.92 * v } else { 1.055 * powf(v, 1.0 / 2.4) - 0.055 }
    }

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

    #[test]
    fn tone_map_rounds_the_srgb_curve() {
        assert_eq!(tone_map(Rgb::new(0.0, 1.0, 0.5)), Rgb888::new(0, 255, 188));
        assert_eq!(tone_map(Rgb::new(-1.0, 7.0, f32::NAN)), Rgb888::new(0, 255, 0));
        assert_eq!(tone_map(Rgb::splat(f32::INFINITY)), Rgb888::new(255, 255, 255));
        // Away from the rounding boundaries the table and the formula agree exactly.
        for i in 0..=20_000 {
            let v = i as f32 / 20_000.0;
            let exact = srgb_formula(v);
            let code = tone_map(Rgb::splat(v)).r();
            if (exact - exact.floor() - 0.5).abs() > 1e-3 {
                assert_eq!(f32::from(code), (exact + 0.5).floor(), "v = {v}");
            } else {
                assert!((f32::from(code) - exact).abs() <= 0.5 + 1e-3, "v = {v}");
            }
        }
        // The steps increase strictly.
        assert!(SRGB_STEPS.windows(2).all(|w| w[0] < w[1]));
    }
}
