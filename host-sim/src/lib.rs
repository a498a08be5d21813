//! # picomis-sim
//!
//! The host side of picomis: renders `picomis-scene/1` files (or the built-in scenes) with the
//! `no_std` kernel on all cores, writes PNG, EXR, PFM or raw RGB565 images, and draws the
//! lecture's MIS figure (Veach and Guibas 1995). The binary `picomis-sim` is a thin command line over this library.
//!
//! Every pixel is the kernel's `render_pixel` of the estimator for the render's settings
//! ([`picomis_host::renderer`]), whose random numbers depend only on the seed, the pixel and the
//! camera sample: images do not depend on the number of threads.
//!
//! ```text
//! picomis-sim scenes                                   # the built-in scenes, one line each
//! picomis-sim render                                   # the Veach scene -> veach_mis.png
//! picomis-sim render box_quad --spp 256 --mis balance --out box.exr
//! picomis-sim render my_scene.json --width 640 --light-samples 2 --seed 7 --out my.pfm
//! picomis-sim render lambert_sphere --out fb.rgb565    # bytes of an RGB565 LE framebuffer
//! picomis-sim render veach_mis -j 1 --pixel 191,127    # one pixel's estimate, split by technique
//! picomis-sim figure --spp 32                          # the lecture's MIS figure -> veach_mis_figure.png
//! picomis-sim serve                                    # the browser page (built in) at http://127.0.0.1:8000/
//! ```
//!
//! Every scene, built-in or file, is built as the host's one scene type ([`scenes::HostScene`]:
//! [`scenes::HOST_SHAPES`] shapes, [`scenes::HOST_LIGHTS`] lights and [`scenes::HOST_MATERIALS`]
//! materials). Bad scene files and flag values print
//! `error: <file>: <entry>: <reason>` (or `error: <flag>: <reason>`) and exit with code 2, and
//! so does a render whose buffers would not fit in memory ([`memory`]), before it allocates.
#![deny(missing_docs)]

pub mod cli;
pub mod figure;
pub mod integrator;
pub mod interop;
pub mod memory;
pub mod output;
pub mod page;
pub mod pixel;
pub mod render;
pub mod scenes;
pub mod serve;
pub mod study;
pub mod text;
pub mod view;

use std::fmt;

use picomis_format::LoadError;

/// Why a command failed.
#[derive(Debug)]
pub enum SimError {
    /// A scene file is bad: printed as `file: entry: reason`.
    Load(LoadError),
    /// A bad command-line value.
    Usage(String),
    /// Writing the result failed.
    Io(String),
}

impl SimError {
    /// The process exit code: 2 for bad input (scene files and command-line values, like clap's
    /// usage errors), 1 when the output could not be written.
    pub fn exit_code(&self) -> i32 {
        match self {
            SimError::Load(_) | SimError::Usage(_) => 2,
            SimError::Io(_) => 1,
        }
    }
}

impl fmt::Display for SimError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SimError::Load(e) => write!(f, "{e}"),
            SimError::Usage(m) | SimError::Io(m) => f.write_str(m),
        }
    }
}

impl std::error::Error for SimError {}

impl From<LoadError> for SimError {
    fn from(e: LoadError) -> Self {
        SimError::Load(e)
    }
}
