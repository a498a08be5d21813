//! Image files: PNG (tone-mapped sRGB, for people), EXR and PFM (linear 32-bit float RGB, for
//! measurement) and raw RGB565 (the bytes of an embedded-graphics little-endian RGB565
//! framebuffer, for comparison with firmware). Images are encoded in memory and written to a
//! temporary file that is then renamed, so a failed or interrupted run never leaves a partial
//! image under the requested name.

use std::io::{Cursor, Write};
use std::path::{Path, PathBuf};

use embedded_graphics_core::pixelcolor::{IntoStorage, Rgb565, Rgb888, RgbColor};
use picomis::{Rgb, tone_map};

/// A linear-radiance RGB image, row-major, row 0 at the top.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Pixels.
    pub data: Vec<Rgb>,
}

impl Image {
    /// The pixel at `(x, y)`.
    pub fn get(&self, x: u32, y: u32) -> Rgb {
        self.data[(y * self.width + x) as usize]
    }
}

/// An output file format, chosen by the file's extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// `.png`: 8-bit sRGB through `picomis::tone_map`.
    Png,
    /// `.exr`: linear 32-bit float RGB.
    Exr,
    /// `.pfm`: linear 32-bit float RGB (Portable Float Map, little-endian, rows bottom-up).
    Pfm,
    /// `.rgb565`: raw little-endian RGB565, row-major, top row first.
    Rgb565,
}

impl Format {
    /// The format for `path`'s extension (case-insensitive).
    pub fn from_path(path: &Path) -> Result<Self, String> {
        let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
        match ext.as_str() {
            "png" => Ok(Format::Png),
            "exr" => Ok(Format::Exr),
            "pfm" => Ok(Format::Pfm),
            "rgb565" => Ok(Format::Rgb565),
            _ => Err(format!(
                "{}: unknown image format {ext:?} (use .png, .exr, .pfm or .rgb565)",
                path.display()
            )),
        }
    }

    /// An upper estimate of the bytes per pixel that encoding takes beyond the linear image:
    /// the file in memory (vectors that grow may hold twice their length) and the encoder's own
    /// buffers. For [`crate::memory`]'s check before a render.
    pub fn encoding_bytes_per_pixel(self) -> u64 {
        match self {
            // The 8-bit RGB pixels (3), the PNG file (at most about 3, twice while it grows).
            Format::Png => 3 + 2 * 3 + 1,
            // The file (12, twice while it grows) and the encoder's blocks (12).
            Format::Exr => 2 * 12 + 12,
            // The file, allocated at its size.
            Format::Pfm => 12,
            Format::Rgb565 => 2,
        }
    }
}

/// Encodes `image` in `format`.
pub fn encode(image: &Image, format: Format) -> Result<Vec<u8>, String> {
    match format {
        Format::Png => {
            let mut rgb = Vec::with_capacity(3 * image.data.len());
            rgb.extend(image.data.iter().flat_map(|&c| {
                let t = tone_map(c);
                [t.r(), t.g(), t.b()]
            }));
            encode_png(image.width, image.height, &rgb)
        }
        Format::Exr => encode_exr(image),
        Format::Pfm => Ok(encode_pfm(image)),
        Format::Rgb565 => Ok(encode_rgb565(image)),
    }
}

/// Encodes 8-bit sRGB pixels (3 bytes each, row-major) as PNG.
pub fn encode_png(width: u32, height: u32, rgb: &[u8]) -> Result<Vec<u8>, String> {
    let mut out = Vec::new();
    let mut encoder = png::Encoder::new(&mut out, width, height);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    encoder.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
    let mut writer = encoder.write_header().map_err(|e| format!("PNG: {e}"))?;
    writer.write_image_data(rgb).map_err(|e| format!("PNG: {e}"))?;
    writer.finish().map_err(|e| format!("PNG: {e}"))?;
    Ok(out)
}

fn encode_exr(image: &Image) -> Result<Vec<u8>, String> {
    use exr::prelude::{Image as ExrImage, SpecificChannels, WritableImage};
    let (w, h) = (image.width as usize, image.height as usize);
    let channels = SpecificChannels::rgb(|p: exr::math::Vec2<usize>| {
        let c = image.data[p.y() * w + p.x()];
        (c.x, c.y, c.z)
    });
    let exr_image = ExrImage::from_channels((w, h), channels);
    let mut out = Cursor::new(Vec::new());
    exr_image.write().non_parallel().to_buffered(&mut out).map_err(|e| format!("EXR: {e}"))?;
    Ok(out.into_inner())
}

fn encode_pfm(image: &Image) -> Vec<u8> {
    let head = format!("PF\n{} {}\n-1.0\n", image.width, image.height);
    let mut out = Vec::with_capacity(head.len() + 12 * image.data.len());
    out.extend_from_slice(head.as_bytes());
    for y in (0..image.height).rev() {
        for x in 0..image.width {
            let c = image.get(x, y);
            for v in [c.x, c.y, c.z] {
                out.extend_from_slice(&v.to_le_bytes());
            }
        }
    }
    out
}

/// The RGB565 value an embedded-graphics `DrawTarget<Color = Rgb565>` receives for radiance
/// `c` from `picomis::render_tile`: `Rgb565::from(tone_map(c))`.
pub fn rgb565(c: Rgb) -> u16 {
    let srgb: Rgb888 = tone_map(c);
    Rgb565::from(srgb).into_storage()
}

fn encode_rgb565(image: &Image) -> Vec<u8> {
    let mut out = Vec::with_capacity(2 * image.data.len());
    out.extend(image.data.iter().flat_map(|&c| rgb565(c).to_le_bytes()));
    out
}

/// Checks before a render that `path` can be written: its format is known and its folder exists.
pub fn check_output(path: &Path) -> Result<Format, String> {
    let format = Format::from_path(path)?;
    let dir = parent_dir(path);
    if !dir.is_dir() {
        return Err(format!("{}: folder {} does not exist", path.display(), dir.display()));
    }
    Ok(format)
}

fn parent_dir(path: &Path) -> PathBuf {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// Writes `bytes` to `path` through a temporary file in the same folder and a rename.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), String> {
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let tmp = parent_dir(path).join(format!(".{name}.{}.tmp", std::process::id()));
    let result = std::fs::File::create(&tmp)
        .and_then(|mut f| {
            f.write_all(bytes)?;
            f.sync_all()
        })
        .and_then(|()| std::fs::rename(&tmp, path));
    result.map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        format!("{}: {e}", path.display())
    })
}

/// Reads an EXR file's first RGB(A) layer as linear RGB.
pub fn read_exr(path: &Path) -> Result<Image, String> {
    let bytes = std::fs::read(path).map_err(|e| format!("{}: {e}", path.display()))?;
    decode_exr(&bytes).map_err(|e| format!("{}: {e}", path.display()))
}

/// Decodes an EXR file's bytes: its first RGB(A) layer as linear RGB.
pub fn decode_exr(bytes: &[u8]) -> Result<Image, String> {
    use exr::prelude::{ReadChannels, ReadLayers, read};
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .rgba_channels(
            |resolution, _| Image {
                width: resolution.width() as u32,
                height: resolution.height() as u32,
                data: vec![Rgb::ZERO; resolution.area()],
            },
            |img: &mut Image, pos, (r, g, b, _a): (f32, f32, f32, f32)| {
                let i = pos.y() * img.width as usize + pos.x();
                img.data[i] = Rgb::new(r, g, b);
            },
        )
        .first_valid_layer()
        .all_attributes()
        .from_buffered(Cursor::new(bytes))
        .map_err(|e| e.to_string())?;
    Ok(image.layer_data.channel_data.pixels)
}

/// Reads a little-endian RGB PFM file (as written here).
pub fn read_pfm(path: &Path) -> Result<Image, String> {
    let bytes = std::fs::read(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let bad = || format!("{}: not a little-endian RGB PFM file", path.display());
    let mut fields = Vec::new();
    let mut start = 0;
    for (i, &b) in bytes.iter().enumerate() {
        if b.is_ascii_whitespace() {
            if i > start {
                fields.push(std::str::from_utf8(&bytes[start..i]).map_err(|_| bad())?);
            }
            start = i + 1;
            if fields.len() == 4 {
                break;
            }
        }
    }
    let [kind, w, h, scale] = fields[..] else { return Err(bad()) };
    let (w, h): (u32, u32) = (w.parse().map_err(|_| bad())?, h.parse().map_err(|_| bad())?);
    let scale: f32 = scale.parse().map_err(|_| bad())?;
    let floats = &bytes[start..];
    if kind != "PF" || scale >= 0.0 || floats.len() != (w * h * 12) as usize {
        return Err(bad());
    }
    let value = |i: usize| {
        let b = [floats[4 * i], floats[4 * i + 1], floats[4 * i + 2], floats[4 * i + 3]];
        f32::from_le_bytes(b)
    };
    let mut data = vec![Rgb::ZERO; (w * h) as usize];
    for y in 0..h {
        for x in 0..w {
            let i = (((h - 1 - y) * w + x) * 3) as usize;
            data[(y * w + x) as usize] = Rgb::new(value(i), value(i + 1), value(i + 2));
        }
    }
    Ok(Image { width: w, height: h, data })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> Image {
        let data = (0..12).map(|i| Rgb::new(i as f32 * 0.1, 1.0 / (i as f32 + 1.0), 3.5)).collect();
        Image { width: 4, height: 3, data }
    }

    #[test]
    fn float_formats_round_trip_bit_exactly() {
        let dir = tempfile::tempdir().unwrap();
        let img = sample();
        let pfm = dir.path().join("a.pfm");
        write_atomic(&pfm, &encode(&img, Format::Pfm).unwrap()).unwrap();
        assert_eq!(read_pfm(&pfm).unwrap(), img);
        let exr = dir.path().join("a.exr");
        write_atomic(&exr, &encode(&img, Format::Exr).unwrap()).unwrap();
        assert_eq!(read_exr(&exr).unwrap(), img);
        // No temporary files are left behind.
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 2);
    }

    #[test]
    fn rgb565_matches_embedded_graphics() {
        // White, black, and a mid grey: 0.5 tone-maps to sRGB 188 -> 565 (23, 46, 23).
        assert_eq!(rgb565(Rgb::splat(1.0)), 0xffff);
        assert_eq!(rgb565(Rgb::ZERO), 0);
        let srgb = tone_map(Rgb::splat(0.5));
        assert_eq!(srgb.r(), 188);
        let c = Rgb565::from(srgb);
        assert_eq!(rgb565(Rgb::splat(0.5)), c.into_storage());
        let img = Image { width: 2, height: 1, data: vec![Rgb::new(1.0, 0.0, 0.0), Rgb::splat(0.5)] };
        let bytes = encode(&img, Format::Rgb565).unwrap();
        assert_eq!(bytes.len(), 4);
        assert_eq!(&bytes[..2], &[0x00, 0xf8]); // pure red, little-endian
    }

    #[test]
    fn formats_come_from_extensions() {
        assert_eq!(Format::from_path(Path::new("a/b.PNG")).unwrap(), Format::Png);
        assert_eq!(Format::from_path(Path::new("x.rgb565")).unwrap(), Format::Rgb565);
        assert!(Format::from_path(Path::new("x.jpg")).unwrap_err().contains("unknown image format"));
        assert!(check_output(Path::new("/no/such/folder/x.png")).is_err());
    }
}
