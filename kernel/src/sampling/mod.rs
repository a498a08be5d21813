//! Every sampling routine with its pdf, as `sample_x` / `x_pdf` pairs, and the random numbers
//! they take ([`Sampler`]). Random numbers come in as `u`; directions are in a local frame whose
//! `z` axis is the normal (or the cone axis). Pdfs are per unit solid angle for directions and
//! per unit area for points.
//!
//! | file | what |
//! |---|---|
//! | `warp.rs` | disk, hemisphere, sphere, cone, parallelogram; linear and bilinear warps |
//! | `rectangle.rs` | spherical rectangles (Ureña et al. 2013) and their cosine warp (Hart et al. 2020) |
//! | `ggx.rs` | GGX D, G1 and visible normals |
//! | `slope_box.rs` | GGX slopes restricted to a box that reflects towards a light (lobe mixing) |
//! | `discrete.rs` | uniform and tabulated discrete distributions |
//! | `sampler.rs` | the sample streams: padded Owen-scrambled Sobol and independent numbers |

mod discrete;
mod ggx;
mod rectangle;
pub mod sampler;
mod slope_box;
mod warp;

pub use discrete::*;
pub use ggx::*;
pub use rectangle::*;
pub use sampler::{Sampler, SamplerKind};
pub use slope_box::*;
pub use warp::*;
