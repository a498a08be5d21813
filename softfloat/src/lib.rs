//! Hand-written single-precision soft-float routines for Arm cores without an FPU (Cortex-M0,
//! ARMv6-M Thumb-1; the code also runs on ARMv7-M), linked over compiler-builtins' weak
//! `__aeabi_*` symbols: `__aeabi_fadd`, `__aeabi_fsub`, `__aeabi_fmul`, the comparisons
//! `__aeabi_fcmp{eq,lt,le,gt,ge}`, the conversion `__aeabi_ui2f`, the 64-bit integer multiply
//! `__aeabi_lmul` and the leading-zero count `__clzsi2` (both used by the random number
//! generator): `m0.s`.
//!
//! On RV32IMC (no F extension; `rv32.s`), the add, subtract, multiply, division (`m0.s`'s
//! algorithm, step for step), the comparisons `__{eq,ne,lt,le,gt,ge,unord}sf2` and the
//! conversion `__floatunsisf`. compiler-builtins names them `__addsf3` and so on only, so
//! `build.rs` links with `--wrap`: the compiler's calls reach `__wrap___addsf3`, whose rare cases
//! go on to `__real___addsf3`, the library's. On Veach an add averages about 35 instructions, a
//! multiply about 35 and a division 61 (compiler-builtins: 55, 43 and 92).
//!
//! Results are IEEE-754 binary32 with round to nearest, ties to even, bit for bit what the host's
//! f32 gives (and what compiler-builtins gives, NaN payloads included):
//! - the fast paths handle normal operands with a normal result, which is what a render does
//!   almost always: on Veach an add or subtract averages about 35 instructions and a multiply
//!   about 42, zero operands included (compiler-builtins: 89 and 101);
//! - everything else (zero, subnormal, infinite or NaN operands, subnormal or overflowing
//!   results) tail-calls compiler-builtins' own `__addsf3` / `__mulsf3` with the original
//!   operands, so the rare cases keep the library's exact behaviour (the comparisons are
//!   complete: they have no rare case);
//! - `x + 0`, `0 + 0` and `0 * finite` are tested first and return without a stack frame
//!   (vectors with zero components are common: about a third of a render's adds and a quarter of
//!   its multiplies have a zero operand).
//!
//! The routines are checked against the host and against compiler-builtins on a large set of
//! operand pairs by the `softfloat-check` firmware feature (see `fpcheck.rs` and
//! `scripts/firmware.sh test`).

#[cfg(target_arch = "arm")]
core::arch::global_asm!(concat!(include_str!("fdiv_recip.s"), include_str!("m0.s")), options(raw));
#[cfg(target_arch = "riscv32")]
core::arch::global_asm!(concat!(include_str!("fdiv_recip.s"), include_str!("rv32.s")), options(raw));
