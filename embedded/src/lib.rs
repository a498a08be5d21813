//! # picomis-embedded
//!
//! The [picomis](https://docs.rs/picomis) kernel on a microcontroller, in the two steps every
//! firmware takes: the scene that `picomis_format::build::Firmware` generated in the build
//! script is loaded once into static memory ([`SceneSlot`]), and the film is drawn tile by tile
//! into any `embedded-graphics` display or framebuffer ([`draw`]), with progress after each row
//! of tiles. The picomis QEMU firmware and the board examples (`boards/` in the repository) both
//! run on it.
//!
//! ```ignore
//! // build.rs: picomis_format::build::Firmware::new("scene.json", 240, 240).generate()?;
//! mod scene {
//!     include!(concat!(env!("OUT_DIR"), "/picomis_scene.rs"));
//! }
//! static SCENE: picomis_embedded::SceneSlot<scene::SceneT> = picomis_embedded::SceneSlot::new();
//!
//! let scene = SCENE.load(scene::load)?;
//! let integrator = scene::integrator(scene)?;
//! let tile = Size::new(16, 16);
//! let stats = picomis_embedded::draw(&integrator, tile, &mut display, |_progress| {})?;
//! ```
//!
//! ## Cargo features
//!
//! - `defmt`: [`draw`] logs each row of tiles with `defmt::debug!` (shown when `DEFMT_LOG` is
//!   `debug` or `trace`), and the errors implement `defmt::Format` (the kernel's `defmt` too).
//! - `fixed`: [`SceneSlot::load`] turns on the kernel's fixed-point ray queries
//!   (`picomis::Arith::Fixed`, the kernel's `fixed` feature) for cores without an FPU.
#![no_std]
#![deny(missing_docs)]

#[cfg(test)]
extern crate std;

mod draw;
mod slot;

pub use draw::{Progress, draw};
pub use slot::{LoadError, SceneSlot};
