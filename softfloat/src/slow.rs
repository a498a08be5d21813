//! The rare cases of the add, multiply and divide: subnormal, infinite, NaN and zero operands,
//! subnormal and overflowing results. The hand-written fast paths (`m0.s`, `rv32.s`) hand these
//! over with the original operands. Bit for bit compiler-builtins' `__addsf3`, `__mulsf3` and
//! `__divsf3` (round to nearest, ties to even; a NaN operand comes back quieted with its payload,
//! the first one if both are, its sign kept by the multiply and the division and dropped by the
//! add; an invalid operation gives `0x7fc0_0000`), in integer
//! operations only, written for size: one unpack and one round-and-pack serve the three, and the
//! division is a bit-by-bit long division (no 64-bit division, no table). On the targets that
//! link it, about 0.7 KiB of code instead of compiler-builtins' three routines (1.5-2 KiB, built for
//! speed); they take tens to a few hundred instructions more, on operands a render almost never
//! meets.
//!
//! Plain functions on bit patterns, so the host tests them against its own f32
//! (`tools/tests/softfloat_slow.rs`); the soft-float targets export them to the assembler as
//! `picomis_fadd_slow`, `picomis_fmul_slow` and `picomis_fdiv_slow`.

const SIGN: u32 = 0x8000_0000;
const INF: u32 = 0x7f80_0000;
const QUIET: u32 = 0x0040_0000;
/// The NaN of an invalid operation (inf - inf, 0 * inf, 0 / 0, inf / inf).
const DEFAULT_NAN: u32 = 0x7fc0_0000;

/// The biased exponent and the 24-bit significand (leading one at bit 23) of a finite, non-zero
/// magnitude; a subnormal's significand is shifted up and its exponent goes to 0 and below.
#[inline(never)]
fn unpack(abs: u32) -> (i32, u32) {
    let e = (abs >> 23) as i32;
    if e != 0 {
        return (e, (abs & 0x007f_ffff) | 0x0080_0000);
    }
    let (mut e, mut m) = (1, abs);
    while m & 0x0080_0000 == 0 {
        m <<= 1;
        e -= 1;
    }
    (e, m)
}

/// `m >> k` with the bits shifted out ORed into bit 0 (sticky), for any `k >= 0`.
#[inline(never)]
fn shift_right_sticky(m: u32, k: i32) -> u32 {
    if k <= 0 {
        m
    } else if k < 32 {
        (m >> k) | u32::from(m << (32 - k) != 0)
    } else {
        u32::from(m != 0)
    }
}

/// The float `sign * m / 2^31 * 2^(e - 127)` for `m` with its leading one at bit 31 (eight bits
/// below the last kept one: the round bit and sticky bits), rounded to nearest, ties to even:
/// infinity above the largest finite, a subnormal or zero below the smallest normal.
#[inline(never)]
fn round_pack(sign: u32, e: i32, m: u32) -> u32 {
    if e >= 255 {
        return sign | INF;
    }
    // A subnormal result: the significand moves down to the exponent 1's scale, its leading one
    // (if any is left) below bit 31, so it packs without an exponent.
    let (e, m) = if e < 1 { (1, shift_right_sticky(m, 1 - e)) } else { (e, m) };
    // (e - 1) << 23 plus the significand with its leading one: e << 23 for a normal one.
    let bits = (((e - 1) as u32) << 23) + (m >> 8);
    let rest = m & 0xff;
    let up = u32::from(rest > 0x80 || (rest == 0x80 && bits & 1 == 1));
    // A carry out of the significand goes into the exponent, up to infinity: right.
    sign | (bits + up)
}

/// The first NaN operand with its quiet bit set, its sign kept (compiler-builtins' rule for the
/// multiply and the division; its add then drops the sign).
#[inline]
fn nan_operand(a: u32, b: u32) -> Option<u32> {
    if a & !SIGN > INF {
        Some(a | QUIET)
    } else if b & !SIGN > INF {
        Some(b | QUIET)
    } else {
        None
    }
}

/// `a + b` on bit patterns.
pub fn add(a: u32, b: u32) -> u32 {
    if let Some(nan) = nan_operand(a, b) {
        return nan & !SIGN;
    }
    let (a_abs, b_abs) = (a & !SIGN, b & !SIGN);
    if a_abs == INF {
        return if b_abs == INF && (a ^ b) & SIGN != 0 { DEFAULT_NAN } else { a };
    }
    if b_abs == INF {
        return b;
    }
    if b_abs == 0 {
        // -0 only when both are -0; a + 0 = a otherwise.
        return if a_abs == 0 { a & b } else { a };
    }
    if a_abs == 0 {
        return b;
    }
    // x: the larger magnitude, whose sign the result takes.
    let (x, y) = if a_abs >= b_abs { (a, b) } else { (b, a) };
    let (ex, mx) = unpack(x & !SIGN);
    let (ey, my) = unpack(y & !SIGN);
    // Leading ones at bit 30 (a carry fits), the smaller aligned with a sticky bit.
    let mx = mx << 7;
    let my = shift_right_sticky(my << 7, ex - ey);
    let m = if (x ^ y) & SIGN != 0 {
        let d = mx - my;
        if d == 0 {
            return 0; // x - x = +0
        }
        d
    } else {
        mx + my
    };
    // Normalize to bit 31: a carry shifts by 0, a cancellation by more than 1 (exact then: the
    // smaller was not shifted by more than one place, so nothing was lost to the sticky bit).
    let (mut e, mut m) = (ex + 1, m);
    while m & SIGN == 0 {
        m <<= 1;
        e -= 1;
    }
    round_pack(x & SIGN, e, m)
}

/// `a * b` on bit patterns.
pub fn mul(a: u32, b: u32) -> u32 {
    if let Some(nan) = nan_operand(a, b) {
        return nan;
    }
    let (a_abs, b_abs) = (a & !SIGN, b & !SIGN);
    let sign = (a ^ b) & SIGN;
    if a_abs == INF || b_abs == INF {
        // inf * 0 is invalid; inf * anything else is inf.
        return if a_abs == 0 || b_abs == 0 { DEFAULT_NAN } else { sign | INF };
    }
    if a_abs == 0 || b_abs == 0 {
        return sign;
    }
    let (ea, ma) = unpack(a_abs);
    let (eb, mb) = unpack(b_abs);
    // A 47- or 48-bit product: its top 32 bits, the rest as a sticky bit, then the leading one
    // at bit 31 (constant shifts only: no 64-bit shift routine).
    let p = u64::from(ma) * u64::from(mb);
    let m = (p >> 16) as u32 | u32::from(p as u32 & 0xffff != 0);
    if m & SIGN != 0 {
        round_pack(sign, ea + eb - 126, m) // the product in [2, 4)
    } else {
        round_pack(sign, ea + eb - 127, m << 1)
    }
}

/// `a / b` on bit patterns.
pub fn div(a: u32, b: u32) -> u32 {
    if let Some(nan) = nan_operand(a, b) {
        return nan;
    }
    let (a_abs, b_abs) = (a & !SIGN, b & !SIGN);
    let sign = (a ^ b) & SIGN;
    if a_abs == INF {
        return if b_abs == INF { DEFAULT_NAN } else { sign | INF };
    }
    if b_abs == INF {
        return sign;
    }
    if b_abs == 0 {
        return if a_abs == 0 { DEFAULT_NAN } else { sign | INF };
    }
    if a_abs == 0 {
        return sign;
    }
    let (mut e, mut r) = unpack(a_abs);
    let (eb, mb) = unpack(b_abs);
    e -= eb - 127;
    // A quotient in [1, 2): the dividend's significand not below the divisor's.
    if r < mb {
        r <<= 1;
        e -= 1;
    }
    // 26 quotient bits (24 kept, the round bit and one more), the remainder as the sticky bit.
    // The first bit is 1 (r >= mb): the loop ends when it reaches bit 25, after 26 steps (a
    // condition on the data, so that an optimiser for speed does not unroll it).
    let mut q = 0u32;
    while q & (1 << 25) == 0 {
        q <<= 1;
        if r >= mb {
            r -= mb;
            q |= 1;
        }
        r <<= 1;
    }
    round_pack(sign, e, (q << 6) | u32::from(r != 0))
}

/// The entry points the assembler's fast paths tail-call (C calling convention, bit patterns in
/// and out).
#[cfg(any(
    all(target_arch = "arm", target_abi = "eabi"),
    all(target_arch = "riscv32", not(target_feature = "f"))
))]
mod exports {
    #[unsafe(no_mangle)]
    extern "C" fn picomis_fadd_slow(a: u32, b: u32) -> u32 {
        super::add(a, b)
    }

    #[unsafe(no_mangle)]
    extern "C" fn picomis_fmul_slow(a: u32, b: u32) -> u32 {
        super::mul(a, b)
    }

    #[unsafe(no_mangle)]
    extern "C" fn picomis_fdiv_slow(a: u32, b: u32) -> u32 {
        super::div(a, b)
    }
}
