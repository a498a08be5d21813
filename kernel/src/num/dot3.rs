//! The dot product of two vectors, [`dot`]: glam's `Vec3::dot`, `(x x' + y y') + z z'` with each
//! product and sum rounded as an f32 operation, on every target. On soft-float RV32 (RV32IMC) the
//! common case runs as one hand-written routine (`dot3_rv32.s`) that keeps the products and the
//! partial sum unpacked between the steps, instead of five calls to compiler-builtins' `__mulsf3`
//! and `__addsf3`, each of which unpacks its operands and packs its result. The bits are the
//! same: the routine rounds every step to nearest, ties to even, and hands back every case it does
//! not take (an infinite, NaN or subnormal operand; a subnormal or overflowing step), which then
//! runs through the library's routines. `scripts/firmware.sh test` checks it against the host's
//! `Vec3::dot` on generated vector pairs (the `softfloat-check` firmware on RV32IMC).

use glam::Vec3;

// The routine: plain RV32IM code, no memory access, no stack.
#[cfg(all(target_arch = "riscv32", target_os = "none", not(target_feature = "f")))]
#[allow(unsafe_code)]
mod routine {
    core::arch::global_asm!(include_str!("dot3_rv32.s"), options(raw));

    unsafe extern "C" {
        /// Low word: the bits of the dot product; high word: 1 when the low word holds it.
        pub fn picomis_dot3(ax: u32, ay: u32, az: u32, bx: u32, by: u32, bz: u32) -> u64;
    }
}

/// `a . b` as `Vec3::dot` computes it, bit for bit.
#[inline(always)]
pub fn dot(a: Vec3, b: Vec3) -> f32 {
    #[cfg(all(target_arch = "riscv32", target_os = "none", not(target_feature = "f")))]
    {
        // SAFETY: the routine reads only its six register arguments and writes only a0 and a1
        // (and caller-saved temporaries), as the C calling convention allows.
        #[allow(unsafe_code)]
        let r = unsafe {
            routine::picomis_dot3(
                a.x.to_bits(),
                a.y.to_bits(),
                a.z.to_bits(),
                b.x.to_bits(),
                b.y.to_bits(),
                b.z.to_bits(),
            )
        };
        if r >> 32 != 0 {
            return f32::from_bits(r as u32);
        }
        library_dot(a, b)
    }
    #[cfg(not(all(target_arch = "riscv32", target_os = "none", not(target_feature = "f"))))]
    {
        a.dot(b)
    }
}

/// The cases the routine hands back, through the library's routines (out of line: rare).
#[cfg(all(target_arch = "riscv32", target_os = "none", not(target_feature = "f")))]
#[cold]
#[inline(never)]
fn library_dot(a: Vec3, b: Vec3) -> f32 {
    a.dot(b)
}
