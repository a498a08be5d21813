//! Text on an RGB canvas with an embedded font (DejaVu Sans, `assets/`, Bitstream Vera licence),
//! so figures look the same everywhere and need no system font lookup.

use ab_glyph::{Font, FontRef, PxScale, ScaleFont, point};

/// An 8-bit sRGB canvas, row-major.
#[derive(Clone, Debug, PartialEq)]
pub struct Canvas {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Pixels.
    pub data: Vec<[u8; 3]>,
}

impl Canvas {
    /// A canvas filled with `color`.
    pub fn new(width: u32, height: u32, color: [u8; 3]) -> Self {
        Self { width, height, data: vec![color; (width * height) as usize] }
    }

    /// Sets pixel `(x, y)` if it is on the canvas.
    pub fn put(&mut self, x: i64, y: i64, color: [u8; 3]) {
        if x >= 0 && y >= 0 && x < i64::from(self.width) && y < i64::from(self.height) {
            self.data[(y as u32 * self.width + x as u32) as usize] = color;
        }
    }

    /// Blends `color` over pixel `(x, y)` with coverage `a` in [0, 1].
    pub fn blend(&mut self, x: i64, y: i64, color: [u8; 3], a: f32) {
        if x >= 0 && y >= 0 && x < i64::from(self.width) && y < i64::from(self.height) {
            let p = &mut self.data[(y as u32 * self.width + x as u32) as usize];
            let a = a.clamp(0.0, 1.0);
            for (d, s) in p.iter_mut().zip(color) {
                *d = (f32::from(*d) * (1.0 - a) + f32::from(s) * a + 0.5) as u8;
            }
        }
    }

    /// Fills a rectangle.
    pub fn fill(&mut self, x: i64, y: i64, w: u32, h: u32, color: [u8; 3]) {
        for yy in y..y + i64::from(h) {
            for xx in x..x + i64::from(w) {
                self.put(xx, yy, color);
            }
        }
    }

    /// Copies `src` (w x h pixels) with its top-left corner at `(x, y)`.
    pub fn blit(&mut self, x: i64, y: i64, w: u32, h: u32, src: &[[u8; 3]]) {
        for yy in 0..h {
            for xx in 0..w {
                self.put(x + i64::from(xx), y + i64::from(yy), src[(yy * w + xx) as usize]);
            }
        }
    }

    /// The pixels as RGB bytes.
    pub fn bytes(&self) -> Vec<u8> {
        self.data.iter().flatten().copied().collect()
    }
}

static FONT_DATA: &[u8] = include_bytes!("../assets/DejaVuSans.ttf");

/// The embedded font.
pub fn font() -> FontRef<'static> {
    // The font is part of this crate, not user data: a broken asset is a build defect.
    FontRef::try_from_slice(FONT_DATA).expect("embedded DejaVuSans.ttf is a valid font")
}

/// Width in pixels of `text` at `size` pixels.
pub fn text_width(text: &str, size: f32) -> f32 {
    let font = font();
    let scaled = font.as_scaled(PxScale::from(size));
    let mut width = 0.0;
    let mut prev = None;
    for c in text.chars() {
        let id = scaled.glyph_id(c);
        if let Some(p) = prev {
            width += scaled.kern(p, id);
        }
        width += scaled.h_advance(id);
        prev = Some(id);
    }
    width
}

/// Draws `text` at `size` pixels with its top-left corner at `(x, y)`; returns its width.
pub fn draw_text(canvas: &mut Canvas, x: f32, y: f32, size: f32, text: &str, color: [u8; 3]) -> f32 {
    let font = font();
    let scaled = font.as_scaled(PxScale::from(size));
    let baseline = y + scaled.ascent();
    let mut caret = x;
    let mut prev = None;
    for c in text.chars() {
        let id = scaled.glyph_id(c);
        if let Some(p) = prev {
            caret += scaled.kern(p, id);
        }
        let glyph = id.with_scale_and_position(size, point(caret, baseline));
        caret += scaled.h_advance(id);
        prev = Some(id);
        if let Some(outline) = font.outline_glyph(glyph) {
            let b = outline.px_bounds();
            outline.draw(|gx, gy, coverage| {
                canvas.blend(b.min.x as i64 + i64::from(gx), b.min.y as i64 + i64::from(gy), color, coverage);
            });
        }
    }
    caret - x
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_renders_with_the_embedded_font() {
        let mut c = Canvas::new(120, 30, [255; 3]);
        let w = draw_text(&mut c, 2.0, 2.0, 20.0, "Balance", [0; 3]);
        assert!(w > 50.0 && w < 110.0, "{w}");
        assert!((w - text_width("Balance", 20.0)).abs() < 1e-3);
        let dark = c.data.iter().filter(|p| p[0] < 128).count();
        assert!(dark > 100, "only {dark} dark pixels: glyphs did not render");
    }
}
