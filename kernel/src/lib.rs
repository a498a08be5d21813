//! # picomis
//!
//! Direct lighting with Multiple Importance Sampling (Veach and Guibas 1995) for small scenes in
//! static memory: `no_std`, no allocation, f32 only, no panics on user data. The same kernel
//! renders on a microcontroller (Cortex-M4F, Cortex-M0, RISC-V RV32IMC), on a desktop and in a
//! browser, with the same bits everywhere, and draws into any `embedded-graphics`
//! [`DrawTarget`](embedded_graphics_core::draw_target::DrawTarget).
//!
//! A camera ray finds a surface point x; its reflected radiance
//! L_r(x, wo) = integral of L_e f_r cos(theta_i) dwi is estimated with two techniques, light
//! sampling (a point on a light, converted to solid angle) and BSDF sampling (a direction from
//! the BSDF, traced to a light), combined with MIS weights w_i = heuristic(n_i p_i):
//! F = sum_i 1/n_i sum_j w_i f / p_i.
//!
//! ## A scene, its settings, the estimator
//!
//! A [`Scene`] has fixed capacities (`S` shapes, `L` lights, `M` materials, const generics);
//! every value is checked as it is added, and a full scene is an error, never a panic.
//! [`RenderSettings`] start from a [`Preset`]. The strategies of a render (how a light is
//! chosen, how spheres and quads are sampled, ...) are types, bundled in [`Direct`]: the
//! [`Integrator`] is compiled for them only, and [`Integrator::new`] checks that the settings
//! name the same ones.
//!
//! ```
//! use picomis::integrator::{control_variate, model};
//! use picomis::light::{lobe, quad, select, sphere};
//! use picomis::*;
//!
//! // The strategies of `Preset::Best` for scenes of at most L lights.
//! type Best<const L: usize> = Direct<
//!     Lights<select::Every, sphere::InCone, quad::BySize, lobe::On>,
//!     control_variate::BySize,
//!     model::Multi,
//! >;
//!
//! # fn main() -> Result<(), SceneError> {
//! let camera = CameraDesc {
//!     origin: Vec3::new(0.0, 1.0, 4.0),
//!     target: Vec3::ZERO,
//!     up: Vec3::Y,
//!     fov_deg: 40.0,
//!     fov_axis: FovAxis::Y,
//!     near_clip: 0.0,
//! };
//! // Capacities: 2 shapes, 1 light, 2 materials.
//! let mut scene: Scene<2, 1, 2> = Scene::new(camera, Film::new(32, 24)?)?;
//! let white = scene.add_material(Material::lambertian(Rgb::splat(0.8))?)?;
//! let black = scene.add_material(Material::lambertian(Rgb::ZERO)?)?;
//! let floor = [
//!     Vec3::new(-2.0, 0.0, 2.0),
//!     Vec3::new(2.0, 0.0, 2.0),
//!     Vec3::new(2.0, 0.0, -2.0),
//!     Vec3::new(-2.0, 0.0, -2.0),
//! ];
//! scene.add_shape(Shape::quad(floor)?, white)?;
//! let bulb = scene.add_shape(Shape::sphere(Vec3::new(0.0, 1.5, 0.0), 0.25)?, black)?;
//! scene.add_area_light(bulb, Rgb::splat(10.0))?;
//!
//! // The power heuristic, one light and one BSDF sample, 4 samples per pixel, seed 7.
//! let settings = Preset::Best.settings().with_spp(4)?.with_seed(7);
//! let integrator = Integrator::<Best<1>, 2, 1, 2>::new(&scene, &settings)?;
//! let pixel = integrator.render_pixel(16, 20);
//! assert!(pixel.radiance().is_finite());
//! let srgb = tone_map(pixel.radiance()); // an `Rgb888` for a display
//! # let _ = srgb;
//! # Ok(())
//! # }
//! ```
//!
//! [`Integrator::render`] draws the whole film tile by tile into a `DrawTarget` whose colour
//! converts from `Rgb888` (such as `Rgb565`), passing the display's error through;
//! [`Integrator::render_tile`] draws one rectangle. The crate's `examples/` render a scene as
//! ASCII art (`ascii.rs`) and into a `DrawTarget` written as a PPM image (`ppm.rs`).
//!
//! ## On a microcontroller
//!
//! A scene is built and checked once, on the host: [`Scene::write_image`] writes it as 32-bit
//! words, and the device fills a `static` scene that starts as [`Scene::EMPTY`] with
//! [`Scene::load_image`], without the code that validates values. Settings fixed at compile
//! time ([`integrator::ConstSettings`]) fold into the code. The crate `picomis-format` does all
//! of this from a `picomis-scene/1` JSON file in a `build.rs`
//! (`picomis_format::build::Firmware`).
//!
//! ## Cargo features
//!
//! - `defmt`: `defmt::Format` for the settings and their options, the errors, the render
//!   statistics, the film and the scene's ids (and `heapless`'s and `embedded-graphics-core`'s
//!   `defmt` support).
//! - `fixed`: ray queries in fixed point ([`Arith::Fixed`], turned on per scene with
//!   `Scene::enable_arith`) for cores without an FPU. Off by default: without it a build
//!   contains none of its code and the [`Scene`] no RAM for it.
//!
//! Neither is on by default. The kernel needs Rust 1.87 or newer.
//!
//! ## Modules
//!
//! | module | what |
//! |---|---|
//! | [`scene`] | the scene in fixed-capacity storage: shapes, materials, lights; its ray queries |
//! | [`geometry`] | shapes, rays, surface points, the pinhole camera and its film |
//! | [`integrator`] | settings and presets, MIS weights and models, the estimator, the strategy bundle |
//! | [`light`] | light sampling: light selection, sphere and quad sampling, lobe mixing |
//! | [`sampling`] | every sampling routine with its pdf, and the sample streams |
//! | [`output`] | rendering into a `DrawTarget`, tone mapping, a digest of an image's estimates |
//! | [`num`] | the math backend: vectors, frames, f32 helpers |
//! | [`choice`] | the closed sets of named options (strategies, methods) and their names |
//! | [`error`] | the typed errors of scene and settings construction |
#![cfg_attr(not(test), no_std)]
#![cfg_attr(docsrs, feature(doc_cfg))]
#![deny(missing_docs, unsafe_code)]
#![deny(rustdoc::broken_intra_doc_links)]
// `!(x > 0.0)` is used on purpose throughout: unlike `x <= 0.0` it also rejects NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod choice;
pub mod error;
pub mod geometry;
pub mod integrator;
pub mod light;
pub mod num;
pub mod output;
// Ray-query acceleration (SIMD packets, culling, fixed point): internal; its one public type,
// `Arith`, is re-exported below.
mod query;
pub mod sampling;
pub mod scene;
mod words;

pub use choice::Choice;
#[cfg(feature = "fixed")]
#[cfg_attr(docsrs, doc(cfg(feature = "fixed")))]
pub use error::Unrepresentable;
pub use error::{Collection, Field, SceneError};
pub use geometry::{Camera, CameraDesc, Film, FovAxis, Ray, Shape, SurfacePoint};
pub use integrator::{
    ControlVariate, Direct, Estimate, Heuristic, Integrator, MAX_CONTRIBUTION, Method, MisModel, Preset,
    RenderSettings, Shading, Strategies, Technique, TechniqueEstimate, dispatch,
};
pub use light::{
    LightChoice, LightSample, LightSampler, LightSelection, Lights, LobeMixing, QuadSampling, ShadingPoint,
    SphereSampling,
};
pub use num::{Rgb, Vec2, Vec3};
pub use output::{Digest, PIXEL_SUM_BLOCK, PixelSum, RenderStats, film_rect, render_digest, tiles, tone_map};
pub use query::Arith;
pub use sampling::{Sampler, SamplerKind};
pub use scene::{
    BsdfSample, Emission, Hit, Light, LightId, MAX_EMISSION, Material, MaterialId, Object, Scene, ShapeId,
};

// The README's examples are compiled and run as doctests.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeDoctests;
