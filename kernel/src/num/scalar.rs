//! Scalars and vectors: glam's `Vec3` and libm's functions, and the f32 helpers every wing uses.

pub use glam::{Vec2, Vec3};

use crate::num::dot3::dot;

/// Linear RGB radiance, irradiance or reflectance, one f32 per channel.
pub type Rgb = Vec3;

/// pi in f32.
pub const PI: f32 = core::f32::consts::PI;
/// 1 / pi in f32.
pub const INV_PI: f32 = core::f32::consts::FRAC_1_PI;

/// True where every f32 operation is a call into a soft-float routine (microcontrollers without
/// an FPU: Cortex-M0, RV32IMC): there, work shared between rays pays for the loads and stores it
/// needs.
pub const SOFT_FLOAT: bool =
    cfg!(all(target_os = "none", not(target_abi = "eabihf"), not(target_feature = "f")));

/// Correctly rounded square root. On hard-float Arm cores this is the FPU's `vsqrt.f32`; on the
/// soft-float cores (Cortex-M0, RV32IMC) `num::sqrt::sqrt_f32`, in 32-bit integer operations;
/// in WebAssembly with SIMD128 the `f32.sqrt` instruction (libm's `sqrtf` there is a software
/// loop: a fifth of the browser page's time); elsewhere libm's `sqrtf` (`sqrtss` on x86). IEEE
/// 754 requires the square root to be correctly rounded, so every path gives the same bits (NaN
/// payloads aside).
#[inline]
pub fn sqrt(x: f32) -> f32 {
    #[cfg(all(target_arch = "arm", target_abi = "eabihf"))]
    {
        let bits: u32;
        // SAFETY: moves the value into s0, takes its square root there and moves it back; it
        // touches no memory, no stack and no flags, and declares s0 clobbered. The hard-float ABI
        // guarantees the FPU is present and enabled. (The `sreg` operand class would avoid the
        // moves but needs an FPU target feature that `cfg` cannot see on these targets.)
        #[allow(unsafe_code)]
        unsafe {
            core::arch::asm!(
                "vmov s0, {x}",
                "vsqrt.f32 s0, s0",
                "vmov {r}, s0",
                x = in(reg) x.to_bits(),
                r = lateout(reg) bits,
                out("s0") _,
                options(pure, nomem, nostack, preserves_flags)
            );
        }
        f32::from_bits(bits)
    }
    #[cfg(all(target_os = "none", not(target_abi = "eabihf"), not(target_feature = "f")))]
    {
        crate::num::sqrt::sqrt_f32(x)
    }
    #[cfg(all(target_arch = "wasm32", target_feature = "simd128"))]
    {
        // Lane 0 of the vector square root: LLVM emits the scalar `f32.sqrt` (the scalar
        // intrinsic, `f32_sqrt`, is not stable yet).
        use core::arch::wasm32::{f32x4_extract_lane, f32x4_splat, f32x4_sqrt};
        f32x4_extract_lane::<0>(f32x4_sqrt(f32x4_splat(x)))
    }
    #[cfg(not(any(
        all(target_arch = "arm", target_abi = "eabihf"),
        all(target_os = "none", not(target_abi = "eabihf"), not(target_feature = "f")),
        all(target_arch = "wasm32", target_feature = "simd128")
    )))]
    {
        libm::sqrtf(x)
    }
}

/// `x` if it is positive, else 0 (NaN gives 0). Inline compare-and-select, where `f32::max`
/// becomes an out-of-line `fmaxf` call on Cortex-M. On the Cortex-M0 the comparison is one on
/// the bits (the positive floats, infinity included, are the patterns 1 to 0x7f80_0000), not a
/// call to the comparison routine (see `MAX0_BY_BITS`).
#[inline]
pub fn max0(x: f32) -> f32 {
    let positive = if MAX0_BY_BITS { positive_bits(x) } else { x > 0.0 };
    if positive { x } else { 0.0 }
}

/// Whether [`max0`] compares the bits: on the soft-float Arm cores, where that is fewer
/// instructions than a call to the comparison routine. On RV32IMC the inlined code changed LLVM's
/// choices around it and cost instructions and stack instead, so the comparison routine stays
/// there (the figures: firmware/README.md).
const MAX0_BY_BITS: bool = SOFT_FLOAT && cfg!(target_arch = "arm");

/// `x > 0.0` from the bits (the soft-float cores' [`max0`]).
#[inline]
fn positive_bits(x: f32) -> bool {
    x.to_bits().wrapping_sub(1) < 0x7f80_0000
}

/// Square root of a value clamped at zero (rounding can make a true zero slightly negative).
#[inline]
pub fn safe_sqrt(x: f32) -> f32 {
    sqrt(max0(x))
}

/// Length of a vector.
#[inline]
pub fn length(v: Vec3) -> f32 {
    sqrt(dot(v, v))
}

/// `x > 0.0 && x.is_finite()`, from the bits: the positive finite floats are the bit patterns
/// 1 to 0x7f7f_ffff (+0, infinity, NaNs and negative values lie outside). The same answer as the
/// two comparisons, which compilers may merge into a floating-point class test that Arm cores
/// without an FPU class instruction expand into some thirty integer instructions.
#[inline]
pub fn positive_finite(x: f32) -> bool {
    x.to_bits().wrapping_sub(1) < 0x7f7f_ffff
}

/// The bits of |x|: for values that are not NaN, |a| < |b| exactly when
/// `magnitude_bits(a) < magnitude_bits(b)`, and |x| = 0 when they are 0 (integer comparisons,
/// where a soft-float core calls a comparison routine for floats).
#[inline]
pub fn magnitude_bits(x: f32) -> u32 {
    x.to_bits() & 0x7fff_ffff
}

/// The unit vector along `v`, or `None` when `v` is zero or not finite.
#[inline]
pub fn try_normalize(v: Vec3) -> Option<Vec3> {
    let len2 = dot(v, v);
    if positive_finite(len2) { Some(v * (1.0 / sqrt(len2))) } else { None }
}

/// The unit vector along `v`, or `fallback` when `v` is zero or not finite.
#[inline]
pub fn normalize_or(v: Vec3, fallback: Vec3) -> Vec3 {
    try_normalize(v).unwrap_or(fallback)
}

/// `x` raised to `y`.
#[inline]
pub fn powf(x: f32, y: f32) -> f32 {
    libm::powf(x, y)
}

/// Arc cosine, in [0, pi] (libm's `acosf`: f32 only).
#[inline]
pub fn acos(x: f32) -> f32 {
    libm::acosf(x)
}

/// The angle of the point (x, y), in (-pi, pi] (libm's `atan2f`: f32 only).
#[inline]
pub fn atan2(y: f32, x: f32) -> f32 {
    libm::atan2f(y, x)
}

/// `v` limited to [lo, hi] by compare-and-select (NaN stays NaN; never panics, unlike
/// `f32::clamp` with bounds out of order).
#[inline]
pub fn clamp(v: f32, lo: f32, hi: f32) -> f32 {
    if v < lo {
        lo
    } else if v > hi {
        hi
    } else {
        v
    }
}

/// Rec. 709 luminance of a linear RGB value.
#[inline]
pub fn luminance(c: Rgb) -> f32 {
    0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z
}

/// The mean of a colour's channels: what a light or a BSDF value weighs when one sample must
/// serve every channel (light selection). Each channel's relative error counts alike, as in the
/// relative MSE; luminance would give green ten times blue's say, and a blue light too few
/// samples for its share of the blue channel (pbrt-v4 averages the spectrum likewise).
#[inline]
pub fn channel_mean(c: Rgb) -> f32 {
    (c.x + c.y + c.z) * (1.0 / 3.0)
}

/// True when every component of the vector is finite.
#[inline]
pub fn finite3(v: Vec3) -> bool {
    v.x.is_finite() && v.y.is_finite() && v.z.is_finite()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn positive_finite_is_the_two_comparisons() {
        let special = [
            0.0f32,
            -0.0,
            f32::MIN_POSITIVE,
            -f32::MIN_POSITIVE,
            f32::from_bits(1),
            f32::from_bits(0x8000_0001),
            f32::MAX,
            f32::MIN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
            -f32::NAN,
            f32::from_bits(0x7f80_0001),
            f32::from_bits(0xffff_ffff),
            1.0,
            -1.0,
        ];
        let mut bits = 0x9e37_79b9u32;
        let random = (0..1_000_000).map(|_| {
            bits = bits.wrapping_mul(0x2c1b_3c6d).wrapping_add(0x297a_2d39);
            f32::from_bits(bits)
        });
        for x in special.into_iter().chain(random) {
            assert_eq!(positive_finite(x), x > 0.0 && x.is_finite(), "{:08x}", x.to_bits());
            assert_eq!(positive_bits(x), x > 0.0, "{:08x}", x.to_bits());
        }
    }

    #[test]
    fn sqrt_and_normalize() {
        assert_eq!(sqrt(4.0), 2.0);
        assert_eq!(safe_sqrt(-1e-9), 0.0);
        assert_eq!(max0(f32::NAN), 0.0);
        assert_eq!(try_normalize(Vec3::ZERO), None);
        assert_eq!(try_normalize(Vec3::new(f32::INFINITY, 0.0, 0.0)), None);
        assert!((length(normalize_or(Vec3::new(3.0, 4.0, 12.0), Vec3::Z)) - 1.0).abs() < 1e-6);
    }
}
