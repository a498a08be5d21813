//! Progressive rendering: each pass adds the next camera samples of every pixel to a running
//! sum, so the image after N samples per pixel is exactly the kernel's `render_pixel` at N spp
//! (the estimator of the settings, [`picomis_host::renderer`]).
//!
//! Camera sample s of pixel p draws its random numbers from (seed, p, s) alone, so a pass adds
//! samples `spp..spp + k`. `render_pixel` adds samples 0, 1, ..., N - 1 in order to a
//! [`PixelSum`] and takes its mean; each pixel here keeps its `PixelSum` between passes, which
//! does the same operations in the same order and gives the same bits.

use picomis::{Estimate, PixelSum, RenderSettings, Rgb, TechniqueEstimate, tone_map};
use picomis_format::SceneFile;
use picomis_host::{HostScene, NO_LIGHT, weight_color};

use embedded_graphics_core::pixelcolor::{Rgb888, RgbColor};

/// The page's scenes: the host's one scene type (that of `picomis-sim render`).
pub type WebScene = HostScene;

/// The most camera samples per pixel a render accumulates.
pub const MAX_SPP: u32 = 1 << 24;

/// The images the page shows, in the order of [`Progressive::rgba`].
pub const IMAGES: [&str; 5] = [
    "image",
    "light samples' contribution",
    "BSDF samples' contribution",
    "weight of light samples",
    "weight of BSDF samples",
];

/// A render in progress.
pub struct Progressive {
    scene: Box<WebScene>,
    settings: RenderSettings,
    width: u32,
    height: u32,
    sums: Vec<PixelSum>,
    spp: u32,
    rgba: Vec<u8>,
}

impl Progressive {
    /// A render of `file` with `settings` (its spp is ignored: passes decide), nothing sampled;
    /// the kernel's error when it refuses the settings.
    pub fn new(file: &SceneFile, settings: RenderSettings) -> Result<Self, String> {
        let scene: Box<WebScene> = Box::new(file.build().map_err(|e| e.to_string())?);
        picomis_host::renderer(&scene, &settings).map_err(|e| e.to_string())?;
        let film = scene.film();
        let (width, height) = (film.width(), film.height());
        let pixels = film.pixels() as usize;
        Ok(Self {
            scene,
            settings,
            width,
            height,
            sums: vec![PixelSum::default(); pixels],
            spp: 0,
            rgba: vec![0; pixels * 4 * IMAGES.len()],
        })
    }

    /// Width in pixels.
    pub fn width(&self) -> u32 {
        self.width
    }
    /// Height in pixels.
    pub fn height(&self) -> u32 {
        self.height
    }
    /// Camera samples per pixel so far.
    pub fn spp(&self) -> u32 {
        self.spp
    }

    /// Adds the next `k` camera samples of every pixel (fewer if [`MAX_SPP`] is reached);
    /// returns how many were added.
    pub fn add_samples(&mut self, k: u32) -> u32 {
        // Accepted by `new`: no error here.
        let Ok(renderer) = picomis_host::renderer(&self.scene, &self.settings) else { return 0 };
        let k = k.min(MAX_SPP - self.spp);
        let (start, end) = (self.spp, self.spp + k);
        let width = self.width as usize;
        for (i, sum) in self.sums.iter_mut().enumerate() {
            let (x, y) = ((i % width) as u32, (i / width) as u32);
            for s in start..end {
                sum.add(&renderer.camera_sample(x, y, s));
            }
        }
        self.spp = end;
        k
    }

    /// The estimate of pixel `i` (row-major) at the current spp: `render_pixel`'s value.
    pub fn mean(&self, i: usize) -> Estimate {
        self.sums.get(i).map(PixelSum::mean).unwrap_or_default()
    }

    /// Tone-maps the current estimates into [`Self::rgba`].
    pub fn update_rgba(&mut self) {
        let n = self.sums.len();
        let mut images = std::mem::take(&mut self.rgba);
        for i in 0..n {
            let e = self.mean(i);
            let colors = [
                tone_map(e.radiance()),
                tone_map(e.light.contribution),
                tone_map(e.bsdf.contribution),
                weight(&e.light),
                weight(&e.bsdf),
            ];
            for (k, c) in colors.iter().enumerate() {
                let at = (k * n + i) * 4;
                if let Some(px) = images.get_mut(at..at + 4) {
                    px.copy_from_slice(&[c.r(), c.g(), c.b(), 255]);
                }
            }
        }
        self.rgba = images;
    }

    /// The [`IMAGES`], one after the other, each `width * height` RGBA pixels, row 0 at the top.
    pub fn rgba(&self) -> &[u8] {
        &self.rgba
    }

    /// Linear radiance at the current spp, RGB f32 per pixel, row 0 at the top (the values
    /// `picomis-sim render --out F.pfm` writes, bottom row first).
    pub fn radiance(&self) -> Vec<f32> {
        (0..self.sums.len())
            .flat_map(|i| {
                let c: Rgb = self.mean(i).radiance();
                [c.x, c.y, c.z]
            })
            .collect()
    }
}

/// The weight panels' colour: the mean weight of the samples that found light, or grey.
fn weight(t: &TechniqueEstimate) -> Rgb888 {
    if t.found > 0 { weight_color(t.mean_weight()) } else { NO_LIGHT }
}

/// `width` pixels of the weight colour bar, RGBA, from weight 0 on the left to 1 on the right
/// (as the desktop figure's legend), then one pixel of [`NO_LIGHT`].
pub fn colorbar(width: u32) -> Vec<u8> {
    let w = width.max(2);
    (0..w)
        .map(|i| weight_color(i as f32 / (w - 1) as f32))
        .chain([NO_LIGHT])
        .flat_map(|c| [c.r(), c.g(), c.b(), 255])
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::catalog::SCENES;
    use picomis::{Heuristic, Method, SphereSampling};

    #[test]
    fn passes_accumulate_to_render_pixel_bit_for_bit() {
        // A small film, uneven passes (1 + 2 + 3 + 4 = 10 spp), two scenes and methods.
        for (name, method) in [
            ("veach_mis", Method::Mis(Heuristic::Power { beta: 2.0 })),
            ("stress", Method::Mis(Heuristic::Balance)),
        ] {
            let b = SCENES.iter().find(|b| b.name == name).unwrap();
            let file = SceneFile::parse(b.json, b.name).unwrap();
            let settings =
                RenderSettings::new(method, 1, 1, 10, 7).unwrap().with_sphere_sampling(SphereSampling::Area);
            let mut p = Progressive::new(&file, settings).unwrap();
            for k in 1..=4 {
                assert_eq!(p.add_samples(k), k);
            }
            assert_eq!(p.spp(), 10);
            let scene: WebScene = file.build().unwrap();
            let renderer = picomis_host::renderer(&scene, &settings).unwrap();
            let w = p.width() as usize;
            // Every 37th pixel, to keep the test quick.
            for i in (0..(p.width() * p.height()) as usize).step_by(37) {
                let expected = renderer.render_pixel((i % w) as u32, (i / w) as u32);
                assert_eq!(p.mean(i), expected, "{name}: pixel {i}");
            }
            p.update_rgba();
            let e = p.mean(0);
            let c = tone_map(e.radiance());
            assert_eq!(&p.rgba()[..4], &[c.r(), c.g(), c.b(), 255]);
        }
    }

    #[test]
    fn colorbar_runs_from_zero_to_one_then_no_light() {
        let bar = colorbar(9);
        assert_eq!(bar.len(), 10 * 4);
        let px = |i: usize| Rgb888::new(bar[4 * i], bar[4 * i + 1], bar[4 * i + 2]);
        assert_eq!(px(0), weight_color(0.0));
        assert_eq!(px(4), weight_color(0.5));
        assert_eq!(px(8), weight_color(1.0));
        assert_eq!(px(9), NO_LIGHT);
    }
}
