//! One render of the study: a method's settings at the scene's sample counts, the host's parallel
//! render ([`crate::render::render_estimates`]) timed, and the part of the radiance that errors
//! are measured on.

use std::time::Instant;

use indicatif::ProgressBar;
use picomis::{Estimate, RenderSettings, Rgb};
use picomis_host::HostScene;
use picomis_host::study::StudyMethod;

use crate::SimError;
use crate::render::render_estimates;

/// The render settings of method `m` with `n` = (light, BSDF) samples per camera sample (at
/// least one of each).
pub fn settings(m: &StudyMethod, n: (u16, u16), spp: u32, seed: u32) -> Result<RenderSettings, SimError> {
    m.settings(n.0.max(1), n.1.max(1), spp, seed).map_err(|e| SimError::Usage(format!("{}: {e}", m.label)))
}

/// Renders every pixel of `scene` on all cores, advancing `bar` by `spp` per row; returns the
/// estimates (row-major) and the wall-clock seconds (the estimator's setup included), or the
/// kernel's refusal of the settings.
pub fn timed(
    scene: &HostScene,
    settings: &RenderSettings,
    bar: &ProgressBar,
) -> Result<(Vec<Estimate>, f64), SimError> {
    let start = Instant::now();
    let estimates =
        render_estimates(scene, settings, bar).map_err(|e| SimError::Usage(format!("settings: {e}")))?;
    Ok((estimates.pixels, start.elapsed().as_secs_f64()))
}

/// The reflected (direct) light of an estimate: what the two techniques estimate.
pub fn reflected(e: &Estimate) -> Rgb {
    e.light.contribution + e.bsdf.contribution
}

/// The radiance that errors are measured on: the reflected light, or the full radiance (lights
/// seen directly included) with `include_emitted`.
pub fn measured(e: &Estimate, include_emitted: bool) -> Rgb {
    if include_emitted { e.radiance() } else { reflected(e) }
}
