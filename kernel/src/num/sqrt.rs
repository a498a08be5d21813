//! A correctly rounded f32 square root in 32-bit integer arithmetic, for the cores without an FPU
//! (Cortex-M0, RV32IMC), where libm's `sqrtf` needs 64-bit multiplies and a final soft-float add.
//! IEEE 754 requires the square root to be correctly rounded, so this gives libm's bits for every
//! non-NaN result; every NaN result is libm's `f32::NAN` (its generic `sqrtf`, which the
//! soft-float targets run, returns that one NaN for NaN and negative inputs alike).
//!
//! For a normal x = 2^(e - 127) m / 2^23 (m the 24-bit significand), let A = m 2^7 when e is odd
//! and m 2^8 when it is even, so that A is in [2^30, 2^32) and sqrt(x) = 2^((e - 127 - k) / 2)
//! sqrt(A) / 2^16 with the result's significand in [1, 2). The 25-bit root Q = floor(sqrt(N)),
//! N = A 2^18, rounds to the result's 24-bit significand as (Q + 1) / 2 (floor): N is even and
//! not zero, so sqrt(N) is never an odd integer and never halfway between two floats.
//!
//! Q comes from a 16-bit reciprocal square root (a table and one Newton step), a first root
//! y ~ sqrt(A) within a few units, its exact remainder A - y^2 and one digit step with the
//! reciprocal. The last estimate, kept with 6 fraction bits and biased by 0.75, lies in
//! [sqrt(N), sqrt(N) + 1) for every significand and exponent parity (measured from 0.20 to 0.76
//! over all 2^25 cases, which the tests check exhaustively), so its floor is Q or Q + 1, and the
//! sign of the exact remainder N - Q'^2 (computed modulo 2^32, where its true value fits)
//! decides between them. Every product fits 32 bits: no 64-bit multiply, no division.

/// `round(2^15 / sqrt(a))` at the middle of each table interval, a = A / 2^32 in [1/4, 1),
/// indexed by A >> 25 (5 fraction bits for odd exponents, 6 for even ones; entries 0 to 31 are
/// never read and repeat entry 32). Evaluated by the compiler (the 64-bit integers below exist
/// only at compile time): 256 bytes of flash.
static RSQRT: [u16; 128] = rsqrt_table();

const fn rsqrt_table() -> [u16; 128] {
    let mut table = [0u16; 128];
    let mut i = 0;
    while i < 128 {
        let k = if i < 32 { 32 } else { i as u64 };
        // The middle of [k, k + 1) 2^25 is a = (2k + 1) / 2^8; 2 * 2^15 / sqrt(a) is the integer
        // square root of 2^32 2^8 / (2k + 1), halved with rounding.
        let twice = isqrt_u64((1u64 << 40) / (2 * k + 1));
        table[i] = twice.div_ceil(2) as u16;
        i += 1;
    }
    table
}

/// floor(sqrt(n)) by bisection (compile time only).
const fn isqrt_u64(n: u64) -> u64 {
    let mut lo = 0u64;
    let mut hi = 1u64 << 32;
    while hi - lo > 1 {
        let mid = (lo + hi) / 2;
        if mid * mid <= n { lo = mid } else { hi = mid }
    }
    lo
}

/// Correctly rounded square root of `x` (round to nearest), in 32-bit integer operations only:
/// +-0 and +inf return themselves, NaN and negative inputs return `f32::NAN` (as libm's generic
/// `sqrtf`), subnormals are normalized first. Never inlined: about 40 instructions, called from
/// hundreds of places (inlined, it would add kilobytes of flash for a few instructions each).
#[inline(never)]
pub fn sqrt_f32(x: f32) -> f32 {
    let bits = x.to_bits();
    // Normal positive inputs: bits - 2^23 below 0x7f00_0000 (exponent field 1 to 254, sign 0).
    let (m, e) = if bits.wrapping_sub(0x0080_0000) < 0x7f00_0000 {
        ((bits & 0x007f_ffff) | 0x0080_0000, (bits >> 23) as i32)
    } else {
        if bits << 1 == 0 || bits == 0x7f80_0000 {
            return x; // +-0, +inf
        }
        if bits > 0x7f80_0000 {
            return f32::NAN; // NaN, or below zero
        }
        // Subnormal: shift the leading one to bit 23; the exponent falls by the same amount.
        let shift = bits.leading_zeros() - 8;
        (bits << shift, 1 - shift as i32)
    };
    let odd = (e & 1) as u32;
    let a = (m << 8) >> odd; // A in [2^30, 2^32)

    // r0 ~ R 2^15 and then r1 ~ R 2^30, R ~ 1 / sqrt(a) in (1, 2], a = A / 2^32 (a16 = a 2^16).
    let r0 = RSQRT[(a >> 25) as usize] as u32;
    let a16 = a >> 16;
    let s = a16 * r0; // a R0 2^31, below 2^31
    let p = (s >> 16) * r0; // a R0^2 2^30
    let h = (3u32 << 30).wrapping_sub(p) >> 16; // (3 - a R0^2) 2^14, about 2^15
    let r1 = r0 * h; // R1 2^30 = R0 (3 - a R0^2) / 2 2^30, at most 2^31

    // y ~ sqrt(A) = a R1 2^16 (a few units low at most), with its exact remainder.
    let y = (a16 * (r1 >> 15)) >> 15;
    let d = a.wrapping_sub(y.wrapping_mul(y)) as i32; // A - y^2, |.| below 2^20
    // 2^6 Q ~ 2^6 (2^9 y + 2^9 d / (2 sqrt(A))) = 2^15 y + d R 2^-2, plus the bias 0.75 2^6.
    let c = ((d >> 3).wrapping_mul((r1 >> 16) as i32)) >> 13;
    let q_est = ((y << 15).wrapping_add(c as u32).wrapping_add(48)) >> 6; // Q or Q + 1
    let rem = (a << 18).wrapping_sub(q_est.wrapping_mul(q_est)) as i32; // N - q_est^2
    let q = q_est.wrapping_add((rem >> 31) as u32); // Q
    let significand = (q + 1) >> 1; // in [2^23, 2^24)

    // Exponent field (e + 127) / 2; the significand's leading one adds the 1 subtracted here.
    let exponent = ((e + 125) >> 1) as u32;
    f32::from_bits((exponent << 23).wrapping_add(significand))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The reference: libm's `sqrtf` for every non-NaN result (on x86 hosts the `sqrtss`
    /// instruction, correctly rounded like libm's generic code); for NaN results the generic
    /// code's `f32::NAN` (`sqrtss` returns the quieted input or 0xffc0_0000 instead).
    fn check(bits: u32) {
        let x = f32::from_bits(bits);
        let got = sqrt_f32(x).to_bits();
        let want = libm::sqrtf(x);
        let want = if want.is_nan() { f32::NAN.to_bits() } else { want.to_bits() };
        assert_eq!(got, want, "sqrt({bits:#010x}) = {got:#010x}, libm {want:#010x}");
    }

    #[test]
    fn every_class() {
        for sign in [0u32, 0x8000_0000] {
            for b in [0u32, 1, 2, 3, 0x0040_0000, 0x007f_fffe, 0x007f_ffff, 0x7f80_0000] {
                check(sign | b); // zeros, subnormals (smallest, largest), infinity
            }
            for b in [0x7f80_0001u32, 0x7fa0_0000, 0x7fbf_ffff, 0x7fc0_0000, 0x7fc0_0001, 0x7fff_ffff] {
                check(sign | b); // signalling and quiet NaNs
            }
            for exp in 1u32..255 {
                for frac in [0u32, 1, 2, 0x0040_0000, 0x007f_fffe, 0x007f_ffff] {
                    check(sign | exp << 23 | frac);
                }
            }
            for shift in 0..23 {
                check(sign | 1 << shift); // every subnormal power of two
                check(sign | ((1 << (shift + 1)) - 1)); // all ones below it
            }
        }
        assert_eq!(sqrt_f32(-0.0).to_bits(), 0x8000_0000);
        assert_eq!(sqrt_f32(f32::INFINITY), f32::INFINITY);
        assert_eq!(sqrt_f32(2.25), 1.5);
    }

    /// Every significand with both exponent parities, near 1, near the smallest normal and near
    /// the largest finite value (the result's significand depends on nothing else, so this covers
    /// every normal input's rounding). A debug build checks every 61st.
    #[test]
    fn every_significand_and_parity() {
        let step = if cfg!(debug_assertions) { 61 } else { 1 };
        for base in [0x3f80_0000u32, 0x4000_0000, 0x0080_0000, 0x0100_0000, 0x7e80_0000, 0x7f00_0000] {
            for frac in (0..1u32 << 23).step_by(step) {
                check(base | frac);
            }
        }
    }

    /// A large deterministic sample of all bit patterns (a 32-bit LCG, full period).
    #[test]
    fn random_bit_patterns() {
        let n = if cfg!(debug_assertions) { 1 << 20 } else { 1 << 24 };
        let mut s = 0x2545_f491u32;
        for _ in 0..n {
            s = s.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
            check(s);
        }
    }

    /// All 2^32 inputs on every core (`cargo test --release -p picomis --lib sqrt -- --ignored`).
    #[test]
    #[ignore = "all 2^32 inputs: about 15 s in release on two cores"]
    fn all_inputs() {
        let threads = std::thread::available_parallelism().map_or(2, |n| n.get()) as u64;
        let chunk = (1u64 << 32) / threads + 1;
        std::thread::scope(|scope| {
            for t in 0..threads {
                scope.spawn(move || {
                    let end = ((t + 1) * chunk).min(1 << 32);
                    for b in t * chunk..end {
                        check(b as u32);
                    }
                });
            }
        });
    }
}
