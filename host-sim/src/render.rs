//! Rendering on all cores: one row per rayon task, every pixel the kernel's estimate
//! ([`picomis_host::Renderer`], monomorphised for the render's strategies; deterministic per
//! seed, pixel and sample, so the thread count never changes the image).

use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use picomis::{Estimate, RenderSettings, SceneError};
use picomis_host::{HostScene, Renderer, renderer};
use rayon::prelude::*;

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

/// Renders the film of `scene` with `settings` on all cores, advancing `progress` by `spp` per
/// row (so one bar can follow renders of different spp).
pub fn render_estimates(
    scene: &HostScene,
    settings: &RenderSettings,
    progress: &ProgressBar,
) -> Result<Estimates, SceneError> {
    Ok(render_with(&*renderer(scene, settings)?, scene.film(), progress))
}

/// Renders `film` with `renderer` on all cores (see [`render_estimates`]).
pub fn render_with(renderer: &dyn Renderer, film: picomis::Film, progress: &ProgressBar) -> Estimates {
    let (width, height) = (film.width(), film.height());
    let spp = renderer.settings().spp();
    let mut pixels = vec![Estimate::default(); film.pixels() as usize];
    pixels.par_chunks_mut(width as usize).zip(0..height).for_each(|(row, y)| {
        renderer.render_row(y, row);
        progress.inc(u64::from(spp));
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

/// Renders of one scene, one per settings entry, sharing one progress bar.
pub struct RenderBatch<'a> {
    /// The renders to do.
    pub settings: &'a [RenderSettings],
    /// Label of the progress bar.
    pub message: &'a str,
}

impl RenderBatch<'_> {
    /// Renders `scene` once per settings entry; the scene's error when the kernel refuses a
    /// settings entry.
    pub fn run(&self, scene: &HostScene) -> Result<Batch, SceneError> {
        let film = scene.film();
        let steps = self.settings.iter().map(|s| u64::from(film.height()) * u64::from(s.spp())).sum();
        let bar = progress_bar(steps, self.message);
        let start = Instant::now();
        let images =
            self.settings.iter().map(|s| render_estimates(scene, s, &bar)).collect::<Result<_, _>>()?;
        let elapsed = start.elapsed();
        bar.finish_and_clear();
        let camera_samples =
            self.settings.iter().map(|s| u64::from(film.pixels()) * u64::from(s.spp())).sum();
        Ok(Batch { images, elapsed, camera_samples })
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
