//! The fixed-point path's integer routines for ARMv6-M (Cortex-M0, Thumb-1), which has neither a
//! 32 x 32 -> 64-bit multiply nor a divide instruction: [`mul_wide`] (`mul_wide_m0.s`), [`dot32`]
//! (`dot32_m0.s`) and [`div_steps`] (`div_floor_m0.s`). Assembled into every M0 build, with or
//! without the `fixed` feature, so that the firmware's soft-float check can test them on the
//! target against the library's 64-bit multiply and division; the linker drops them where
//! nothing calls them.
#![cfg_attr(not(feature = "fixed"), allow(dead_code))]
#![allow(unsafe_code)]

core::arch::global_asm!(include_str!("mul_wide_m0.s"), options(raw));
core::arch::global_asm!(include_str!("dot32_m0.s"), options(raw));
core::arch::global_asm!(include_str!("div_floor_m0.s"), options(raw));

unsafe extern "C" {
    fn picomis_mul_wide(a: i32, b: i32) -> i64;
    fn picomis_dot32(a: &[i32; 3], b: &[i32; 3]) -> i64;
    fn picomis_div_steps(rem: u32, w: u32, d: u32) -> u32;
}

/// `a b` in 64 bits, exact: one call (about 20 instructions) instead of compiler-builtins'
/// 64 x 64-bit `__aeabi_lmul` on the sign-extended operands.
#[inline(always)]
pub(crate) fn mul_wide(a: i32, b: i32) -> i64 {
    // SAFETY: the routine reads its two register arguments and writes only r0-r3 and the flags
    // (r4 is saved and restored), as AAPCS allows.
    unsafe { picomis_mul_wide(a, b) }
}

/// `a . b` of 32-bit vectors in 64 bits (each product exact): one call, fewer instructions than
/// three of [`mul_wide`] and their sums.
#[inline(always)]
pub(crate) fn dot32(a: &[i32; 3], b: &[i32; 3]) -> i64 {
    // SAFETY: the routine reads three words through each pointer (valid references to three i32)
    // and writes only r0-r3, r12 and the flags (r4-r7 are saved and restored), as AAPCS allows.
    unsafe { picomis_dot32(a, b) }
}

/// The 31 steps of restoring division of the fixed-point path's `div_steps`: one call, four or
/// five instructions a step (about half of what the compiler's loop takes).
#[inline(always)]
pub(crate) fn div_steps(rem: u32, w: u32, d: u32) -> u32 {
    // SAFETY: the routine reads its three register arguments and writes only r0-r3 and the
    // flags, as AAPCS allows; every input gives a result (the bounds make it the quotient).
    unsafe { picomis_div_steps(rem, w, d) }
}
