//! Ray queries over a scene's shapes, and what makes them fast: shapes four to a SIMD packet on
//! hosts (`accel.rs`), the objects a camera ray through a tile of the film can hit
//! (`camera_cull.rs`), the objects that can block a shadow ray from a receiver to a light
//! (`shadow_cull.rs`), and the same queries in fixed point for cores without an FPU (`fixed.rs`,
//! feature `fixed`, in the arithmetic `arith.rs` names). Every query gives the answer of the
//! plain loop over all shapes, bit for bit.

pub(crate) mod accel;
mod arith;
pub(crate) mod camera_cull;
#[cfg(feature = "fixed")]
pub(crate) mod fixed;
pub(crate) mod shadow_cull;

pub use arith::Arith;
