//! Hand-written IEEE-754 single-precision soft float for cores without an FPU: Arm ARMv6-M
//! (Cortex-M0, M0+, M1; Thumb-1, so it also runs on ARMv7-M without an FPU) and RISC-V RV32
//! without the F extension (RV32IMC). Every result is bit for bit what compiler-builtins gives
//! (NaN payloads included), in two to three times fewer instructions on the common paths.
//!
//! # Use
//!
//! Add the crate and link it in from the binary (it has no items to call: like a panic handler,
//! it is linked only when named):
//!
//! ```ignore
//! use picomis_softfloat as _;
//! ```
//!
//! On targets with an FPU (`thumbv7em-none-eabihf`...) and on hosts the crate is empty.
//!
//! ## Arm (`thumbv6m-none-eabi`, and `thumbv7m-none-eabi` / `thumbv7em-none-eabi`)
//!
//! Nothing else: `m0.s` defines strong `__aeabi_fadd`, `__aeabi_fsub`, `__aeabi_fmul`,
//! `__aeabi_fdiv`, the comparisons `__aeabi_fcmp{eq,lt,le,gt,ge}`, the conversion
//! `__aeabi_ui2f`, the 64-bit multiply `__aeabi_lmul` and the leading-zero count `__clzsi2`.
//! compiler-builtins defines the same symbols weak, so the linker takes these, and their rare
//! cases (subnormal, infinite or NaN operands, subnormal or overflowing results) go on to
//! [`slow`]'s routines with the original operands (compiler-builtins' bits, in a third of the
//! code of its `__addsf3`, `__mulsf3` and `__divsf3`, which are no longer linked).
//!
//! Another crate that also defines them strong is a duplicate-symbol error at link time. The one
//! to know: `rp2040-hal` (and the `rp-pico` board crate) maps the float operations to the
//! RP2040's ROM routines unless its `disable-intrinsics` feature is on. The ROM's are fast too
//! but flush subnormals to zero, so they do not give the host's bits in every case; with this
//! crate an RP2040 renders the host's pixels. `disable-intrinsics` also turns off that HAL's
//! integer division by the hardware divider.
//!
//! ## RISC-V (`riscv32imc-unknown-none-elf`)
//!
//! compiler-builtins names its routines `__addsf3` and so on only, so the fast paths are
//! `__wrap___addsf3`... (their rare cases go to [`slow`] as on Arm): link the binary with
//! `--wrap=NAME` for each NAME of [`RV32_WRAPPED`], e.g. in its build script (with this crate as
//! a build-dependency too):
//!
//! ```no_run
//! for name in picomis_softfloat::RV32_WRAPPED {
//!     println!("cargo:rustc-link-arg-bins=--wrap={name}");
//! }
//! ```
//!
//! Without those flags the compiler's calls do not reach these routines.
//!
//! # What the routines do
//!
//! Round to nearest, ties to even, exactly like IEEE-754 binary32:
//! - the fast paths handle normal operands with a normal result, which is what a render does
//!   almost always; `x + 0`, `0 + 0` and `0 * finite` are tested first and return without a
//!   stack frame (about a third of a render's adds and a quarter of its multiplies have a zero
//!   operand);
//! - the division computes the quotient from a 16-bit reciprocal of the divisor (a 128-entry
//!   table, `fdiv_recip.s`, and one Newton step) in two digit steps and one correction, with no
//!   64-bit multiply; `tools/tests/fdiv_bound.rs` in the picomis repository proves its error
//!   bound for every divisor significand;
//! - everything else tail-calls [`slow`] with the original operands, which gives the library's
//!   exact bits; the comparisons and conversions are complete (they have no rare case).
//!
//! On the picomis Veach scene (Cortex-M0) an add averages about 35 instructions, a multiply
//! about 42 and a division 66, where compiler-builtins takes 89, 101 and 209.
//!
//! # Checked
//!
//! The picomis repository's `scripts/firmware.sh test` runs its `softfloat-check` firmware
//! under QEMU (M0 and RV32IMC): 2^17 operand pairs built to hit the hard cases (alignment
//! shifts, cancellation, exact ties of both parities, products near the subnormal boundary and
//! overflow, every pair of special values) through every routine, each result compared with
//! compiler-builtins' bit for bit, and the conversion on 2^20 values; and the digests of the
//! results compared with the host's own f32.
#![no_std]

pub mod slow;

/// The symbols a RISC-V binary wraps (`--wrap=NAME`) to use these routines: the compiler's
/// calls reach `__wrap_NAME` here.
pub const RV32_WRAPPED: [&str; 13] = [
    "__addsf3",
    "__subsf3",
    "__mulsf3",
    "__divsf3",
    "__floatunsisf",
    "__floatsisf",
    "__eqsf2",
    "__nesf2",
    "__ltsf2",
    "__lesf2",
    "__gtsf2",
    "__gesf2",
    "__unordsf2",
];

#[cfg(all(target_arch = "arm", target_abi = "eabi"))]
core::arch::global_asm!(concat!(include_str!("fdiv_recip.s"), include_str!("m0.s")), options(raw));
#[cfg(all(target_arch = "riscv32", not(target_feature = "f")))]
core::arch::global_asm!(concat!(include_str!("fdiv_recip.s"), include_str!("rv32.s")), options(raw));
