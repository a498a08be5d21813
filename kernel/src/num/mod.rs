//! The one place that chooses the math backend: glam vectors (scalar `Vec3`, no SIMD) and libm
//! functions, so the host and a microcontroller run the same f32 operations bit for bit.
//!
//! | file | what |
//! |---|---|
//! | `scalar.rs` | `Vec3`, `Rgb`, square roots, clamps and the other f32 helpers |
//! | `frame.rs` | orthonormal frames around a normal |
//! | `trig.rs` | sine and cosine as fixed-point polynomials |
//! | `dot3.rs` | the dot product (hand-written on RV32IMC) |
//! | `sqrt.rs` | the correctly rounded square root in integers (soft-float cores) |
//! | `wide.rs`, `int_m0.rs` | 32 x 32 -> 64-bit products and the Cortex-M0's integer routines |

pub(crate) mod dot3;
mod frame;
#[cfg(all(target_arch = "arm", target_os = "none", target_abi = "eabi"))]
pub(crate) mod int_m0;
mod scalar;
// The soft-float cores take their square root from here; its tests run on every target.
#[cfg_attr(not(all(target_os = "none", not(target_abi = "eabihf"))), allow(dead_code))]
pub(crate) mod sqrt;
mod trig;
pub(crate) mod wide;

pub use dot3::dot;
pub use frame::{Frame, from_local_around};
pub use scalar::*;
pub use trig::{sin_cos_eighths, sin_cos_turns};
