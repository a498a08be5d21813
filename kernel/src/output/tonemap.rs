//! Tone mapping: linear radiance to 8-bit sRGB, the last step of every pixel the kernel draws
//! (`render_tile`) and of every PNG the host writes.

use embedded_graphics_core::pixelcolor::Rgb888;

use crate::num::Rgb;

/// Linear values at which the 8-bit sRGB code steps up: entry `k - 1` is the sRGB decoding of
/// `(k - 0.5) / 255` (the sRGB transfer curve, IEC 61966-2-1), rounded to f32. Generated once by
/// evaluating the curve in double precision; a unit test checks it against `powf`.
#[rustfmt::skip]
const SRGB_STEPS: [f32; 255] = [
    0.0001517635, 0.0004552905, 0.0007588175, 0.0010623444, 0.0013658714, 0.0016693984, 0.0019729254,
    0.0022764525, 0.0025799794, 0.0028835062, 0.0031883009, 0.0035092593, 0.003848315, 0.004205748,
    0.004581833, 0.0049768374, 0.005391024, 0.0058246506, 0.0062779696, 0.0067512277, 0.0072446684,
    0.0077585303, 0.0082930485, 0.008848453, 0.0094249705, 0.010022826, 0.010642237, 0.011283421,
    0.0119465925, 0.01263196, 0.013339732, 0.014070112, 0.014823303, 0.015599503, 0.01639891, 0.017221715,
    0.018068114, 0.018938294, 0.019832443, 0.020750744, 0.021693382, 0.022660539, 0.02365239, 0.024669115,
    0.025710888, 0.026777882, 0.02787027, 0.02898822, 0.030131903, 0.03130148, 0.032497123, 0.03371899,
    0.034967244, 0.036242045, 0.037543554, 0.038871925, 0.04022732, 0.041609887, 0.043019786, 0.044457164,
    0.04592217, 0.047414962, 0.048935685, 0.050484486, 0.052061506, 0.053666897, 0.055300802, 0.05696336,
    0.058654718, 0.060375012, 0.062124383, 0.063902974, 0.06571092, 0.06754835, 0.06941541, 0.071312234,
    0.073238954, 0.07519571, 0.07718261, 0.07919982, 0.08124744, 0.083325624, 0.08543449, 0.087574154,
    0.08974477, 0.09194644, 0.0941793, 0.096443474, 0.098739095, 0.10106627, 0.10342513, 0.105815805,
    0.1082384, 0.110693045, 0.11317986, 0.11569897, 0.11825048, 0.12083452, 0.1234512, 0.12610064, 0.12878296,
    0.13149826, 0.13424668, 0.1370283, 0.13984327, 0.14269169, 0.14557366, 0.14848931, 0.15143873, 0.15442206,
    0.15743938, 0.16049083, 0.1635765, 0.16669649, 0.16985093, 0.17303991, 0.17626357, 0.17952198, 0.18281525,
    0.1861435, 0.18950683, 0.19290535, 0.19633915, 0.19980834, 0.20331304, 0.20685335, 0.21042934, 0.21404114,
    0.21768884, 0.22137256, 0.2250924, 0.22884843, 0.23264076, 0.2364695, 0.24033478, 0.24423663, 0.2481752,
    0.25215057, 0.25616285, 0.26021212, 0.26429847, 0.26842204, 0.2725829, 0.2767811, 0.2810168, 0.2852901,
    0.28960103, 0.29394972, 0.2983363, 0.3027608, 0.30722335, 0.31172404, 0.31626296, 0.32084018, 0.32545584,
    0.33010998, 0.33480275, 0.33953416, 0.34430438, 0.34911346, 0.3539615, 0.35884857, 0.36377478, 0.36874023,
    0.37374496, 0.37878913, 0.38387278, 0.388996, 0.3941589, 0.39936152, 0.40460402, 0.40988642, 0.41520882,
    0.42057136, 0.42597404, 0.43141702, 0.43690035, 0.44242412, 0.44798842, 0.4535933, 0.45923892, 0.4649253,
    0.47065252, 0.4764207, 0.48222992, 0.48808023, 0.49397177, 0.49990454, 0.5058787, 0.5118943, 0.5179514,
    0.5240501, 0.5301905, 0.5363727, 0.54259676, 0.5488627, 0.55517066, 0.5615207, 0.5679129, 0.5743473,
    0.58082414, 0.58734334, 0.593905, 0.6005092, 0.6071561, 0.6138457, 0.6205781, 0.62735337, 0.6341716,
    0.6410329, 0.64793724, 0.6548848, 0.66187567, 0.6689098, 0.67598736, 0.68310845, 0.6902731, 0.69748133,
    0.7047334, 0.71202916, 0.7193688, 0.72675246, 0.73418003, 0.7416518, 0.7491677, 0.7567278, 0.7643323,
    0.7719811, 0.7796744, 0.7874123, 0.79519475, 0.8030219, 0.81089383, 0.8188105, 0.8267722, 0.8347788,
    0.8428305, 0.8509273, 0.8590692, 0.8672565, 0.87548906, 0.88376707, 0.89209056, 0.9004596, 0.9088742,
    0.91733456, 0.9258406, 0.9343926, 0.94299036, 0.95163417, 0.96032405, 0.96906, 0.97784215, 0.98667055,
    0.99554527,
];

/// The bits of [`SRGB_STEPS`]: positive floats order like their bits read as integers.
const SRGB_STEP_BITS: [i32; 255] = {
    let mut bits = [0i32; 255];
    let mut k = 0;
    while k < 255 {
        bits[k] = SRGB_STEPS[k].to_bits() as i32;
        k += 1;
    }
    bits
};

/// Linear radiance to 8-bit sRGB: clamp to [0, 1], sRGB transfer curve, round to the nearest
/// code. The code is found by a binary search over a table of the 255 steps (8 comparisons per
/// channel instead of a `powf`, one per bit of the code), so it costs the same on a Cortex-M0 as
/// anywhere else. The
/// comparisons `v >= step` are integer comparisons of the bits: every step is a positive float,
/// and positive floats (+inf included) order like their bits read as `i32`; a negative `v`
/// (-0 included) reads as a negative `i32`, below every step, as it compares below them; a NaN
/// compares false, so it is mapped below every step too.
pub fn tone_map(c: Rgb) -> Rgb888 {
    let encode = |v: f32| {
        let bits = v.to_bits() as i32;
        let key = if bits > f32::INFINITY.to_bits() as i32 { -1 } else { bits };
        // Number of steps at or below v, by halves of the 256 codes: after the halves from 128
        // down to 2^k the count is known to 2^k, and entry count + 2^k - 1 (at most 254) decides
        // the next bit. Eight loads and compares, no loop bounds to test.
        let mut count = 0usize;
        for half in [128, 64, 32, 16, 8, 4, 2, 1] {
            if SRGB_STEP_BITS.get(count + half - 1).is_some_and(|&step| key >= step) {
                count += half;
            }
        }
        count as u8 // count <= 255
    };
    Rgb888::new(encode(c.x), encode(c.y), encode(c.z))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::num::powf;
    use embedded_graphics_core::pixelcolor::RgbColor;

    fn srgb_formula(v: f32) -> f32 {
        let v = v.clamp(0.0, 1.0);
        255.0 * if v <= 0.003_130_8 { 12.92 * v } else { 1.055 * powf(v, 1.0 / 2.4) - 0.055 }
    }

    #[test]
    fn tone_map_rounds_the_srgb_curve() {
        assert_eq!(tone_map(Rgb::new(0.0, 1.0, 0.5)), Rgb888::new(0, 255, 188));
        assert_eq!(tone_map(Rgb::new(-1.0, 7.0, f32::NAN)), Rgb888::new(0, 255, 0));
        assert_eq!(tone_map(Rgb::splat(f32::INFINITY)), Rgb888::new(255, 255, 255));
        // Away from the rounding boundaries the table and the formula agree exactly.
        for i in 0..=20_000 {
            let v = i as f32 / 20_000.0;
            let exact = srgb_formula(v);
            let code = tone_map(Rgb::splat(v)).r();
            if (exact - exact.floor() - 0.5).abs() > 1e-3 {
                assert_eq!(f32::from(code), (exact + 0.5).floor(), "v = {v}");
            } else {
                assert!((f32::from(code) - exact).abs() <= 0.5 + 1e-3, "v = {v}");
            }
        }
        // The steps increase strictly.
        assert!(SRGB_STEPS.windows(2).all(|w| w[0] < w[1]));
    }

    /// The float comparisons the integer search stands for: the same code for every class of
    /// value (zeros of both signs, subnormals, steps and their neighbours, 1, above 1, infinities,
    /// NaNs of both signs, negatives).
    #[test]
    fn integer_search_equals_the_float_comparisons() {
        let by_floats = |v: f32| SRGB_STEPS.iter().filter(|&&s| v >= s).count();
        let mut values = std::vec![0.0, -0.0, 1e-45, -1e-45, 1.0, 1.5, 1e30, f32::MAX, -1.0, -f32::MAX];
        values.extend([f32::INFINITY, f32::NEG_INFINITY, f32::NAN, -f32::NAN, f32::from_bits(0x7f80_0001)]);
        values.push(f32::from_bits(0xffff_ffff));
        for s in SRGB_STEPS {
            let b = s.to_bits();
            values.extend([s, -s, f32::from_bits(b - 1), f32::from_bits(b + 1)]);
        }
        for i in 0..=10_000 {
            values.push(i as f32 / 8_000.0);
        }
        for v in values {
            let want = by_floats(v);
            assert_eq!(usize::from(tone_map(Rgb::splat(v)).r()), want, "v = {v} ({:#x})", v.to_bits());
        }
    }
}
