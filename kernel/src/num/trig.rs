//! Sine and cosine for the samplers' azimuths, in integer arithmetic: [`sin_cos_eighths`] and
//! [`sin_cos_turns`]. The argument is reduced to t pi / 4 with |t| <= 1, and the two polynomials
//! in u = t^2 run in fixed point, each step the high word of one 32 x 32 -> 64-bit multiply (one
//! instruction on the M4F and RV32IMC, a short routine on the Cortex-M0: about half a soft-float
//! multiply and add), and integers give the same bits on every machine like IEEE f32 does. The
//! results are f32: cos(t pi / 4) and sin(t pi / 4) / t lie in [1/2, 1], where Q30 holds more
//! than the 24 bits of a significand, and the sine is t times the latter in f32, so it keeps its
//! relative precision near zero.

use crate::num::scalar::{SOFT_FLOAT, clamp};
use crate::num::wide::mul_wide;

/// sin(t pi / 4) / t = sum SIN[k] u^k for u = t^2 in [0, 1], coefficient k in Q(30 + 2k) (so
/// that each Horner step is a high word, see [`horner`]): interpolation at the four Chebyshev
/// nodes of [0, 1] (near minimax); with the steps' truncation, within 3.4e-9 on [0, 1].
const SIN: [i32; 4] = [843_314_854, -346_799_001, 42_777_991, -2_470_760];
/// cos(t pi / 4) = sum COS[k] u^k, the same way with five nodes: within 1.3e-9. COS[0] is
/// exactly one (Q30), so cos(0) = 1.
const COS: [i32; 5] = [1 << 30, -1_324_675_869, 272_375_233, -22_398_329, 970_263];

/// `a b / 2^32`, rounded down: the high word of the 64-bit product.
#[inline(always)]
fn mul_hi(a: i32, b: i32) -> i32 {
    (mul_wide(a, b) >> 32) as i32
}

/// The polynomial with coefficients `c` (constant first, coefficient k in Q(30 + 2k)) at `u` in
/// Q30, by Horner's rule: p in Q(32 + 2k) times u in Q30 is in Q(30 + 2k) after dropping the
/// low word, the scale of the next coefficient. The result is in Q30.
#[inline(always)]
fn horner(c: &[i32], u: i32) -> i32 {
    let Some((&last, rest)) = c.split_last() else { return 0 };
    rest.iter().rev().fold(last, |p, &k| k.wrapping_add(mul_hi(p, u)))
}

/// floor(|x| 2^31) for |x| < 1, saturating: `(|x| 2^31) as i32` (1 or more and infinities give
/// 2^31 - 1, NaN gives 0). On cores with an FPU that is what they compute (a multiply by a power
/// of two is exact, the conversion truncates); on the others [`q31_of_unit_bits`], the same
/// integer from the bits.
#[inline(always)]
fn q31_of_unit(x: f32) -> i32 {
    if SOFT_FLOAT { q31_of_unit_bits(x) } else { (x.abs() * 2_147_483_648.0) as i32 }
}

/// [`q31_of_unit`] in integer operations only.
#[inline(always)]
fn q31_of_unit_bits(x: f32) -> i32 {
    let bits = x.to_bits() & 0x7fff_ffff;
    // |x| = m 2^(e - 150) with the biased exponent e: |x| 2^31 = m 2^(e - 119).
    let e = (bits >> 23) as i32;
    let m = ((bits & 0x7f_ffff) | 0x80_0000) as i32;
    let shift = e - 119;
    if bits > 0x7f80_0000 {
        0 // NaN
    } else if shift >= 8 {
        i32::MAX // |x| >= 1
    } else if shift >= 0 {
        m << shift
    } else if shift > -24 {
        m >> -shift
    } else {
        0
    }
}

/// The f32 nearest (halves up) to x / 2^30 for x in [2^29, 2^30]: an exponent of -1 and the
/// significand's 24 bits, a carry into the exponent giving 1 exactly. (Both polynomials stay in
/// that range for every u in [0, 2^30): `values_stay_in_range` below.)
#[inline(always)]
fn f32_of_q30_half_to_one(x: i32) -> f32 {
    f32::from_bits(((x as u32).wrapping_add(32) >> 6).wrapping_add(125 << 23))
}

/// `(sin(t pi / 4), cos(t pi / 4))` for `t` in [-1, 1], with `tq` = t 2^31 (the same value in
/// Q31, 2^31 - 1 for 1). Both within about 1e-8 of the exact values.
#[inline(always)]
fn sin_cos_scaled(t: f32, tq: i32) -> (f32, f32) {
    let u = mul_hi(tq, tq); // t^2 in Q30
    let sin_over_t = f32_of_q30_half_to_one(horner(&SIN, u));
    let cos = f32_of_q30_half_to_one(horner(&COS, u));
    (t * sin_over_t, cos)
}

/// `(sin(t pi / 4), cos(t pi / 4))` for `t` in [-1, 1] (the eighth of a turn either side of
/// zero; a larger |t| counts as 1).
#[inline]
pub fn sin_cos_eighths(t: f32) -> (f32, f32) {
    let t = clamp(t, -1.0, 1.0);
    sin_cos_scaled(t, q31_of_unit(t))
}

/// Sine and cosine of the angle `2 pi u` (`u` in turns; exact reduction for |u| < 2^23, where
/// `u` minus its integer part is an f32; 0 for a `u` that is not finite). `u` in [0, 1], what the
/// samplers pass, goes to fixed point from its bits; the nearest quarter turn is then taken off
/// in integers, and an exact quadrant rotation follows. (libm's `sincosf` computes in f64,
/// software double on a Cortex-M4F.)
#[inline]
pub fn sin_cos_turns(u: f32) -> (f32, f32) {
    // Q31 turns, in (-2^31, 2^31): `u` itself when it is in [+0, 1) (bits below those of 1.0),
    // else its part after the integer (exact; `as` saturates and sends NaN to 0).
    let x = if u.to_bits() < 0x3f80_0000 {
        q31_of_unit(u)
    } else {
        let w = u - (u as i32) as f32;
        let w = if w.is_finite() { w } else { 0.0 };
        let q = q31_of_unit(w);
        if w < 0.0 { -q } else { q }
    };
    // The nearest quarter turn k (2^29 in Q31) and the rest, r in [-2^28, 2^28): t = r / 2^28.
    let k = x.wrapping_add(1 << 28) >> 29;
    let r = x.wrapping_sub(k << 29);
    // t as an f32: r converted (rounded to 24 bits), then 2^-28 exactly on the exponent.
    let t = if r == 0 { 0.0 } else { f32::from_bits((r as f32).to_bits() - (28 << 23)) };
    let (s, c) = sin_cos_scaled(t, r << 3);
    match k & 3 {
        0 => (s, c),
        1 => (c, -s),
        2 => (-s, -c),
        _ => (-c, s),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::num::scalar::PI;

    /// Distance in units in the last place (the f32 grid's steps between `a` and `b`).
    fn ulps(a: f32, b: f32) -> u32 {
        let key = |x: f32| {
            let b = x.to_bits() as i32;
            if b < 0 { i32::MIN.wrapping_sub(b) } else { b }
        };
        key(a).wrapping_sub(key(b)).unsigned_abs()
    }

    #[test]
    fn eighths_match_libm_within_two_ulps() {
        let mut worst = (0, 0);
        for i in -4096..=4096 {
            let t = i as f32 / 4096.0;
            let (s, c) = sin_cos_eighths(t);
            let a = t * core::f32::consts::FRAC_PI_4;
            // libm's f32 functions are within an ulp; ours within two of them (or 1e-9 absolute
            // for a sine near zero, where libm rounds the exact product of t and pi/4).
            let (ds, dc) = (ulps(s, libm::sinf(a)), ulps(c, libm::cosf(a)));
            assert!(ds <= 2 || (s - libm::sinf(a)).abs() < 1e-9, "t {t}: sin {s} vs {}", libm::sinf(a));
            assert!(dc <= 2, "t {t}: cos {c} vs {}", libm::cosf(a));
            worst = (worst.0.max(ds), worst.1.max(dc));
        }
        // The extremes: cos(0) = 1 and sin(0) = 0 exactly, and a clamped argument.
        assert_eq!(sin_cos_eighths(0.0), (0.0, 1.0));
        assert_eq!(sin_cos_eighths(1.0), sin_cos_eighths(3.0));
        assert!(worst.1 <= 2, "{worst:?}");
    }

    #[test]
    fn values_stay_in_range() {
        // Both polynomials decrease in u on [0, 2^30]: checked at every 2^10-th u and the ends.
        let (mut last_s, mut last_c) = (i32::MAX, i32::MAX);
        for u in (0..=1 << 20).map(|i: i32| (i << 10).min((1 << 30) - 1)) {
            let (s, c) = (horner(&SIN, u), horner(&COS, u));
            assert!((1 << 29..=1 << 30).contains(&s) && (1 << 29..=1 << 30).contains(&c), "u {u}: {s} {c}");
            assert!(s <= last_s && c <= last_c, "u {u}");
            (last_s, last_c) = (s, c);
        }
        assert_eq!(horner(&COS, 0), 1 << 30);
        // The conversion from the bits is the saturating cast: on a sample of every 4099th bit
        // pattern (all exponents, both signs, NaNs and infinities) and the edges.
        let edges = [0.0f32, -0.0, 1e-12, 0.3, -0.7, 0.999_999_94, 1.0, -1.0, 2.5, f32::INFINITY, f32::NAN];
        let sample = (0..=u32::MAX / 4099).map(|i| f32::from_bits(i * 4099));
        for x in edges.into_iter().chain(sample) {
            assert_eq!(q31_of_unit_bits(x), (x.abs() * 2_147_483_648.0) as i32, "{x} ({:#x})", x.to_bits());
        }
    }

    #[test]
    fn turns_match_libm_and_rotate_exactly() {
        for i in 0..=8192 {
            let u = i as f32 / 8192.0;
            let (s, c) = sin_cos_turns(u);
            let a = u * 2.0 * core::f32::consts::PI;
            // (a itself is rounded to an f32: up to 2.4e-7 off at 2 pi.)
            assert!((s - libm::sinf(a)).abs() < 6e-7 && (c - libm::cosf(a)).abs() < 6e-7, "u {u}: {s} {c}");
            // Whole turns away: the same angle.
            let (s2, c2) = sin_cos_turns(u - 3.0);
            assert!((s2 - s).abs() < 1e-6 && (c2 - c).abs() < 1e-6, "u {u}");
        }
        // Quarter turns are exact.
        assert_eq!(sin_cos_turns(0.25), (1.0, -0.0));
        assert_eq!(sin_cos_turns(0.5), (-0.0, -1.0));
        assert_eq!(sin_cos_turns(0.0), (0.0, 1.0));
        for bad in [f32::NAN, f32::INFINITY, -f32::INFINITY, 1e30] {
            let (s, c) = sin_cos_turns(bad);
            assert!(s.is_finite() && c.is_finite());
        }
    }

    #[test]
    fn trig_matches_libm_over_whole_turns() {
        let mut worst = 0.0f32;
        for i in 0..=100_000 {
            let u = i as f32 / 100_000.0 * 2.0 - 0.5; // [-0.5, 1.5] turns
            let (s, c) = sin_cos_turns(u);
            let (ls, lc) = libm::sincosf(2.0 * PI * u);
            worst = worst.max((s - ls).abs()).max((c - lc).abs());
        }
        // libm's reference itself carries the rounding of 2 pi u (about 1 ulp of 2 pi u).
        assert!(worst < 1e-6, "{worst}");
        assert_eq!(sin_cos_turns(0.0), (0.0, 1.0));
        assert_eq!(sin_cos_turns(0.25), (1.0, -0.0));
        assert_eq!(sin_cos_turns(0.5), (-0.0, -1.0));
    }
}
