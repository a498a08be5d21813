//! Geometry: the shapes (quads and spheres), rays and surface points, and the pinhole camera
//! with its film.

mod camera;
mod shape;
mod terms;

pub use camera::*;
pub use shape::*;
// (`FixedDir` is read by the microcontrollers' ray queries and the tests.)
#[cfg_attr(not(any(target_os = "none", test)), allow(unused_imports))]
pub(crate) use terms::{FixedDir, OriginTerms};
