//! What a render produces: pixels through any `embedded-graphics` `DrawTarget` (`render.rs`),
//! tone-mapped to sRGB (`tonemap.rs`), and a digest of the HDR estimates that two machines can
//! compare (`digest.rs`).

mod digest;
mod render;
mod tonemap;

pub use digest::{Digest, render_digest};
pub use render::{RenderStats, film_rect, tiles};
pub use tonemap::tone_map;
