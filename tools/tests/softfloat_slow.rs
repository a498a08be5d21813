//! picomis-softfloat's rare-case routines (`slow::add`, `slow::mul`, `slow::div`: subnormal,
//! infinite, NaN and zero operands, subnormal and overflowing results, which the fast paths of
//! `m0.s` and `rv32.s` hand over) against the host's own f32, bit for bit, on the soft-float
//! check's operand pairs, its division pairs, and every pair of a list of edge values. A NaN
//! result must be a NaN (the host's invalid-operation NaN has another sign than compiler-builtins';
//! the QEMU check of `scripts/firmware.sh test` compares the NaN bits with compiler-builtins').
//! They serve every operand, not only the rare ones, so every pair checks them.

use picomis_softfloat::slow;

#[path = "../../firmware/src/fpcheck.rs"]
#[allow(dead_code)]
mod fpcheck;

/// Checks `ours` against the host's `want` for one operation; returns 1 on a mismatch.
fn mismatch(op: &str, a: u32, b: u32, ours: u32, want: f32) -> u32 {
    let ok = if want.is_nan() { f32::from_bits(ours).is_nan() } else { ours == want.to_bits() };
    if !ok {
        eprintln!("{op}({a:#010x}, {b:#010x}) = {ours:#010x}, the host's {:#010x}", want.to_bits());
    }
    u32::from(!ok)
}

/// The four operations on one pair; the number of mismatches.
fn check(a: u32, b: u32) -> u32 {
    let (x, y) = (f32::from_bits(a), f32::from_bits(b));
    mismatch("add", a, b, slow::add(a, b), x + y)
        + mismatch("sub", a, b, slow::add(a, b ^ 0x8000_0000), x - y)
        + mismatch("mul", a, b, slow::mul(a, b), x * y)
        + mismatch("div", a, b, slow::div(a, b), x / y)
}

#[test]
fn the_check_pairs() {
    let bad: u32 = (0..fpcheck::PAIRS).map(|i| check(fpcheck::operands(i).0, fpcheck::operands(i).1)).sum();
    assert_eq!(bad, 0, "{bad} mismatches on the soft-float check's pairs");
}

#[test]
fn the_division_pairs() {
    // Every 16th of the 2^24 division pairs (all their classes: i % 12 runs through all).
    let bad: u32 = (0..fpcheck::DIV_PAIRS)
        .step_by(16)
        .map(|i| check(fpcheck::div_operands(i).0, fpcheck::div_operands(i).1))
        .sum();
    assert_eq!(bad, 0, "{bad} mismatches on the division pairs");
}

#[test]
fn every_pair_of_edge_values() {
    // Zeros, subnormals (smallest, largest, in between), the normal boundary, ones, ties, the
    // largest finite values, infinities and NaNs (quiet, signalling, with payloads), both signs.
    let magnitudes: [u32; 18] = [
        0,
        1,
        2,
        3,
        0x0000_0100,
        0x0040_0000,
        0x007f_ffff,
        0x0080_0000,
        0x0080_0001,
        0x00ff_ffff,
        0x0100_0000,
        0x3f80_0000,
        0x3f80_0001,
        0x4b00_0000,
        0x7f7f_ffff,
        0x7f80_0000,
        0x7fc0_0000,
        0x7f80_0001,
    ];
    let values: Vec<u32> = magnitudes.iter().flat_map(|&m| [m, m | 0x8000_0000]).collect();
    let bad: u32 = values.iter().flat_map(|&a| values.iter().map(move |&b| check(a, b))).sum();
    assert_eq!(bad, 0, "{bad} mismatches on the edge values");
}

#[test]
fn nan_operands_come_back_quieted_with_their_payload() {
    // compiler-builtins' rules, which the QEMU check compares bit for bit: the first NaN operand
    // with its quiet bit set; the add drops its sign, the multiply and the division keep it.
    let (snan, qnan) = (0xff80_0001, 0x7fc0_1234);
    assert_eq!(slow::add(snan, 0x3f80_0000), 0x7fc0_0001);
    assert_eq!(slow::add(0x3f80_0000, snan), 0x7fc0_0001);
    assert_eq!(slow::add(qnan, snan), qnan);
    for op in [slow::mul, slow::div] {
        assert_eq!(op(snan, 0x3f80_0000), 0xffc0_0001);
        assert_eq!(op(0x3f80_0000, snan), 0xffc0_0001);
        assert_eq!(op(qnan, snan), qnan);
    }
    // Invalid operations: the default NaN.
    assert_eq!(slow::add(0x7f80_0000, 0xff80_0000), 0x7fc0_0000);
    assert_eq!(slow::mul(0x7f80_0000, 0x8000_0000), 0x7fc0_0000);
    assert_eq!(slow::div(0, 0x8000_0000), 0x7fc0_0000);
    assert_eq!(slow::div(0xff80_0000, 0x7f80_0000), 0x7fc0_0000);
}
