//! A 64-bit tick count from the `minstret` counter (instructions retired). Under QEMU with
//! `-icount shift=0` it counts exactly the instructions executed; on a board, instructions.

/// Ticks (instructions retired) since reset.
#[inline(never)]
pub fn ticks() -> u64 {
    loop {
        let (hi, lo, hi2): (u32, u32, u32);
        // SAFETY: reads machine-mode counter CSRs (the firmware runs in machine mode).
        unsafe {
            core::arch::asm!(
                "csrr {0}, minstreth",
                "csrr {1}, minstret",
                "csrr {2}, minstreth",
                out(reg) hi, out(reg) lo, out(reg) hi2,
                options(nomem, nostack),
            )
        };
        if hi == hi2 {
            return (u64::from(hi) << 32) | u64::from(lo);
        }
    }
}
