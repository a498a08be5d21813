//! The one place that chooses the math backend: glam vectors (scalar `Vec3`, no SIMD) and libm
//! functions, so the host and a microcontroller run the same f32 operations bit for bit.

pub use crate::dot3::dot;
pub use crate::trig::{sin_cos_eighths, sin_cos_turns};
pub use glam::{Vec2, Vec3};

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
/// soft-float cores (Cortex-M0, RV32IMC) [`crate::sqrt::sqrt_f32`], in 32-bit integer operations;
/// elsewhere libm's `sqrtf` (`sqrtss` on x86). IEEE 754 requires the square root to be correctly
/// rounded, so every path gives the same bits (NaN payloads aside).
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
        crate::sqrt::sqrt_f32(x)
    }
    #[cfg(not(any(
        all(target_arch = "arm", target_abi = "eabihf"),
        all(target_os = "none", not(target_abi = "eabihf"), not(target_feature = "f"))
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

/// Whether [`max0`] compares the bits: on the soft-float Arm cores, where it saves about 90
/// instructions per camera sample on the Veach scene (for 48 bytes more peak stack). On RV32IMC
/// it cost 49 instructions and 160 bytes of stack instead (the inlined code changed LLVM's
/// choices around it), so the comparison routine stays there.
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

/// An orthonormal frame around a unit normal: local `z` is the normal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    /// First tangent.
    pub t: Vec3,
    /// Second tangent.
    pub b: Vec3,
    /// Normal.
    pub n: Vec3,
    /// -1 / (sign(n.z) + n.z), the frame's one division, kept for [`Frame::to_world`].
    a: f32,
}

/// `sign(n.z) v`: exact. On the soft-float cores a flip of the sign bit instead of a multiply
/// (the same bits for every non-NaN operand, a multiply call less each).
#[inline(always)]
fn signed_by(n: Vec3, v: f32) -> f32 {
    if SOFT_FLOAT {
        f32::from_bits(v.to_bits() ^ (n.z.to_bits() & 0x8000_0000))
    } else {
        1.0f32.copysign(n.z) * v
    }
}

/// -1 / (sign(n.z) + n.z): |sign(n.z) + n.z| >= 1, so the frame has no singularity.
#[inline(always)]
fn frame_a(n: Vec3) -> f32 {
    -1.0 / (1.0f32.copysign(n.z) + n.z)
}

/// The local direction `v` (`z` along the unit `n`) in world coordinates, in the frame of
/// [`Frame::from_normal`] around `n` with its `a`: t v.x + b v.y + n v.z with the tangents'
/// terms gathered (q = sign n.x v.x + n.y v.y, m = a q + v.z: (v.x + n.x m, sign v.y + n.y m,
/// n.z v.z - q)), 5 multiplies and 5 adds where the tangents take 9 and 6.
#[inline(always)]
fn from_local_with(n: Vec3, a: f32, v: Vec3) -> Vec3 {
    let q = signed_by(n, n.x) * v.x + n.y * v.y;
    let m = a * q + v.z;
    Vec3::new(v.x + n.x * m, signed_by(n, v.y) + n.y * m, n.z * v.z - q)
}

/// [`Frame::from_normal`]`(n).to_world(v)` without building the tangents: for a direction
/// sampled around an axis used once (a light's cone).
#[inline]
pub fn from_local_around(n: Vec3, v: Vec3) -> Vec3 {
    from_local_with(n, frame_a(n), v)
}

impl Frame {
    /// Builds a frame around the unit vector `n` (Duff et al. 2017, branchless, no singularity).
    /// The products with sign(n.z) are exact (`signed_by`: sign flips on the soft-float cores).
    #[inline]
    pub fn from_normal(n: Vec3) -> Self {
        let sign = 1.0f32.copysign(n.z);
        let a = frame_a(n);
        let b = n.x * n.y * a;
        Self {
            t: Vec3::new(1.0 + signed_by(n, n.x) * n.x * a, signed_by(n, b), -signed_by(n, n.x)),
            b: Vec3::new(b, sign + n.y * n.y * a, -n.y),
            n,
            a,
        }
    }

    /// World direction to local coordinates.
    #[inline]
    pub fn to_local(&self, v: Vec3) -> Vec3 {
        Vec3::new(dot(v, self.t), dot(v, self.b), dot(v, self.n))
    }

    /// Local direction to world coordinates (see [`from_local_around`]).
    #[inline]
    pub fn to_world(&self, v: Vec3) -> Vec3 {
        from_local_with(self.n, self.a, v)
    }
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
    fn frames_flip_signs_as_the_products_with_sign_did() {
        // Normals on both sides of z = 0 (signed zeros included): the frame's sign flips give
        // the bits of the products with sign = 1.0f32.copysign(n.z) they replace.
        let mut bits = 0x1234_5678u32;
        let mut next = || {
            bits = bits.wrapping_mul(0x2c1b_3c6d).wrapping_add(0x297a_2d39);
            f32::from_bits(0x3f80_0000 | bits >> 9) * 2.0 - 3.0
        };
        let mut normals = std::vec![Vec3::Z, -Vec3::Z, Vec3::X, Vec3::new(0.0, 1.0, -0.0)];
        normals.extend((0..10_000).map(|_| Vec3::new(next(), next(), next()).normalize()));
        for n in normals {
            let sign = 1.0f32.copysign(n.z);
            let a = -1.0 / (sign + n.z);
            let b = n.x * n.y * a;
            let t = Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
            let f = Frame::from_normal(n);
            let same = |u: Vec3, v: Vec3| u.to_array().map(f32::to_bits) == v.to_array().map(f32::to_bits);
            assert!(same(f.t, t), "{n}: {} {t}", f.t);
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

    #[test]
    fn sqrt_and_normalize() {
        assert_eq!(sqrt(4.0), 2.0);
        assert_eq!(safe_sqrt(-1e-9), 0.0);
        assert_eq!(max0(f32::NAN), 0.0);
        assert_eq!(try_normalize(Vec3::ZERO), None);
        assert_eq!(try_normalize(Vec3::new(f32::INFINITY, 0.0, 0.0)), None);
        assert!((length(normalize_or(Vec3::new(3.0, 4.0, 12.0), Vec3::Z)) - 1.0).abs() < 1e-6);
    }

    #[test]
    fn frame_is_orthonormal_for_any_normal() {
        for n in [
            Vec3::Z,
            -Vec3::Z,
            Vec3::X,
            Vec3::new(0.3, -0.4, -0.866).normalize(),
            Vec3::new(1e-7, 0.0, -1.0).normalize(),
        ] {
            let f = Frame::from_normal(n);
            assert!((f.t.length() - 1.0).abs() < 1e-5, "{n}");
            assert!((f.b.length() - 1.0).abs() < 1e-5, "{n}");
            assert!(f.t.dot(f.b).abs() < 1e-5 && f.t.dot(n).abs() < 1e-5 && f.b.dot(n).abs() < 1e-5);
            let v = Vec3::new(0.2, -0.5, 0.7);
            assert!((f.to_local(f.to_world(v)) - v).length() < 1e-5);
        }
    }
}
