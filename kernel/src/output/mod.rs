//! What a render produces: pixels through any `embedded-graphics` `DrawTarget` (`render.rs`), the
//! mean of a pixel's camera samples (`pixel_sum.rs`),
//! tone-mapped to sRGB (`tonemap.rs`), and a digest of the HDR estimates that two machines can
//! compare (`digest.rs`).

mod digest;
mod pixel_sum;
mod render;
mod tonemap;

pub use digest::{Digest, render_digest};
pub use pixel_sum::{PIXEL_SUM_BLOCK, PixelSum};
pub use render::{RenderStats, film_rect, tiles};
pub use tonemap::tone_map;
