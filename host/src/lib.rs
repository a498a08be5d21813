//! # picomis-host
//!
//! What every host program of picomis shares (the simulator, the browser page, the benchmarks
//! and the test suites), and what a microcontroller never needs:
//! - [`render`]: the estimator for any render's settings, monomorphised for their strategies
//!   and matched once per render ([`renderer`]), in the host's one scene type ([`HostScene`]);
//! - [`study`]: the methods of the speed-against-accuracy study, the one list of them;
//! - [`colormap`]: the colour map of the MIS weight images.
#![deny(missing_docs)]

pub mod colormap;
pub mod render;
pub mod study;

pub use colormap::{NO_LIGHT, weight_color};
pub use render::{HOST_LIGHTS, HOST_MATERIALS, HOST_SHAPES, HostScene, Renderer, renderer};
