//! Bit-exactness check of the soft-float routines of picomis-softfloat (`softfloat-check` feature).
//!
//! A deterministic list of operand pairs, about a fifth of them random bit patterns and the rest
//! built to hit the hard cases: alignment shifts of 0 to 33 binades (sticky bits), near and
//! exact cancellation, short significands (exact ties in sums and products, both parities), products
//! near the subnormal boundary and near overflow, subnormal operands, and every pair of special
//! values (signed zeros, infinities, quiet and signalling NaNs, extreme normals and subnormals).
//!
//! For each pair the add, sub, mul, the seven comparisons (the five ordered ones, not-equal and
//! unordered) and a 64-bit integer multiply (`__aeabi_lmul`, used by the random number
//! generator) are folded into FNV-1a digests (a NaN result counts as one canonical NaN: x86
//! and Arm produce different NaN bit patterns for `inf - inf`). The host computes the same
//! digests with its own f32 (`picomis-firmware softfloat-digest`) and `scripts/firmware.sh test`
//! compares the two lines: that comparison is independent of the target's library, whose own
//! routines call the M0's `__clzsi2` too.
//! On the target the check also compares every result, NaN bits included, with
//! compiler-builtins' own routines and counts the mismatches, and also checks the u32 -> f32
//! conversion (`__aeabi_ui2f`) against compiler-builtins' `__floatunsisf` (and on RV32IMC the
//! i32 -> f32 one against `__floatsisf`) on 2^20 values (every leading-one position, exact ties of both parities), and the count of
//! leading zeros (the M0's `__clzsi2`) of the same values against a shift loop. On the M0 it
//! also checks the fixed-point path's integer routines (`kernel/src/num/int_m0.rs`), the quad test's
//! division steps, the 32 x 32 -> 64-bit product and the 64-bit dot product of 32-bit vectors,
//! against the 64-bit division and products on [`DIVISIONS`] operand pairs each.

/// Operand pairs checked.
pub const PAIRS: u32 = 1 << 17;

/// Special values: signed zeros, infinities, NaNs (quiet, signalling, with payloads), the
/// extreme subnormals and normals, and values around 1 and the rounding boundary.
const SPECIALS: [u32; 24] = [
    0x0000_0000,
    0x8000_0000,
    0x7f80_0000,
    0xff80_0000,
    0x7fc0_0000,
    0xffc0_0001,
    0x7f80_0001,
    0xffbf_ffff,
    0x0000_0001,
    0x807f_ffff,
    0x0040_0000,
    0x0080_0000,
    0x8080_0001,
    0x7f7f_ffff,
    0xff7f_fffe,
    0x3f80_0000,
    0xbf80_0000,
    0x3f80_0001,
    0x3fff_ffff,
    0x4b00_0000,
    0x3380_0000,
    0x3400_0000,
    0x1f80_0000,
    0x5f80_0000,
];

/// A 32-bit integer hash (lowbias32).
fn mix(mut x: u32) -> u32 {
    x ^= x >> 16;
    x = x.wrapping_mul(0x7feb_352d);
    x ^= x >> 15;
    x = x.wrapping_mul(0x846c_a68b);
    x ^ (x >> 16)
}

/// `bits` with its exponent field replaced by `e` (0..=255).
fn with_exponent(bits: u32, e: u32) -> u32 {
    (bits & 0x807f_ffff) | ((e & 0xff) << 23)
}

/// Operand pair number `i` (bit patterns).
pub fn operands(i: u32) -> (u32, u32) {
    let r0 = mix(i.wrapping_mul(3).wrapping_add(0x9e37_79b9));
    let r1 = mix(r0 ^ 0x68e3_1da4);
    let r2 = mix(r1 ^ 0xb529_7a4d);
    let ea = (r0 >> 23) & 0xff;
    match i % 10 {
        // Any bit patterns.
        0 | 1 => (r0, r1),
        // b 0..=33 binades below a: alignment shifts, sticky bits, cancellation when the signs
        // differ.
        2 | 3 => {
            let a = with_exponent(r0, 1 + ea % 254);
            let eb = ((a >> 23) & 0xff).saturating_sub(r2 % 34).max(1);
            (a, with_exponent(r1, eb))
        }
        // Near and exact cancellation: b = -(a + k ulps), k in -2..=2.
        4 => {
            let a = with_exponent(r0, 1 + ea % 254);
            let b = (a ^ 0x8000_0000).wrapping_add(r1 % 5).wrapping_sub(2);
            if r2 & 1 == 0 { (a, b) } else { (b, a) }
        }
        // Short significands (12 fraction bits): exact ties in sums and products. Half of them
        // are a + (half an ulp of a), a tie, with both parities of a.
        5 => {
            let a = with_exponent(r0 & 0xffff_f800, 30 + ea % 196);
            let b = if r2 & 1 == 0 {
                with_exponent(r1 & 0xffff_f800, ((a >> 23) & 0xff) - (r2 >> 1) % 26)
            } else {
                with_exponent(r1 & 0x8000_0000, ((a >> 23) & 0xff) - 24)
            };
            (a, b)
        }
        // Products near the subnormal boundary (ea + eb - 127 in -30..=3) and near overflow
        // (in 250..=258).
        6 => {
            let a = with_exponent(r0, 40 + ea % 180);
            let ea = (a >> 23) & 0xff;
            let target = if r2 & 1 == 0 { 97 + (r2 >> 1) % 34 } else { 377 + (r2 >> 1) % 9 };
            let eb = target.saturating_sub(ea).clamp(1, 254);
            if r2 & 2 == 0 { (a, with_exponent(r1, eb)) } else { (with_exponent(r1, eb), a) }
        }
        // Subnormal and tiny operands (exponent fields 0..=3).
        7 => (r0 & 0x81ff_ffff, r1 & 0x81ff_ffff),
        // A special value with a random one.
        8 => {
            let s = SPECIALS[(r2 % SPECIALS.len() as u32) as usize];
            if r2 & 0x100 == 0 { (s, r1) } else { (r1, s) }
        }
        // Two special values.
        _ => {
            let n = SPECIALS.len() as u32;
            (SPECIALS[(r1 % n) as usize], SPECIALS[(r2 % n) as usize])
        }
    }
}

/// u32 -> f32 conversions checked (`__aeabi_ui2f`, target only: against compiler-builtins).
#[cfg(target_os = "none")]
pub const CONVERSIONS: u32 = 1 << 20;

/// Conversion operand number `i`: every value below 2^16, then random values shifted right by
/// 0..=31 bits (every leading-one position), then exact ties and their neighbours: a 24-bit
/// significand of either parity shifted left by 1..=8 with the bits below it 10..0 +- 1 (and so
/// up to 0xffff_ffff, which rounds up to 2^32).
#[cfg(target_os = "none")]
pub fn conversion_operand(i: u32) -> u32 {
    let r = mix(i ^ 0x5bd1_e995);
    match i >> 16 {
        0 => i,
        1..=7 => r >> (i % 32),
        _ => {
            let s = 1 + (i >> 2) % 8;
            let m = (r >> 8) | 1 << 23;
            let tie = (m << s) | 1 << (s - 1);
            match i % 4 {
                0 => tie,
                1 => tie.wrapping_sub(1),
                2 => tie.wrapping_add(1),
                _ => u32::MAX - (r % 256),
            }
        }
    }
}

/// Division pairs checked (about 2 s of QEMU per million).
pub const DIV_PAIRS: u32 = 1 << 24;

/// A float from its sign (bit 31 of `sign`), biased exponent (0..=255) and 23 fraction bits.
fn float_bits(sign: u32, e: u32, fraction: u32) -> u32 {
    (sign & 0x8000_0000) | (e & 0xff) << 23 | (fraction & 0x7f_ffff)
}

/// Division pair number `i` (bit patterns): random bits and the classes that are hard for a
/// division (see the match arms). The M0's `__aeabi_fdiv` reads a 128-entry reciprocal table
/// indexed by the divisor's top 7 fraction bits, so one class puts the divisor at the table's
/// boundaries.
pub fn div_operands(i: u32) -> (u32, u32) {
    let r0 = mix(i.wrapping_mul(5).wrapping_add(0x2545_f491));
    let r1 = mix(r0 ^ 0x5bd1_e995);
    let r2 = mix(r1 ^ 0x27d4_eb2f);
    let r3 = mix(r2 ^ 0x1656_67b1);
    // An exponent for b that leaves room for a's to be chosen relative to it.
    let eb = 40 + r2 % 170;
    match i % 12 {
        // Any bit patterns.
        0 | 1 => (r0, r1),
        // Normal operands, any exponents.
        2 => (float_bits(r0, 1 + (r2 >> 8) % 254, r0), float_bits(r1, 1 + (r3 >> 8) % 254, r1)),
        // Results near and below the smallest normal: subnormal results, underflow to zero and
        // rounding up to the smallest normal (ea - eb + 127 in -30..=2).
        3 => {
            let eb = 160 + r2 % 90;
            (float_bits(r0, eb - 157 + r3 % 33, r0), float_bits(r1, eb, r1))
        }
        // Results near and above the largest normal: overflow to infinity and rounding up to
        // it (ea - eb + 127 in 252..=258).
        4 => {
            let eb = 1 + r2 % 120;
            (float_bits(r0, eb + 125 + r3 % 7, r0), float_bits(r1, eb, r1))
        }
        // The divisor's significand at a reciprocal-table boundary (top 7 fraction bits k, the
        // low 16 bits within 3 of 0 or of 0xffff), or the dividend's.
        5 => {
            let k = r2 % 128;
            let low = [0, 1, 2, 3, 0xffff, 0xfffe, 0xfffd, 0xfffc][(r3 % 8) as usize];
            let edge = float_bits(r1, eb, k << 16 | low);
            let a = float_bits(r0, 1 + (r3 >> 8) % 254, r0);
            if r3 & 0x10 == 0 {
                (a, edge)
            } else {
                (float_bits(r0, 1 + (r3 >> 8) % 254, k << 16 | low), edge)
            }
        }
        // The dividend's significand equal to the divisor's, or within 2 ulps (both sides of the
        // A < B doubling), any exponents and signs.
        6 => {
            let b = float_bits(r1, eb, r1);
            let f = (r1 & 0x7f_ffff).wrapping_add(r3 % 5).wrapping_sub(2) & 0x7f_ffff;
            (float_bits(r0, 1 + (r2 >> 8) % 254, f), b)
        }
        // Powers of two: the divisor, the dividend or both.
        7 => {
            let p = float_bits(r3, 1 + (r2 >> 8) % 254, 0);
            match r3 % 3 {
                0 => (float_bits(r0, 1 + (r0 >> 8) % 254, r0), p),
                1 => (p, float_bits(r1, eb, r1)),
                _ => (p, float_bits(r1, 1 + (r1 >> 8) % 254, 0)),
            }
        }
        // Quotients within an ulp/2^24 of halfway between two floats (exact ties cannot happen
        // with a normal result): a significand A = floor(Q B / 2^24) + {0, 1} for an odd Q, so
        // that A 2^24 / B is just below or just above the odd Q.
        8 => {
            let sb = 1 << 23 | (r1 & 0x7f_ffff);
            let span = ((1u64 << 48) / u64::from(sb)) as u32 - (1 << 24); // A < 2^24
            let q = ((1 << 24) + r2 % span.max(1)) | 1;
            let sa = ((u64::from(q) * u64::from(sb)) >> 24) as u32 + (r3 & 1);
            let sa = sa.min((1 << 24) - 1);
            (float_bits(r0, 1 + (r3 >> 8) % 254, sa), float_bits(r1, eb, sb))
        }
        // Exact quotients of short significands (12 bits) made subnormal, 0 to 13 of their bits
        // shifted out: exact results, exact ties of both parities (round to even), underflow.
        9 => {
            let mq = 1 << 11 | (r0 & 0x7ff);
            let mb = 1 << 11 | (r1 & 0x7ff);
            // a's significand mq mb (24 bits, normalized) over b's mb 2^12: the quotient is
            // mq 2^-12, or mq 2^-11 when the product was shifted up, times 2^(ea - eb).
            let (p, up) = if mq * mb < 1 << 23 { ((mq * mb) << 1, 1) } else { (mq * mb, 0) };
            // Biased exponent of the quotient ea - eb + 126 + up = 1 - s for s in 12..=25.
            let eb = 160 + r2 % 90;
            let ea = eb - 125 - up - (12 + r3 % 14);
            (float_bits(r0, ea, p), float_bits(r1, eb, mb << 12))
        }
        // Subnormal and tiny operands (exponent fields 0..=3), both signs, against normals or
        // each other.
        10 => match r3 % 3 {
            0 => (r0 & 0x81ff_ffff, r1 & 0x81ff_ffff),
            1 => (r0 & 0x81ff_ffff, float_bits(r1, 1 + (r2 >> 8) % 254, r1)),
            _ => (float_bits(r0, 1 + (r2 >> 8) % 254, r0), r1 & 0x81ff_ffff),
        },
        // Special values (signed zeros, infinities, NaNs, extreme normals and subnormals) with a
        // random operand or with each other.
        _ => {
            let n = SPECIALS.len() as u32;
            let s = SPECIALS[(r2 % n) as usize];
            match r3 % 3 {
                0 => (s, r1),
                1 => (r0, s),
                _ => (s, SPECIALS[(r1 % n) as usize]),
            }
        }
    }
}

/// One NaN for all: x86 and Arm give different NaN bit patterns.
pub fn canonical(bits: u32) -> u32 {
    if (bits << 1) > 0xff00_0000 { 0x7fc0_0000 } else { bits }
}

/// The comparisons as bits: eq, lt, le, gt, ge, ne and unordered (a NaN among them).
pub fn compare_bits(a: f32, b: f32) -> u32 {
    u32::from(a == b)
        | u32::from(a < b) << 1
        | u32::from(a <= b) << 2
        | u32::from(a > b) << 3
        | u32::from(a >= b) << 4
        | u32::from(a != b) << 5
        | u32::from(a.is_nan() || b.is_nan()) << 6
}

/// FNV-1a digests of the results, one per operation (`lmul`: the 64-bit integer multiply,
/// whose hand-written `__aeabi_lmul` is checked here too).
#[derive(Clone, Copy, PartialEq, Eq)]
pub struct Digests {
    pub add: u32,
    pub sub: u32,
    pub mul: u32,
    pub cmp: u32,
    pub lmul: u32,
    /// The quotients of the [`DIV_PAIRS`] division pairs ([`div_operands`]).
    pub div: u32,
    /// The dot products of the [`DOTS`] vector pairs ([`dot_operands`]), `picomis::num::dot`.
    pub dot: u32,
}

impl Digests {
    pub const fn new() -> Self {
        Self {
            add: 0x811c_9dc5,
            sub: 0x811c_9dc5,
            mul: 0x811c_9dc5,
            cmp: 0x811c_9dc5,
            lmul: 0x811c_9dc5,
            div: 0x811c_9dc5,
            dot: 0x811c_9dc5,
        }
    }

    fn fold(h: u32, v: u32) -> u32 {
        v.to_le_bytes().iter().fold(h, |h, &b| (h ^ u32::from(b)).wrapping_mul(0x0100_0193))
    }

    /// Adds one pair's results (add, sub and mul bits, comparison bits, 64-bit product).
    pub fn push(&mut self, add: u32, sub: u32, mul: u32, cmp: u32, lmul: u64) {
        self.add = Self::fold(self.add, canonical(add));
        self.sub = Self::fold(self.sub, canonical(sub));
        self.mul = Self::fold(self.mul, canonical(mul));
        self.cmp = Self::fold(self.cmp, cmp);
        self.lmul = Self::fold(Self::fold(self.lmul, lmul as u32), (lmul >> 32) as u32);
    }
}

/// Digests of this machine's f32 operations (the host's reference; on the target, the
/// routines under test). `each_quotient(i, a, b, a / b)` sees every division (the target
/// compares it with compiler-builtins' there, so that the long division run is done once).
#[inline(never)]
pub fn digests(mut each_quotient: impl FnMut(u32, u32, u32, u32)) -> Digests {
    let mut d = Digests::new();
    for i in 0..PAIRS {
        let (a, b) = operands(i);
        let (x, y) = (core::hint::black_box(f32::from_bits(a)), core::hint::black_box(f32::from_bits(b)));
        let (p, q) = wide(i, a, b);
        let lmul = core::hint::black_box(p).wrapping_mul(core::hint::black_box(q));
        d.push((x + y).to_bits(), (x - y).to_bits(), (x * y).to_bits(), compare_bits(x, y), lmul);
    }
    for i in 0..DOTS {
        let (a, b) = dot_operands(i);
        let (a, b) = (core::hint::black_box(a), core::hint::black_box(b));
        d.dot = Digests::fold(d.dot, canonical(picomis::num::dot(a, b).to_bits()));
    }
    for i in 0..DIV_PAIRS {
        let (a, b) = div_operands(i);
        let (x, y) = (core::hint::black_box(f32::from_bits(a)), core::hint::black_box(f32::from_bits(b)));
        let q = (x / y).to_bits();
        d.div = Digests::fold(d.div, canonical(q));
        each_quotient(i, a, b, q);
    }
    d
}

/// Vector pairs checked by the dot product.
pub const DOTS: u32 = 1 << 18;

/// Vector pair number `i` for the dot product (`picomis::num::dot`, the kernel's; on RV32IMC a
/// hand-written routine that keeps the products and the partial sum unpacked):
/// - three of the operand pairs above (hard cases of products: special values, subnormal and
///   overflowing products, exact ties);
/// - nearly cancelling products (the second a neighbour of the first's negation, by a few units
///   in the last place or a power of two): exact zeros and long normalizations of the sum;
/// - values of a render's magnitude (exponents 2^-8 to 2^8, any signs and fractions), with
///   random components set to +0 or -0 (a normal's zero components).
pub fn dot_operands(i: u32) -> (picomis::Vec3, picomis::Vec3) {
    let v =
        |a: [u32; 3]| picomis::Vec3::new(f32::from_bits(a[0]), f32::from_bits(a[1]), f32::from_bits(a[2]));
    let r = |k: u32| mix(i.wrapping_mul(7).wrapping_add(k).wrapping_mul(0x2c1b_3c6d) ^ 0x5bd1_e995);
    let moderate = |x: u32| with_exponent(x, 119 + (x >> 24) % 17);
    match i % 3 {
        0 => {
            let (p, q, t) = (operands(3 * i), operands(3 * i + 1), operands(3 * i + 2));
            (v([p.0, q.0, t.0]), v([p.1, q.1, t.1]))
        }
        1 => {
            let (x, y, z, w) = (moderate(r(0)), moderate(r(1)), moderate(r(2)), moderate(r(3)));
            // y' = y nudged by a few ulps (or a binade), x' = -x: x y + x' y' nearly cancels.
            let nudge = match r(4) % 4 {
                0 => 0,
                1 => r(5) % 8,
                2 => 0x0080_0000,
                _ => r(5) % 0x100,
            };
            let y2 = if r(6) & 1 == 0 { y.wrapping_add(nudge) } else { y.wrapping_sub(nudge) };
            let order = r(7) % 3;
            let (a, b) = ([x, x ^ 0x8000_0000, z], [y, y2, w]);
            let rot = |u: [u32; 3]| match order {
                0 => u,
                1 => [u[2], u[0], u[1]],
                _ => [u[1], u[2], u[0]],
            };
            (v(rot(a)), v(rot(b)))
        }
        _ => {
            let mut a = [moderate(r(0)), moderate(r(1)), moderate(r(2))];
            let mut b = [moderate(r(3)), moderate(r(4)), moderate(r(5))];
            let zeros = r(6);
            for k in 0..3 {
                if zeros >> k & 7 == 0 {
                    a[k] &= 0x8000_0000;
                }
                if zeros >> (k + 8) & 7 == 0 {
                    b[k] &= 0x8000_0000;
                }
            }
            (v(a), v(b))
        }
    }
}

/// Operand pairs for each of the M0's integer routines of the fixed-point path.
#[cfg_attr(not(target_os = "none"), allow(dead_code))]
pub const DIVISIONS: u32 = 1 << 16;

/// Division pair `i` in the steps' bounds, 0 <= n < 2^31 d and 1 <= d <= 2^31: every eighth from
/// the edges (the divisor's extremes and powers of two, the dividend at 0, d - 1, d, multiples of
/// d and the top of the range), the rest random divisors of every magnitude with random
/// dividends of every magnitude below the bound.
#[cfg_attr(not(all(target_arch = "arm", target_abi = "eabi")), allow(dead_code))]
pub fn division_operands(i: u32) -> (u64, u32) {
    const D: [u32; 8] = [1, 2, 3, 0x8000_0000, 0x7fff_ffff, 0x1_0000, 0x1_0001, 0x5555_5555];
    let (a, b) = (mix(i ^ 0x5bd1_e995), mix(i.wrapping_add(0x68e3_1da4)));
    let d = if i.is_multiple_of(8) { D[(a % 8) as usize] } else { 1 + ((a >> 1) >> (b % 31)) };
    let top = u64::from(d) << 31; // the bound: n < top
    let n = if i.is_multiple_of(8) {
        let k = u64::from(b);
        [0, u64::from(d) - 1, u64::from(d), top - 1, top - u64::from(d), k * u64::from(d), k, top >> 1]
            [(b >> 29) as usize]
    } else {
        let c = mix(a ^ b);
        (u64::from(c) << 32 | u64::from(mix(c))) >> (b >> 26)
    };
    (n % top, d)
}

/// Factors of the M0's 32 x 32 -> 64-bit product, pair `i`: every eighth from the edges (0, 1,
/// -1, the extremes, the 16-bit halves' boundaries), the rest random of every magnitude and sign.
#[cfg_attr(not(all(target_arch = "arm", target_abi = "eabi")), allow(dead_code))]
pub fn wide_factors(i: u32) -> (i32, i32) {
    const E: [i32; 8] = [0, 1, -1, i32::MIN, i32::MAX, 0xffff, -0x1_0000, 0x7fff_8000];
    let (a, b) = (mix(i ^ 0x2545_f491), mix(i.wrapping_add(0x1b87_3593)));
    if i.is_multiple_of(8) {
        (E[(a % 8) as usize], E[(b % 8) as usize])
    } else {
        ((a as i32) >> (b % 32), (b as i32) >> (a % 32))
    }
}

/// 64-bit operands for the integer multiply, from pair `i`'s bits.
pub fn wide(i: u32, a: u32, b: u32) -> (u64, u64) {
    let c = mix(a ^ i);
    (u64::from(a) << 32 | u64::from(b), u64::from(c) << 32 | u64::from(mix(c)))
}

/// Target side: the digests of the routines linked into the firmware, and a bit-exact
/// comparison with compiler-builtins' own routines.
#[cfg(target_os = "none")]
pub fn run() -> u32 {
    // compiler-builtins' routines (on RV32IMC the linker's --wrap gives them the __real_ prefix:
    // their own names lead to ours, see build.rs).
    unsafe extern "C" {
        #[cfg_attr(target_arch = "riscv32", link_name = "__real___addsf3")]
        fn __addsf3(a: f32, b: f32) -> f32;
        #[cfg_attr(target_arch = "riscv32", link_name = "__real___subsf3")]
        fn __subsf3(a: f32, b: f32) -> f32;
        #[cfg_attr(target_arch = "riscv32", link_name = "__real___mulsf3")]
        fn __mulsf3(a: f32, b: f32) -> f32;
        #[cfg_attr(target_arch = "riscv32", link_name = "__real___eqsf2")]
        fn __eqsf2(a: f32, b: f32) -> i32;
        #[cfg_attr(target_arch = "riscv32", link_name = "__real___ltsf2")]
        fn __ltsf2(a: f32, b: f32) -> i32;
        #[cfg_attr(target_arch = "riscv32", link_name = "__real___lesf2")]
        fn __lesf2(a: f32, b: f32) -> i32;
        #[cfg_attr(target_arch = "riscv32", link_name = "__real___gtsf2")]
        fn __gtsf2(a: f32, b: f32) -> i32;
        #[cfg_attr(target_arch = "riscv32", link_name = "__real___gesf2")]
        fn __gesf2(a: f32, b: f32) -> i32;
        #[cfg_attr(target_arch = "riscv32", link_name = "__real___nesf2")]
        fn __nesf2(a: f32, b: f32) -> i32;
        #[cfg_attr(target_arch = "riscv32", link_name = "__real___unordsf2")]
        fn __unordsf2(a: f32, b: f32) -> i32;
        fn __muldi3(a: u64, b: u64) -> u64;
        #[cfg_attr(target_arch = "riscv32", link_name = "__real___divsf3")]
        fn __divsf3(a: f32, b: f32) -> f32;
        #[cfg_attr(target_arch = "riscv32", link_name = "__real___floatunsisf")]
        fn __floatunsisf(a: u32) -> f32;
        #[cfg_attr(target_arch = "riscv32", link_name = "__real___floatsisf")]
        fn __floatsisf(a: i32) -> f32;
    }
    let mut mismatches = 0u32;
    let d = digests(|i, a, b, q| {
        // SAFETY: compiler-builtins' soft-float division takes and returns plain f32 values.
        let lib = unsafe { __divsf3(f32::from_bits(a), f32::from_bits(b)) }.to_bits();
        if q != lib {
            if mismatches < 8 {
                info!("softfloat mismatch: division pair {} a {} b {}: ours {} library {}", i, a, b, q, lib);
            }
            mismatches += 1;
        }
    });
    info!(
        "softfloat digest: {} pairs, add {} sub {} mul {} cmp {} lmul {}; {} division pairs, div {}",
        PAIRS, d.add, d.sub, d.mul, d.cmp, d.lmul, DIV_PAIRS, d.div
    );
    info!("softfloat dot digest: {} pairs, dot {}", DOTS, d.dot);
    for i in 0..DOTS {
        let (a, b) = dot_operands(i);
        let (a, b) = (core::hint::black_box(a), core::hint::black_box(b));
        // glam's dot product: the library's multiply and add, one call each.
        let (ours, lib) = (picomis::num::dot(a, b).to_bits(), a.dot(b).to_bits());
        if ours != lib {
            if mismatches < 8 {
                // The operands are `dot_operands(i)`, on the host too.
                info!("softfloat mismatch: dot pair {}: ours {} library {}", i, ours, lib);
            }
            mismatches += 1;
        }
    }
    for i in 0..PAIRS {
        let (a, b) = operands(i);
        let (x, y) = (core::hint::black_box(f32::from_bits(a)), core::hint::black_box(f32::from_bits(b)));
        // SAFETY: compiler-builtins' soft-float routines take and return plain f32 values.
        let lib = unsafe {
            [
                __addsf3(x, y).to_bits(),
                __subsf3(x, y).to_bits(),
                __mulsf3(x, y).to_bits(),
                u32::from(__eqsf2(x, y) == 0)
                    | u32::from(__ltsf2(x, y) < 0) << 1
                    | u32::from(__lesf2(x, y) <= 0) << 2
                    | u32::from(__gtsf2(x, y) > 0) << 3
                    | u32::from(__gesf2(x, y) >= 0) << 4
                    | u32::from(__nesf2(x, y) != 0) << 5
                    | u32::from(__unordsf2(x, y) != 0) << 6,
            ]
        };
        let (p, q) = wide(i, a, b);
        let (p, q) = (core::hint::black_box(p), core::hint::black_box(q));
        // SAFETY: compiler-builtins' 64-bit multiply takes and returns plain integers.
        let (ours64, lib64) = (p.wrapping_mul(q), unsafe { __muldi3(p, q) });
        if ours64 != lib64 {
            if mismatches < 8 {
                info!("softfloat mismatch: pair {} lmul {} x {}: ours {} library {}", i, p, q, ours64, lib64);
            }
            mismatches += 1;
        }
        let ours = [(x + y).to_bits(), (x - y).to_bits(), (x * y).to_bits(), compare_bits(x, y)];
        for (k, (o, l)) in ours.iter().zip(lib.iter()).enumerate() {
            if o != l {
                if mismatches < 8 {
                    info!(
                        "softfloat mismatch: pair {} op {} a {} b {}: ours {} library {}",
                        i, k as u32, a, b, *o, *l
                    );
                }
                mismatches += 1;
            }
        }
    }
    for i in 0..CONVERSIONS {
        let u = core::hint::black_box(conversion_operand(i));
        // SAFETY: compiler-builtins' conversion takes and returns plain values.
        let (ours, lib) = (u as f32, unsafe { __floatunsisf(u) });
        if ours.to_bits() != lib.to_bits() {
            if mismatches < 8 {
                info!(
                    "softfloat mismatch: u32 -> f32 {}: ours {} library {}",
                    u,
                    ours.to_bits(),
                    lib.to_bits()
                );
            }
            mismatches += 1;
        }
        // The same bits as i32, and i32::MIN (RV32IMC's `__wrap___floatsisf`; the M0 runs
        // compiler-builtins').
        let v = if i == 1 { i32::MIN } else { u as i32 };
        // SAFETY: as above.
        let (ours, lib) = (v as f32, unsafe { __floatsisf(v) });
        if ours.to_bits() != lib.to_bits() {
            if mismatches < 8 {
                info!(
                    "softfloat mismatch: i32 -> f32 {}: ours {} library {}",
                    v as u32,
                    ours.to_bits(),
                    lib.to_bits()
                );
            }
            mismatches += 1;
        }
        // The leading zeros (the M0's hand-written `__clzsi2`) against a shift loop.
        let (mut want, mut v) = (32, u);
        while v != 0 {
            v >>= 1;
            want -= 1;
        }
        if u.leading_zeros() != want {
            if mismatches < 8 {
                info!("softfloat mismatch: leading zeros of {}: ours {} want {}", u, u.leading_zeros(), want);
            }
            mismatches += 1;
        }
    }
    // The M0's integer routines of the fixed-point path (kernel/src/num/int_m0.rs): the division
    // steps against the 64-bit division, the 32 x 32 -> 64-bit product against the 64-bit one.
    #[cfg(all(target_arch = "arm", target_abi = "eabi"))]
    {
        unsafe extern "C" {
            fn picomis_div_steps(rem: u32, w: u32, d: u32) -> u32;
            fn picomis_mul_wide(a: i32, b: i32) -> i64;
            fn picomis_dot32(a: &[i32; 3], b: &[i32; 3]) -> i64;
        }
        for i in 0..DIVISIONS {
            let (a, b) = wide_factors(i);
            // SAFETY: the routine takes and returns plain integers.
            let ours = unsafe { picomis_mul_wide(a, b) };
            let want = i64::from(a) * i64::from(b);
            if ours != want {
                if mismatches < 8 {
                    info!(
                        "softfloat mismatch: wide product pair {}: ours {} want {}",
                        i, ours as u64, want as u64
                    );
                }
                mismatches += 1;
            }
        }
        for i in 0..DIVISIONS {
            let ((a0, b0), (a1, b1), (a2, b2)) =
                (wide_factors(3 * i), wide_factors(3 * i + 1), wide_factors(3 * i + 2));
            let (a, b) = ([a0, a1, a2], [b0, b1, b2]);
            // SAFETY: the routine reads three i32 through each reference.
            let ours = unsafe { picomis_dot32(&a, &b) };
            let want = (0..3).fold(0i64, |sum, k| sum.wrapping_add(i64::from(a[k]) * i64::from(b[k])));
            if ours != want {
                if mismatches < 8 {
                    info!(
                        "softfloat mismatch: wide dot product {}: ours {} want {}",
                        i, ours as u64, want as u64
                    );
                }
                mismatches += 1;
            }
        }
        for i in 0..DIVISIONS {
            let (n, d) = division_operands(i);
            // SAFETY: the routine takes and returns plain integers (see kernel/src/query/fixed.rs).
            let ours = unsafe { picomis_div_steps((n >> 31) as u32, (n as u32) << 1, d) };
            let want = n / u64::from(d);
            if u64::from(ours) != want {
                if mismatches < 8 {
                    info!("softfloat mismatch: division steps {} / {}: ours {} want {}", n, d, ours, want);
                }
                mismatches += 1;
            }
        }
    }
    let divisions = if cfg!(all(target_arch = "arm", target_abi = "eabi")) { 3 * DIVISIONS } else { 0 };
    info!(
        "softfloat library comparison: {} mismatches in {} results",
        mismatches,
        5 * PAIRS + DIV_PAIRS + 2 * CONVERSIONS + DOTS + divisions
    );
    if mismatches == 0 { 0 } else { 6 }
}
