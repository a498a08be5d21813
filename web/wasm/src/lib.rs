//! # picomis-web
//!
//! The picomis kernel for the browser page in `web/`: a few exported functions over buffers in
//! linear memory, no bindings generator. The page's worker (`web/worker.js`) calls them:
//!
//! | export | what it does |
//! |---|---|
//! | `info_ptr()`, `info_len()` | JSON: built-in scenes (film, integrator defaults), methods, strategies |
//! | `setup(scene, method, beta, alpha, light, bsdf, spheres, lobe, selection, seed)` | starts a render (indices into the info lists); 0 = ok, else the reason is at `message_ptr()`, `message_len()` |
//! | `add_samples(k)` | adds the next `k` camera samples of every pixel; returns how many it added |
//! | `update()` | tone-maps the current estimate into the RGBA images at `rgba_ptr()` (`rgba_len()` bytes) |
//! | `width()`, `height()`, `spp()` | the film and the camera samples per pixel so far |
//! | `radiance_ptr()`, `radiance_len()` | linear radiance, f32 RGB per pixel, row 0 first |
//! | `colorbar_ptr(width)` | the weight colour bar: `width` RGBA pixels for weights 0..=1, then the "no light" grey |
//!
//! Pointers and lengths are byte offsets into the module's memory, valid until the next call.
//! After N samples per pixel, the image equals `picomis-sim render --spp N` bit for bit
//! (see [`progressive`]).

pub mod catalog;
pub mod progressive;

use std::cell::RefCell;

use picomis::RenderSettings;
use picomis_format::{IntegratorDesc, SceneFile};

use crate::catalog::{LIGHT_SELECTION, LOBE_MIXING, METHODS, SCENES, SPHERE_SAMPLING};
use crate::progressive::{Progressive, colorbar};

/// What the page asks for: indices into the [`catalog`] lists and the numbers.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Request {
    /// Index into [`SCENES`].
    pub scene: u32,
    /// Index into [`METHODS`].
    pub method: u32,
    /// Power-heuristic exponent (used by `power`).
    pub beta: f32,
    /// Cutoff threshold (used by `cutoff`).
    pub alpha: f32,
    /// Light samples per camera sample.
    pub light_samples: u32,
    /// BSDF samples per camera sample.
    pub bsdf_samples: u32,
    /// Index into [`SPHERE_SAMPLING`].
    pub spheres: u32,
    /// Index into [`LOBE_MIXING`].
    pub lobe: u32,
    /// Index into [`LIGHT_SELECTION`].
    pub selection: u32,
    /// Seed.
    pub seed: u32,
}

impl Request {
    /// The scene file and kernel settings, or why not (an unknown index, invalid numbers): the
    /// page's choices as keys of the integrator block ([`IntegratorDesc`], the type the scene
    /// file and the command line use) over the scene file's own block.
    pub fn resolve(&self) -> Result<(SceneFile, RenderSettings), String> {
        let pick = |i: u32, len: usize, what: &str| {
            usize::try_from(i).ok().filter(|&i| i < len).ok_or_else(|| format!("no {what} number {i}"))
        };
        let b = SCENES[pick(self.scene, SCENES.len(), "scene")?];
        let file = SceneFile::parse(b.json, b.name).map_err(|e| e.to_string())?;
        let method = catalog::method(pick(self.method, METHODS.len(), "method")?, self.beta, self.alpha)?;
        let count =
            |n: u32, what: &str| u16::try_from(n).map_err(|_| format!("{n} {what} samples: too many"));
        let keys = IntegratorDesc {
            mis: Some(method),
            beta: method.beta(),
            alpha: method.alpha(),
            light_samples: Some(count(self.light_samples, "light")?),
            bsdf_samples: Some(count(self.bsdf_samples, "BSDF")?),
            sphere_sampling: Some(
                SPHERE_SAMPLING[pick(self.spheres, SPHERE_SAMPLING.len(), "sphere sampling")?],
            ),
            light_selection: Some(
                LIGHT_SELECTION[pick(self.selection, LIGHT_SELECTION.len(), "light selection")?],
            ),
            lobe_mixing: Some(LOBE_MIXING[pick(self.lobe, LOBE_MIXING.len(), "lobe mixing")?]),
            ..IntegratorDesc::default()
        };
        let settings = keys.over(file.integrator()).settings(1, self.seed).map_err(|e| e.to_string())?;
        Ok((file, settings))
    }
}

#[derive(Default)]
struct State {
    info: Vec<u8>,
    message: Vec<u8>,
    render: Option<Progressive>,
    radiance: Vec<f32>,
    colorbar: Vec<u8>,
}

thread_local! {
    static STATE: RefCell<State> = RefCell::new(State::default());
}

fn with<T>(f: impl FnOnce(&mut State) -> T) -> T {
    STATE.with(|s| f(&mut s.borrow_mut()))
}

fn offset<T>(v: &[T]) -> u32 {
    v.as_ptr() as usize as u32
}

fn byte_len<T>(v: &[T]) -> u32 {
    std::mem::size_of_val(v) as u32
}

/// Offset of the info JSON.
#[unsafe(no_mangle)]
pub extern "C" fn info_ptr() -> u32 {
    with(|s| {
        if s.info.is_empty() {
            s.info = catalog::info().to_string().into_bytes();
        }
        offset(&s.info)
    })
}

/// Length of the info JSON in bytes (call [`info_ptr`] first).
#[unsafe(no_mangle)]
pub extern "C" fn info_len() -> u32 {
    with(|s| byte_len(&s.info))
}

/// Starts a render (see the crate docs); 0 on success, 1 with a message otherwise.
#[unsafe(no_mangle)]
#[allow(clippy::too_many_arguments)]
pub extern "C" fn setup(
    scene: u32,
    method: u32,
    beta: f32,
    alpha: f32,
    light_samples: u32,
    bsdf_samples: u32,
    spheres: u32,
    lobe: u32,
    selection: u32,
    seed: u32,
) -> u32 {
    let request =
        Request { scene, method, beta, alpha, light_samples, bsdf_samples, spheres, lobe, selection, seed };
    let result = request.resolve().and_then(|(file, settings)| Progressive::new(&file, settings));
    with(|s| match result {
        Ok(p) => {
            s.render = Some(p);
            s.message.clear();
            0
        }
        Err(e) => {
            s.render = None;
            s.message = e.into_bytes();
            1
        }
    })
}

/// Offset of the last error message.
#[unsafe(no_mangle)]
pub extern "C" fn message_ptr() -> u32 {
    with(|s| offset(&s.message))
}

/// Length of the last error message in bytes.
#[unsafe(no_mangle)]
pub extern "C" fn message_len() -> u32 {
    with(|s| byte_len(&s.message))
}

/// Adds `k` camera samples per pixel; returns how many were added (0 without a render).
#[unsafe(no_mangle)]
pub extern "C" fn add_samples(k: u32) -> u32 {
    with(|s| s.render.as_mut().map_or(0, |r| r.add_samples(k)))
}

/// Tone-maps the current estimate into the RGBA images; returns their offset.
#[unsafe(no_mangle)]
pub extern "C" fn update() -> u32 {
    with(|s| {
        s.render.as_mut().map_or(0, |r| {
            r.update_rgba();
            offset(r.rgba())
        })
    })
}

/// Offset of the RGBA images.
#[unsafe(no_mangle)]
pub extern "C" fn rgba_ptr() -> u32 {
    with(|s| s.render.as_ref().map_or(0, |r| offset(r.rgba())))
}

/// Length of the RGBA images in bytes.
#[unsafe(no_mangle)]
pub extern "C" fn rgba_len() -> u32 {
    with(|s| s.render.as_ref().map_or(0, |r| byte_len(r.rgba())))
}

/// Film width.
#[unsafe(no_mangle)]
pub extern "C" fn width() -> u32 {
    with(|s| s.render.as_ref().map_or(0, Progressive::width))
}

/// Film height.
#[unsafe(no_mangle)]
pub extern "C" fn height() -> u32 {
    with(|s| s.render.as_ref().map_or(0, Progressive::height))
}

/// Camera samples per pixel so far.
#[unsafe(no_mangle)]
pub extern "C" fn spp() -> u32 {
    with(|s| s.render.as_ref().map_or(0, Progressive::spp))
}

/// Computes the linear radiance; returns its offset.
#[unsafe(no_mangle)]
pub extern "C" fn radiance_ptr() -> u32 {
    with(|s| {
        s.radiance = s.render.as_ref().map(Progressive::radiance).unwrap_or_default();
        offset(&s.radiance)
    })
}

/// Length of the radiance in bytes (call [`radiance_ptr`] first).
#[unsafe(no_mangle)]
pub extern "C" fn radiance_len() -> u32 {
    with(|s| byte_len(&s.radiance))
}

/// The weight colour bar, `width` + 1 RGBA pixels (see [`colorbar`]); returns its offset.
#[unsafe(no_mangle)]
pub extern "C" fn colorbar_ptr(width: u32) -> u32 {
    with(|s| {
        s.colorbar = colorbar(width.min(4096));
        offset(&s.colorbar)
    })
}
