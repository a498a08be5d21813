//! Error of an image against a reference: the mean squared error and the
//! relative MSE, the mean of (I - R)^2 / (R^2 + 0.01), both over pixels and RGB channels, summed
//! in f64.

use picomis::Rgb;

/// Offset of the relative MSE's denominator: it keeps dark pixels from dominating.
pub const REL_EPSILON: f64 = 0.01;

/// Errors of one image.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ErrorStats {
    /// Mean squared error.
    pub mse: f64,
    /// Relative MSE.
    pub rel_mse: f64,
}

/// Squared error and relative squared error of one channel value.
#[inline]
pub fn channel_errors(value: f32, reference: f32) -> (f64, f64) {
    let (v, r) = (f64::from(value), f64::from(reference));
    let d2 = (v - r) * (v - r);
    (d2, d2 / (r * r + REL_EPSILON))
}

/// Errors of `image` against `reference` (the same size).
pub fn error(image: &[Rgb], reference: &[Rgb]) -> ErrorStats {
    assert_eq!(image.len(), reference.len(), "image and reference differ in size");
    let (mut mse, mut rel) = (0.0, 0.0);
    for (i, r) in image.iter().zip(reference) {
        for (v, rv) in [(i.x, r.x), (i.y, r.y), (i.z, r.z)] {
            let (a, b) = channel_errors(v, rv);
            mse += a;
            rel += b;
        }
    }
    let n = (3 * image.len()).max(1) as f64;
    ErrorStats { mse: mse / n, rel_mse: rel / n }
}

/// Box-filters `image` (`w` x `h`) down by the integer factor `k`.
pub fn downsample(image: &[Rgb], w: u32, h: u32, k: u32) -> Vec<Rgb> {
    let (ow, oh) = (w / k, h / k);
    let mut out = vec![Rgb::ZERO; (ow * oh) as usize];
    let inv = 1.0 / (k * k) as f32;
    for y in 0..oh {
        for x in 0..ow {
            let mut sum = Rgb::ZERO;
            for yy in 0..k {
                for xx in 0..k {
                    sum += image[((y * k + yy) * w + x * k + xx) as usize];
                }
            }
            out[(y * ow + x) as usize] = sum * inv;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn errors_follow_the_definitions() {
        let reference = vec![Rgb::splat(1.0), Rgb::splat(0.0)];
        let image = vec![Rgb::splat(1.5), Rgb::splat(0.1)];
        let e = error(&image, &reference);
        assert!((e.mse - (0.25 + 0.01) / 2.0).abs() < 1e-7);
        assert!((e.rel_mse - (0.25 / 1.01 + 0.01 / 0.01) / 2.0).abs() < 1e-6);
        assert_eq!(error(&reference, &reference), ErrorStats::default());
    }

    #[test]
    fn downsampling_averages_blocks() {
        let img: Vec<Rgb> = (0..16).map(|i| Rgb::splat(i as f32)).collect();
        let d = downsample(&img, 4, 4, 2);
        assert_eq!(d, vec![Rgb::splat(2.5), Rgb::splat(4.5), Rgb::splat(10.5), Rgb::splat(12.5)]);
    }
}
