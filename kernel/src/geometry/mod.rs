//! Geometry: the shapes (quads and spheres), rays and surface points, and the pinhole camera
//! with its film.

mod camera;
mod shape;

pub use camera::*;
pub use shape::*;
