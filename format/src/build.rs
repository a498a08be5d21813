//! For a firmware's build script: a `picomis-scene/1` file turned into a Rust module that holds
//! the scene built on the host (its image, loaded in place on the device), the integrator's
//! settings as constants and the strategy types its integrator block names, so the firmware
//! carries only the code its scene uses.
//!
//! The firmware's `Cargo.toml` has `picomis` as a dependency and `picomis-format` as a
//! build-dependency; its `build.rs`:
//!
//! ```no_run
//! // build.rs: the scene for a 240 x 240 display, into OUT_DIR/picomis_scene.rs.
//! let firmware = picomis_format::build::Firmware::new("scene.json", 240, 240);
//! if let Err(e) = firmware.generate() {
//!     // One line naming the file, the entry and the reason; the build stops.
//!     panic!("{e}");
//! }
//! ```
//!
//! The fields choose more (`Firmware { spp: Some(4), ..Firmware::new(...) }`): a preset instead
//! of the file's integrator block, the samples per pixel, the seed, the module's file name.
//!
//! The firmware (`no_std`) includes the module, loads the scene into a `static` and draws it
//! into any `embedded-graphics` `DrawTarget` whose colour converts from `Rgb888`:
//!
//! ```ignore
//! // main.rs (no_std): the generated module only exists in a build script's OUT_DIR.
//! mod scene {
//!     include!(concat!(env!("OUT_DIR"), "/picomis_scene.rs"));
//! }
//! static mut SCENE: scene::SceneT = scene::SceneT::EMPTY;
//! // ...
//! let scene = unsafe { &mut *core::ptr::addr_of_mut!(SCENE) };
//! scene::load(scene)?;
//! let integrator = scene::integrator(scene)?;
//! integrator.render(Size::new(16, 16), &mut display, |_area, _stats| {})?;
//! ```
//!
//! The module ([`Firmware::module`]) holds: `NAME`; `SHAPES`, `LIGHTS`, `MATERIALS` (the scene's
//! counts, its capacities); `SceneT`; `IMAGE` (the scene built for the film, as words) and
//! `load(&mut SceneT)`; `Settings` (a `picomis::integrator::ConstSettings`) and `SETTINGS`;
//! `Strategies<C>`, `IntegratorT<'a>` and `integrator(&SceneT)`; and, to build the scene at run
//! time instead, `camera()`, `populate(&mut SceneT)` and `build(film)`.

use std::fmt::Write as _;
use std::path::PathBuf;

use picomis::{Film, Preset};

use crate::{IntegratorDesc, LoadError, SceneFile};

/// What a firmware's build script asks for: the generator of the scene module (see the
/// [module docs](self) for a `build.rs` and the firmware that uses the module).
#[derive(Clone, Debug, PartialEq)]
pub struct Firmware {
    /// The scene file.
    pub scene: PathBuf,
    /// The film (the display) the scene is built for.
    pub width: u32,
    /// Its height.
    pub height: u32,
    /// A preset's settings instead of the file's integrator block ([`SceneFile::with_integrator`]).
    pub preset: Option<Preset>,
    /// Camera samples per pixel (default: 1).
    pub spp: Option<u32>,
    /// The seed (default: 0).
    pub seed: Option<u32>,
    /// The module's file name in `OUT_DIR`.
    pub module_file: String,
}

/// The preset named by the environment variable `PICOMIS_PRESET` (`lecture`, `best`), for a
/// build script's [`Firmware::preset`]: `None` when it is unset or empty. Tells cargo to rerun the
/// build script when it changes. Any other name is an error that lists the presets.
pub fn preset_from_env() -> Result<Option<Preset>, String> {
    println!("cargo:rerun-if-env-changed=PICOMIS_PRESET");
    match std::env::var("PICOMIS_PRESET").ok().filter(|v| !v.trim().is_empty()) {
        Some(name) => Preset::from_name(name.trim()).map(Some).ok_or_else(|| {
            format!("PICOMIS_PRESET={name:?}: expected {}", picomis::choice::Names::<Preset>::of())
        }),
        None => Ok(None),
    }
}

impl Firmware {
    /// The scene file `scene` for a `width` x `height` display, its integrator block's settings
    /// at 1 spp, seed 0, into `OUT_DIR/picomis_scene.rs`.
    pub fn new(scene: impl Into<PathBuf>, width: u32, height: u32) -> Self {
        Firmware {
            scene: scene.into(),
            width,
            height,
            preset: None,
            spp: None,
            seed: None,
            module_file: "picomis_scene.rs".into(),
        }
    }

    /// Loads the scene file, writes the module into `OUT_DIR` and tells cargo to run the build
    /// script again when the file changes; returns the module's path.
    pub fn generate(&self) -> Result<PathBuf, LoadError> {
        let out = std::env::var_os("OUT_DIR")
            .map(PathBuf::from)
            .ok_or_else(|| self.error("OUT_DIR is not set (not in a build script?)"))?;
        println!("cargo:rerun-if-changed={}", self.scene.display());
        let module = self.module()?;
        let path = out.join(&self.module_file);
        std::fs::write(&path, module).map_err(|e| self.error(&format!("writing {}: {e}", path.display())))?;
        Ok(path)
    }

    /// The module's Rust source (see the module docs).
    pub fn module(&self) -> Result<String, LoadError> {
        let file = SceneFile::load(&self.scene)?;
        let file = match self.preset {
            Some(p) => {
                file.with_integrator(&IntegratorDesc { preset: Some(p), ..IntegratorDesc::default() })?
            }
            None => file,
        };
        let film = Film::new(self.width, self.height)
            .map_err(|e| self.error(&format!("film {}x{}: {e}", self.width, self.height)))?;
        let spp = self.spp.unwrap_or(1);
        if spp == 0 {
            return Err(self.error("spp: at least one sample per pixel"));
        }
        let mut o = file.to_rust();
        o += &file.image_rust(film)?;
        let seed = self.seed.unwrap_or(0);
        // `write!` into a String cannot fail.
        let _ = write!(
            o,
            "/// The integrator's settings ({spp} spp, seed {seed}), as constants.\n\
             pub struct Settings;\n\
             impl picomis::integrator::ConstSettings for Settings {{\n    \
             const SETTINGS: picomis::RenderSettings = match settings() {{\n        \
             Ok(s) => match s.with_spp({spp}) {{\n            \
             Ok(s) => s.with_seed({seed}),\n            \
             Err(_) => panic!(\"spp\"),\n        \
             }},\n        \
             Err(_) => panic!(\"the scene file's integrator block was checked when it was loaded\"),\n    \
             }};\n\
             }}\n\
             /// The settings, in flash.\n\
             pub static SETTINGS: picomis::RenderSettings = <Settings as picomis::integrator::ConstSettings>::SETTINGS;\n\
             /// The estimator of the scene, with the strategies and settings of its file.\n\
             pub type IntegratorT<'a> = picomis::Integrator<'a, Strategies<Settings>, SHAPES, LIGHTS, MATERIALS>;\n\
             /// Fills `scene` (in place: a `static` that starts as `SceneT::EMPTY`) from [`IMAGE`].\n\
             pub fn load(scene: &mut SceneT) -> Result<(), picomis::SceneError> {{\n    \
             scene.load_image(&IMAGE)\n\
             }}\n\
             /// The estimator of `scene` (loaded by [`load`]) with [`SETTINGS`].\n\
             pub fn integrator(scene: &SceneT) -> Result<IntegratorT<'_>, picomis::SceneError> {{\n    \
             IntegratorT::new(scene, &SETTINGS)\n\
             }}\n"
        );
        Ok(o)
    }

    fn error(&self, reason: &str) -> LoadError {
        LoadError { file: self.scene.display().to_string(), entry: "build".into(), reason: reason.into() }
    }
}
