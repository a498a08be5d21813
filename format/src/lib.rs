//! # picomis-format
//!
//! The `picomis-scene/1` JSON scene format of the [`picomis`] renderer (specified in `FORMAT.md`,
//! in this package): strict loading with errors that name the file, the entry and the reason;
//! kernel scenes of any capacity; and Rust source for a firmware's build script ([`build`]), so a
//! microcontroller gets the same scene, bit for bit.
//!
//! Loading goes in two steps. [`SceneFile::parse`] deserializes strictly (unknown keys and wrong
//! types are errors) and lowers the file into a list of validated kernel values. Both
//! [`SceneFile::build`] and [`SceneFile::to_rust`] then replay that one list, so the host and the
//! firmware add the same materials, shapes and lights in the same order with the same f32 bits.
//!
//! ```no_run
//! use picomis_format::SceneFile;
//!
//! # fn main() -> Result<(), picomis_format::LoadError> {
//! let file = SceneFile::load(std::path::Path::new("scene.json"))?;
//! let counts = file.counts(); // the capacities the kernel scene needs
//! // A scene with room for 16 shapes, 4 lights and 8 materials, and the file's settings.
//! let scene = file.build::<16, 4, 8>()?;
//! let settings = file.default_settings();
//! # let _ = (counts, scene, settings);
//! # Ok(())
//! # }
//! ```
//!
//! For a firmware, [`build::Firmware`] does it all in `build.rs`: the scene built and checked on
//! the host, as an image the device loads in place, its settings as constants and the strategy
//! types they name.
//!
//! ## Cargo features
//!
//! - `cli`: [`IntegratorDesc`] as a `clap` argument group (`#[command(flatten)]`), with the
//!   integrator block's keys as flags.
#![cfg_attr(docsrs, feature(doc_cfg))]
#![deny(missing_docs)]

pub mod build;
mod catalog;
mod codegen;
mod desc;
mod integrator;
pub mod mitsuba;

use std::fmt;
use std::path::Path;

// Public for the build script of the workspace's built-in scene list (picomis-builtins); not API.
#[doc(hidden)]
pub use catalog::builtins_rust;
pub use codegen::firmware_settings;
#[cfg(feature = "cli")]
#[cfg_attr(docsrs, doc(cfg(feature = "cli")))]
pub use integrator::choice_parser;
pub use integrator::{IntegratorDesc, IntegratorType, KeyError};

use picomis::{
    Camera, CameraDesc, Collection, Film, Material, RenderSettings, Rgb, Scene, SceneError, Shape, Vec3,
};

/// Why a scene file could not be loaded: which file, which entry, and why.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LoadError {
    /// The file (a path or a built-in scene's name).
    pub file: String,
    /// The entry, e.g. `shapes[3] "plate1"` or `materials.floor`.
    pub entry: String,
    /// What is wrong.
    pub reason: String,
}

impl fmt::Display for LoadError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}: {}", self.file, self.entry, self.reason)
    }
}

impl std::error::Error for LoadError {}

/// How many of each object a scene holds: the kernel capacities it needs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Counts {
    /// Shapes (emitting or not).
    pub shapes: usize,
    /// Lights: area emitters plus point lights.
    pub lights: usize,
    /// Materials.
    pub materials: usize,
}

/// Geometry of a shape as written in the file.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Geometry {
    Sphere { center: Vec3, radius: f32 },
    Quad([Vec3; 4]),
}

impl Geometry {
    pub(crate) fn shape(&self) -> Result<Shape, SceneError> {
        match *self {
            Geometry::Sphere { center, radius } => Shape::sphere(center, radius),
            Geometry::Quad(p) => Shape::quad(p),
        }
    }
}

/// One validated step of building the scene, in order.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Step {
    Material(Material),
    Shape { entry: String, geometry: Geometry, material: usize, emitter: Option<Rgb> },
    PointLight { entry: String, position: Vec3, intensity: Rgb },
}

/// A parsed and fully validated `picomis-scene/1` file.
#[derive(Clone, Debug)]
pub struct SceneFile {
    file: String,
    name: String,
    description: String,
    film: Film,
    camera: CameraDesc,
    integrator: IntegratorDesc,
    steps: Vec<Step>,
    counts: Counts,
}

/// The shapes a scene built for its image may hold ([`SceneFile::image`]).
pub const IMAGE_SHAPES: usize = 128;
/// The lights a scene built for its image may hold.
pub const IMAGE_LIGHTS: usize = 64;
/// The materials a scene built for its image may hold.
pub const IMAGE_MATERIALS: usize = 64;

/// Largest scene file read, in bytes (scenes are small; this bounds memory on hostile input).
pub const MAX_FILE_BYTES: u64 = 4 << 20;

/// The file at `path` as it is named in errors, and its text: at most [`MAX_FILE_BYTES`] long,
/// UTF-8 (the scene file and the Mitsuba XML file readers).
pub(crate) fn read_bounded(path: &Path) -> Result<(String, String), LoadError> {
    let file = path.display().to_string();
    let err = |reason: String| LoadError { file: file.clone(), entry: "file".into(), reason };
    let meta = std::fs::metadata(path).map_err(|e| err(e.to_string()))?;
    if meta.len() > MAX_FILE_BYTES {
        return Err(err(format!("larger than {MAX_FILE_BYTES} bytes")));
    }
    let text = std::fs::read_to_string(path).map_err(|e| err(e.to_string()))?;
    Ok((file, text))
}

impl SceneFile {
    /// The entry (e.g. `shapes[1] "sphere_light"`) of the kernel's shape `index` (shapes are
    /// added in the file's order), to name it in an error the kernel reports by index.
    pub fn shape_entry(&self, index: usize) -> Option<&str> {
        let mut shapes = self.steps.iter().filter_map(|s| match s {
            Step::Shape { entry, .. } => Some(entry.as_str()),
            _ => None,
        });
        shapes.nth(index)
    }

    /// Parses and validates a scene; `file` names it in errors.
    pub fn parse(text: &str, file: &str) -> Result<Self, LoadError> {
        desc::lower(text, file)
    }

    /// Reads, parses and validates a scene file.
    pub fn load(path: &Path) -> Result<Self, LoadError> {
        let (file, text) = read_bounded(path)?;
        Self::parse(&text, &file)
    }

    /// The scene's name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The scene's description.
    pub fn description(&self) -> &str {
        &self.description
    }

    /// The file this scene came from.
    pub fn file(&self) -> &str {
        &self.file
    }

    /// Object counts: the capacities a kernel scene needs to hold this file.
    pub fn counts(&self) -> Counts {
        self.counts
    }

    /// The film of the file.
    pub fn film(&self) -> Film {
        self.film
    }

    /// The camera of the file.
    pub fn camera(&self) -> CameraDesc {
        self.camera
    }

    /// Builds the kernel scene with capacities `S` shapes, `L` lights, `M` materials.
    pub fn build<const S: usize, const L: usize, const M: usize>(&self) -> Result<Scene<S, L, M>, LoadError> {
        self.build_with_film(self.film)
    }

    /// Builds the kernel scene for another film size.
    pub fn build_with_film<const S: usize, const L: usize, const M: usize>(
        &self,
        film: Film,
    ) -> Result<Scene<S, L, M>, LoadError> {
        let mut scene = Scene::new(self.camera, film).map_err(|e| self.error("camera", e))?;
        let mut materials = Vec::new();
        for (i, step) in self.steps.iter().enumerate() {
            match step {
                Step::Material(m) => {
                    let id =
                        scene.add_material(*m).map_err(|e| self.capacity(format!("materials[{i}]"), e, M))?;
                    materials.push(id);
                }
                Step::Shape { entry, geometry, material, emitter } => {
                    let shape = geometry.shape().map_err(|e| self.error(entry, e))?;
                    let &mat = materials
                        .get(*material)
                        .ok_or_else(|| self.error(entry, SceneError::UnknownMaterial))?;
                    let id = scene.add_shape(shape, mat).map_err(|e| self.capacity(entry.clone(), e, S))?;
                    if let Some(radiance) = emitter {
                        scene
                            .add_area_light(id, *radiance)
                            .map_err(|e| self.capacity(entry.clone(), e, L))?;
                    }
                }
                Step::PointLight { entry, position, intensity } => {
                    scene
                        .add_point_light(*position, *intensity)
                        .map_err(|e| self.capacity(entry.clone(), e, L))?;
                }
            }
        }
        Ok(scene)
    }

    /// The file's integrator block.
    pub fn integrator(&self) -> &IntegratorDesc {
        &self.integrator
    }

    /// The settings of the file's integrator block (1 spp, seed 0): from the best preset unless
    /// the block names another, with the block's keys.
    pub fn default_settings(&self) -> RenderSettings {
        // Checked when the file was loaded.
        self.integrator.settings(1, 0).unwrap_or_else(|_| picomis::Preset::Best.settings())
    }

    /// The same scene with `keys` over its integrator block ([`IntegratorDesc::over`]: a preset
    /// among them starts over from it), validated like the file's own block.
    pub fn with_integrator(&self, keys: &IntegratorDesc) -> Result<SceneFile, LoadError> {
        let integrator = keys.over(&self.integrator);
        integrator.settings(1, 0).map_err(|e| LoadError {
            file: self.file.clone(),
            entry: format!("integrator.{}", e.key),
            reason: e.reason,
        })?;
        Ok(SceneFile { integrator, ..self.clone() })
    }

    /// Whether the scene has a light of each kind: area lights on spheres, area lights on quads,
    /// point lights (a firmware build carries the code of the kinds it has only).
    pub fn light_kinds(&self) -> LightKinds {
        let mut kinds = LightKinds::default();
        for step in &self.steps {
            match step {
                Step::Shape { emitter: Some(_), geometry: Geometry::Sphere { .. }, .. } => {
                    kinds.spheres = true
                }
                Step::Shape { emitter: Some(_), geometry: Geometry::Quad(_), .. } => kinds.quads = true,
                Step::PointLight { .. } => kinds.points = true,
                _ => {}
            }
        }
        kinds
    }

    /// Whether the scene has a material of each kind.
    pub fn material_kinds(&self) -> MaterialKinds {
        let mut kinds = MaterialKinds::default();
        for step in &self.steps {
            let Step::Material(m) = step else { continue };
            match m {
                Material::Lambertian { .. } => kinds.lambertian = true,
                Material::GgxConductor { .. } => kinds.ggx = true,
            }
            kinds.quads_by_size |= picomis::light::quad::BySize::by_area_for(m);
        }
        kinds
    }

    /// Rust source of a module that builds this scene with its own capacities (see the crate
    /// docs): `SHAPES`, `LIGHTS`, `MATERIALS`, `NAME`, `WIDTH`, `HEIGHT`, `SceneT`, `camera()`,
    /// `populate(&mut SceneT)` (fills an empty scene in place), `build(film)` and `settings()`.
    pub fn to_rust(&self) -> String {
        codegen::module(self)
    }

    /// The scene built for `film`, as the words of its image (`picomis::Scene::write_image`):
    /// what a firmware loads with `Scene::load_image` instead of building it.
    pub fn image(&self, film: Film) -> Result<Vec<u32>, LoadError> {
        // Room for any scene a firmware holds: the image does not depend on the capacities.
        let scene = Box::new(self.build_with_film::<IMAGE_SHAPES, IMAGE_LIGHTS, IMAGE_MATERIALS>(film)?);
        let mut words = Vec::new();
        scene.write_image(&mut |w| words.push(w));
        Ok(words)
    }

    /// Rust source of `pub static IMAGE: [u32; N]`, the scene's image for `film`
    /// ([`SceneFile::image`]), to go with [`SceneFile::to_rust`]'s module.
    pub fn image_rust(&self, film: Film) -> Result<String, LoadError> {
        let words = self.image(film)?;
        let mut o = format!(
            "/// The scene built for a {}x{} film, as the words of its image (`Scene::load_image`).\n\
             pub static IMAGE: [u32; {}] = [",
            film.width(),
            film.height(),
            words.len()
        );
        for (i, w) in words.iter().enumerate() {
            if i % 8 == 0 {
                o.push_str("\n   ");
            }
            o.push_str(&format!(" {w:#010x},"));
        }
        o.push_str("\n];\n");
        Ok(o)
    }

    fn error(&self, entry: &str, e: SceneError) -> LoadError {
        LoadError { file: self.file.clone(), entry: entry.into(), reason: e.to_string() }
    }

    fn capacity(&self, entry: String, e: SceneError, capacity: usize) -> LoadError {
        let reason = match e {
            SceneError::CapacityExceeded(c) => {
                let what = match c {
                    Collection::Shapes => "shapes",
                    Collection::Lights => "lights",
                    Collection::Materials => "materials",
                };
                format!("too many {what} for this build (it holds {capacity})")
            }
            other => other.to_string(),
        };
        LoadError { file: self.file.clone(), entry, reason }
    }
}

/// Which kinds of lights a scene has ([`SceneFile::light_kinds`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LightKinds {
    /// Area lights on spheres.
    pub spheres: bool,
    /// Area lights on quads.
    pub quads: bool,
    /// Point lights.
    pub points: bool,
}

/// Which kinds of materials a scene has ([`SceneFile::material_kinds`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MaterialKinds {
    /// Lambertian.
    pub lambertian: bool,
    /// GGX conductor.
    pub ggx: bool,
    /// A material on which quad lights `by-size` differ from `auto`
    /// ([`picomis::light::quad::BySize::by_area_for`]).
    pub quads_by_size: bool,
}

/// Checks that a camera description is valid for a 1x1 film (used while lowering).
pub(crate) fn check_camera(camera: CameraDesc, film: Film) -> Result<(), SceneError> {
    Camera::new(camera, film).map(|_| ())
}

// The README's examples are compiled as doctests.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeDoctests;
