//! The error bound of the Cortex-M0 division (`__aeabi_fdiv` in picomis-softfloat's `m0.s`, and
//! RV32IMC's `__wrap___divsf3` in `rv32.s`, the same algorithm step for step), proved on the host
//! over every divisor significand:
//! `cargo test --release -p picomis-tools --test fdiv_bound -- --nocapture` prints the bound.
//!
//! The routine computes Q' = floor(A 2^24 / B) for 24-bit significands B in [2^23, 2^24) and A in
//! [B, 2B) from a 16-bit reciprocal X of B (a table entry and one Newton step), in two digit
//! steps whose remainders it computes modulo 2^32 with `MULS`. That is right only if each true
//! remainder is in [0, 2^32), the first one below 2^27 (so that `(r1 >> 11) * X` fits 32 bits),
//! every product fits 32 bits, and the estimate Q before the correction loop is at most Q' (the
//! loop only counts up). [`model`] is the routine's integer arithmetic step by step, in the
//! same 32-bit wrapping operations; [`bound`] derives, for one B and every A at once, how far
//! below Q' the estimate can be. [`every_divisor_significand`] checks every B (2^23 of them) with
//! the bound and with the model on the dividends that are worst for the bound;
//! [`whole_division_on_the_check_pairs`] checks the whole division (exponents, rounding, the cases
//! handed to compiler-builtins) against the host's f32 on the soft-float check's division pairs,
//! the pairs on which `scripts/firmware.sh test` checks the routine itself under QEMU against
//! compiler-builtins: so the model is the routine there.

/// The soft-float check's operand pairs (the firmware's `softfloat-check` runs the routines on
/// them; one definition, read here for its [`fpcheck::div_operands`]).
#[path = "../../firmware/src/fpcheck.rs"]
#[allow(dead_code)]
mod fpcheck;

/// The table entry for a divisor significand `b` (the assembler's `.rept` computes the same
/// 128 values): 2^24 / (257 + 2i) for B in [2^23 + 2^16 i, 2^23 + 2^16 (i + 1)).
fn table(b: u32) -> u32 {
    let i = (b >> 16) - 128;
    (1 << 24) / (257 + 2 * i)
}

/// The reciprocal X <= 2^39 / B after the Newton step, as the routine computes it, or `None`
/// when one of its products would not fit 32 bits.
fn reciprocal(b: u32) -> Option<u32> {
    let x0 = table(b);
    let b16 = (b >> 8) + 1;
    let p = u64::from(x0) * u64::from(b16);
    if p >= 1 << 32 {
        return None;
    }
    let e = ((1u32 << 31).wrapping_sub(p as u32)) as i32; // E = 2^31 - P
    let t = i64::from(x0) * i64::from(e >> 8);
    if !(-(1 << 31)..1 << 31).contains(&t) {
        return None;
    }
    let x = (x0 as i32).wrapping_add((t as i32) >> 23);
    u32::try_from(x).ok()
}

/// The routine's quotient for significands `a` in [b, 2b) and `b` in [2^23, 2^24): Q' and the
/// number of correction steps it took (0 or 1), in the routine's 32-bit operations; `None` when
/// a product overflows 32 bits, a remainder leaves the range where it is exact, or one
/// correction is not enough.
fn model(a: u32, b: u32) -> Option<(u32, u32)> {
    let x = reciprocal(b)?;
    let ah = a >> 9;
    let q1 = ah.checked_mul(x)? >> 16;
    let r1 = (a << 14).wrapping_sub(q1.wrapping_mul(b)); // exact if A 2^14 - q1 B is in [0, 2^27)
    let t1 = i64::from(a) * (1 << 14) - i64::from(q1) * i64::from(b);
    if t1 != i64::from(r1) || r1 >= 1 << 27 {
        return None;
    }
    let q2 = (r1 >> 11).checked_mul(x)? >> 18;
    let mut q = (q1 << 10) + q2;
    let mut r = (r1 << 10).wrapping_sub(q2.wrapping_mul(b));
    let t = i64::from(a) * (1 << 24) - i64::from(q) * i64::from(b);
    if t != i64::from(r) {
        return None; // the true remainder is negative or 2^32 or more
    }
    // The routine corrects once: Q' = Q + (R >= B), right if R < 2B.
    let step = u32::from(r >= b);
    q += step;
    r -= step * b;
    if r >= b {
        return None;
    }
    Some((q, step))
}

/// For divisor `b`: an upper bound on the first remainder r1 and on the number of correction
/// steps over every dividend A in [B, 2B), or `None` if a product or remainder can leave its
/// range or one correction may not be enough. With D = 2^39 - X B >= 0 (X <= 2^39 / B), a' = floor(A / 2^9) = (A - f) / 2^9 and
/// q1 > a' X / 2^16 - 1:
///   r1 = A 2^14 - q1 B < f 2^14 + (A - f) D / 2^25 + B <= 511 2^14 + B D / 2^24 + B;
/// with r' = floor(r1 / 2^11) = (r1 - g) / 2^11 and q2 > r' X / 2^18 - 1:
///   R = r1 2^10 - q2 B < g 2^10 + (r1 - g) D / 2^29 + B <= 2047 2^10 + r1 D / 2^29 + B.
/// Both remainders are >= 0 because X <= 2^39 / B makes each digit an underestimate.
fn bound(b: u32) -> Option<(u64, u64)> {
    let x = reciprocal(b)?;
    let (b, x) = (u128::from(b), u128::from(x));
    if x >= 1 << 16 || x * b > 1 << 39 {
        return None;
    }
    let d = (1u128 << 39) - x * b;
    // The largest integer strictly below n / 2^k.
    let below = |n: u128, k: u32| (n - 1) >> k;
    let r1 = below(d * b + (((511 << 14) + b) << 24), 24);
    if r1 >= 1 << 27 {
        return None;
    }
    let r = below(r1 * d + (((2047 << 10) + b) << 29), 29);
    if r >= 1 << 32 {
        return None;
    }
    // The routine corrects Q at most once.
    if r / b > 1 {
        return None;
    }
    Some((r1 as u64, (r / b) as u64))
}

/// What the routine does with one pair of operands.
#[derive(Debug, PartialEq)]
enum Division {
    /// It hands the operands to compiler-builtins' `__divsf3`: a zero, subnormal, infinite or NaN
    /// divisor; a subnormal, infinite or NaN dividend; a subnormal or overflowing result before
    /// rounding.
    Library,
    /// Its quotient's bits.
    Quotient(u32),
    /// Its integer steps leave their range ([`model`] fails): the routine would be wrong.
    Broken,
}

/// The routine's whole division (bits in, bits out).
fn divide(a: u32, b: u32) -> Division {
    let (ea, eb) = ((a >> 23) & 0xff, (b >> 23) & 0xff);
    if eb.wrapping_sub(1) > 253 {
        return Division::Library;
    }
    let sign = (a ^ b) & 0x8000_0000;
    if ea.wrapping_sub(1) > 253 {
        return if a << 1 == 0 { Division::Quotient(sign) } else { Division::Library };
    }
    let (mut sa, sb) = (a & 0x7f_ffff | 1 << 23, b & 0x7f_ffff | 1 << 23);
    let mut e1 = ea as i32 - eb as i32 + 126; // e - 1
    if sa < sb {
        sa <<= 1;
        e1 -= 1;
    }
    if !(0..=253).contains(&e1) {
        return Division::Library;
    }
    match model(sa, sb) {
        Some((q, _)) => Division::Quotient(sign + ((e1 as u32) << 23) + ((q + 1) >> 1)),
        None => Division::Broken,
    }
}

/// The dividends that are worst for [`bound`] and for the floors: A = B, A = 2B - 1, and the
/// largest A < 2B with 511 in its low 9 bits (f = 511).
fn worst_dividends(b: u32) -> [u32; 3] {
    let top = 2 * b - 1;
    let f511 = if top & 511 >= 511 { top } else { (top & !511) - 1 };
    [b, top, f511]
}

/// Every divisor significand: the bound holds (every product and remainder in range, at most one
/// correction) and the model gives Q' exactly on the worst dividends.
#[test]
fn every_divisor_significand() {
    let mut failures = 0u64;
    let (mut max_r1, mut max_steps_bound, mut max_steps_seen) = (0u64, 0u64, 0u32);
    for b in 1u32 << 23..1 << 24 {
        let Some((r1, steps)) = bound(b) else {
            if failures < 8 {
                eprintln!("fdiv-bound: divisor significand {b:#x}: a product or remainder leaves its range");
            }
            failures += 1;
            continue;
        };
        max_r1 = max_r1.max(r1);
        max_steps_bound = max_steps_bound.max(steps);
        for a in worst_dividends(b) {
            let exact = ((u64::from(a) << 24) / u64::from(b)) as u32;
            match model(a, b) {
                Some((q, s)) if q == exact && u64::from(s) <= steps => max_steps_seen = max_steps_seen.max(s),
                other => {
                    if failures < 8 {
                        eprintln!("fdiv-bound: {a:#x} / {b:#x}: model {other:?}, exact {exact:#x}");
                    }
                    failures += 1;
                }
            }
        }
    }
    println!(
        "fdiv-bound: {} divisor significands: r1 < {} (limit 2^27 = {}), at most {} correction steps \
         (bound), {} seen on the worst dividends; {} failures",
        1u32 << 23,
        max_r1 + 1,
        1u32 << 27,
        max_steps_bound,
        max_steps_seen,
        failures
    );
    assert_eq!(failures, 0, "the division's error bound fails for some divisor significands");
}

/// The whole division (model) against the host's f32 on the check's division pairs that stay on
/// the routine's fast path.
#[test]
fn whole_division_on_the_check_pairs() {
    let (mut fast, mut mismatches) = (0u32, 0u32);
    for i in 0..fpcheck::DIV_PAIRS {
        let (a, b) = fpcheck::div_operands(i);
        let model = divide(a, b);
        if model == Division::Library {
            continue;
        }
        fast += 1;
        let host = (f32::from_bits(a) / f32::from_bits(b)).to_bits();
        if model != Division::Quotient(host) {
            if mismatches < 8 {
                eprintln!("fdiv-bound: {a:#x} / {b:#x}: model {model:?}, host {host:#x}");
            }
            mismatches += 1;
        }
    }
    println!(
        "fdiv-bound: model == host f32 on {} of {} division pairs that stay on the fast path \
         ({} mismatches; {} pairs in all)",
        fast - mismatches,
        fast,
        mismatches,
        fpcheck::DIV_PAIRS
    );
    // Most pairs are normal operands with a normal result: the check must reach the fast path.
    assert!(fast > fpcheck::DIV_PAIRS / 2, "only {fast} pairs reached the fast path");
    assert_eq!(mismatches, 0, "the division's model differs from the host's f32");
}
