//! # picomis
//!
//! Direct lighting with Multiple Importance Sampling (Veach and Guibas 1995) for small scenes in
//! static memory: `no_std`, no allocation, f32 only, no panics on user data.
//!
//! A camera ray finds a surface point x; its reflected radiance
//! L_r(x, wo) = integral of L_e f_r cos(theta_i) dwi is estimated with two techniques, light
//! sampling (a point on a light, converted to solid angle) and BSDF sampling (a direction from
//! the BSDF, traced to a light), combined with MIS weights w_i = heuristic(n_i p_i):
//! F = sum_i 1/n_i sum_j w_i f / p_i.
//!
//! ```
//! use picomis::*;
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
//! let floor = [Vec3::new(-2., 0., 2.), Vec3::new(2., 0., 2.), Vec3::new(2., 0., -2.), Vec3::new(-2., 0., -2.)];
//! scene.add_shape(Shape::quad(floor)?, white)?;
//! let bulb = scene.add_shape(Shape::sphere(Vec3::new(0.0, 1.5, 0.0), 0.25)?, black)?;
//! scene.add_area_light(bulb, Rgb::splat(10.0))?;
//!
//! let settings = RenderSettings::new(Method::Mis(Heuristic::Balance), 1, 1, 4, 7)?;
//! let pixel = render_pixel(&scene, &settings, 16, 20);
//! assert!(pixel.radiance().is_finite());
//! # Ok(())
//! # }
//! ```
#![cfg_attr(not(test), no_std)]
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
pub mod query;
pub mod sampling;
pub mod scene;
mod words;

pub use choice::Choice;
#[cfg(feature = "fixed")]
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
pub use output::{Digest, RenderStats, film_rect, render_digest, tiles, tone_map};
pub use query::Arith;
pub use sampling::{Sampler, SamplerKind};
pub use scene::{
    BsdfSample, Emission, Hit, Light, LightId, MAX_EMISSION, Material, MaterialId, Object, Scene, ShapeId,
};
