//! The exact 32 x 32 -> 64-bit signed product, [`mul_wide`]: one multiply instruction on 64-bit
//! hosts, the M4F and RV32IMC (`smull`, `mul` + `mulh`); on the Cortex-M0, which has neither,
//! `int_m0.rs`'s Thumb-1 routine instead of compiler-builtins' 64 x 64-bit `__aeabi_lmul`.

/// `a b` in 64 bits, exact.
#[cfg(not(all(target_arch = "arm", target_os = "none", target_abi = "eabi")))]
#[inline(always)]
pub(crate) fn mul_wide(a: i32, b: i32) -> i64 {
    i64::from(a) * i64::from(b)
}

#[cfg(all(target_arch = "arm", target_os = "none", target_abi = "eabi"))]
pub(crate) use crate::num::int_m0::mul_wide;
