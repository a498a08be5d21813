//! False colour for the lecture's MIS weight images: a weight in [0, 1] as a viridis colour, and the
//! grey of pixels where no sample of a technique found light. One definition for every place
//! that shows weights (the desktop figure, the study's charts, the browser page, a display).

use embedded_graphics_core::pixelcolor::Rgb888;

/// Viridis (perceptually uniform, readable in grey and by colour-blind readers), sampled at
/// 0, 1/8, ..., 1.
pub const VIRIDIS: [[u8; 3]; 9] = [
    [68, 1, 84],
    [71, 44, 122],
    [59, 81, 139],
    [44, 113, 142],
    [33, 144, 141],
    [39, 173, 129],
    [92, 200, 99],
    [170, 220, 50],
    [253, 231, 37],
];

/// Weight-image colour of pixels where no sample of the technique found light.
pub const NO_LIGHT: Rgb888 = Rgb888::new(128, 128, 128);

/// False colour of a weight in [0, 1]: linear interpolation between the [`VIRIDIS`] samples
/// (values outside [0, 1] are clamped, NaN and infinities map to 0).
pub fn weight_color(w: f32) -> Rgb888 {
    let t = if w.is_finite() { w.clamp(0.0, 1.0) } else { 0.0 } * 8.0;
    let i = (t as usize).min(VIRIDIS.len() - 2);
    let f = t - i as f32;
    let (a, b) = match (VIRIDIS.get(i), VIRIDIS.get(i + 1)) {
        (Some(a), Some(b)) => (a, b),
        _ => return NO_LIGHT, // unreachable: i <= 7
    };
    let mix = |k: usize| (f32::from(a[k]) * (1.0 - f) + f32::from(b[k]) * f + 0.5) as u8;
    Rgb888::new(mix(0), mix(1), mix(2))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weight_colors_span_viridis() {
        let v = |i: usize| Rgb888::new(VIRIDIS[i][0], VIRIDIS[i][1], VIRIDIS[i][2]);
        assert_eq!(weight_color(0.0), v(0));
        assert_eq!(weight_color(1.0), v(8));
        assert_eq!(weight_color(0.5), v(4));
        assert_eq!(weight_color(f32::NAN), v(0));
        assert_eq!(weight_color(7.0), v(8));
        assert_eq!(weight_color(-1.0), v(0));
        assert_ne!(weight_color(0.5), NO_LIGHT);
    }
}
