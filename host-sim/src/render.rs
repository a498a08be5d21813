//! Rendering on all cores: one row per rayon task, every pixel `picomis::render_pixel`
//! (deterministic per seed, pixel and sample, so the thread count never changes the image).

use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use picomis::{Estimate, RenderSettings, Scene, render_pixel};
use rayon::prelude::*;

use crate::scenes::SceneVisitor;

/// Per-pixel estimates of one render, row-major, row 0 at the top.
#[derive(Clone, Debug)]
pub struct Estimates {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// One estimate per pixel (radiance split into emitted, light and BSDF parts).
    pub pixels: Vec<Estimate>,
}

/// A progress bar of `steps` steps (rows times spp, for [`render_estimates`]) on stderr: hidden
/// when stderr is not a terminal (indicatif's rule) or when the `CI` environment variable is set.
pub fn progress_bar(steps: u64, message: &str) -> ProgressBar {
    if std::env::var_os("CI").is_some() {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::with_draw_target(Some(steps), ProgressDrawTarget::stderr());
    if let Ok(style) =
        ProgressStyle::with_template("{msg} [{bar:40}] {percent:>3}% {elapsed_precise} (eta {eta})")
    {
        bar.set_style(style.progress_chars("=> "));
    }
    bar.set_message(message.to_string());
    bar
}

/// Renders `scene` with `settings` on all cores, advancing `progress` by `spp` per row (so one
/// bar can follow renders of different spp).
pub fn render_estimates<const S: usize, const L: usize, const M: usize>(
    scene: &Scene<S, L, M>,
    settings: &RenderSettings,
    progress: &ProgressBar,
) -> Estimates {
    let film = scene.film();
    let (width, height) = (film.width(), film.height());
    let mut pixels = vec![Estimate::default(); film.pixels() as usize];
    pixels.par_chunks_mut(width as usize).zip(0..height).for_each(|(row, y)| {
        for (x, px) in (0..width).zip(row.iter_mut()) {
            *px = render_pixel(scene, settings, x, y);
        }
        progress.inc(u64::from(settings.spp()));
    });
    Estimates { width, height, pixels }
}

/// What a batch of renders of one scene took.
#[derive(Clone, Debug)]
pub struct Batch {
    /// One result per entry of the settings list.
    pub images: Vec<Estimates>,
    /// Wall-clock time of all renders.
    pub elapsed: Duration,
    /// Camera samples taken in all renders.
    pub camera_samples: u64,
}

/// A [`SceneVisitor`] that renders the scene once per settings entry, sharing one progress bar.
pub struct RenderBatch<'a> {
    /// The renders to do.
    pub settings: &'a [RenderSettings],
    /// Label of the progress bar.
    pub message: &'a str,
}

impl SceneVisitor for RenderBatch<'_> {
    type Output = Batch;
    fn visit<const S: usize, const L: usize, const M: usize>(self, scene: Scene<S, L, M>) -> Batch {
        let film = scene.film();
        let steps = self.settings.iter().map(|s| u64::from(film.height()) * u64::from(s.spp())).sum();
        let bar = progress_bar(steps, self.message);
        let start = Instant::now();
        let images = self.settings.iter().map(|s| render_estimates(&scene, s, &bar)).collect();
        let elapsed = start.elapsed();
        bar.finish_and_clear();
        let camera_samples =
            self.settings.iter().map(|s| u64::from(film.pixels()) * u64::from(s.spp())).sum();
        Batch { images, elapsed, camera_samples }
    }
}

/// A [`RenderBatch`] whose scene runs its ray queries in `arith` ([`Scene::enable_arith`]):
/// the scene's error when the arithmetic cannot represent it.
pub struct ArithBatch<'a> {
    /// The ray queries' arithmetic.
    pub arith: picomis::Arith,
    /// The renders.
    pub batch: RenderBatch<'a>,
}

impl SceneVisitor for ArithBatch<'_> {
    type Output = Result<Batch, picomis::SceneError>;
    fn visit<const S: usize, const L: usize, const M: usize>(
        self,
        mut scene: Scene<S, L, M>,
    ) -> Result<Batch, picomis::SceneError> {
        scene.enable_arith(self.arith)?;
        Ok(self.batch.visit(scene))
    }
}

/// `e` in words, with the scene file's name of the entry that fixed point cannot represent
/// (`fixed point cannot represent shape 1: ... (shapes[1] "tiny_light")`).
pub fn scene_error(file: &picomis_format::SceneFile, e: &picomis::SceneError) -> String {
    let entry = match e {
        picomis::SceneError::NotRepresentable { entry, .. } => file.shape_entry(usize::from(*entry)),
        _ => None,
    };
    format!("{e}{}", entry.map(|n| format!(" ({n})")).unwrap_or_default())
}
