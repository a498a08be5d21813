//! The integrator of a command: its flags ([`IntegratorDesc`], one argument group for
//! `render`, `figure`, `view` and `study`) over the scene file's integrator block over a preset,
//! and errors that name where a key was set.

use picomis::{Method, Preset, RenderSettings};
use picomis_format::{IntegratorDesc, KeyError};

use crate::SimError;
use crate::scenes::Loaded;

/// `e` in words, naming where its key was set: the flag, or the scene file's integrator block.
pub fn key_error(loaded: &Loaded, flags: &IntegratorDesc, e: &KeyError) -> SimError {
    let set_by_flag = serde_json::to_value(flags).ok().is_some_and(|v| v.get(e.key).is_some());
    if set_by_flag || flags.preset.is_some() {
        SimError::Usage(format!("{}: {}", e.flag(), e.reason))
    } else {
        SimError::Usage(format!("{}: integrator.{}: {}", loaded.file.file(), e.key, e.reason))
    }
}

/// The integrator keys of a command: its flags over the scene file's integrator block, and that
/// over `preset` where the file names none (the best preset when `preset` is `None` too).
pub fn keys(loaded: &Loaded, flags: &IntegratorDesc, preset: Option<Preset>) -> IntegratorDesc {
    let file = loaded.file.integrator();
    flags.over(&IntegratorDesc { preset: file.preset.or(preset), ..file.clone() })
}

/// The integrator of a command ([`keys`]) with `spp` camera samples per pixel and `seed`.
pub fn integrator(
    loaded: &Loaded,
    flags: &IntegratorDesc,
    preset: Option<Preset>,
    spp: u32,
    seed: u32,
) -> Result<RenderSettings, SimError> {
    keys(loaded, flags, preset).settings(spp, seed).map_err(|e| key_error(loaded, flags, &e))
}

/// `keys` with `method` (and its parameters) in place of their method.
pub fn with_method(keys: &IntegratorDesc, method: Method) -> IntegratorDesc {
    IntegratorDesc { mis: Some(method), beta: None, alpha: None, ..keys.clone() }
}
