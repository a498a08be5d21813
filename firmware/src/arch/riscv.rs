//! RISC-V (RV32IMC; QEMU `sifive_e`, an FE310 like the HiFive1): the entry point comes from
//! riscv-rt, the clock is the `minstret` instruction counter (riscv_clock.rs), semihosting is the
//! `slli; ebreak; srai` sequence; riscv-rt does not paint the stack (stack.rs does, at the start
//! of `main`); the exception handler is in fault.rs.

// A memcpy whose word-aligned copies take two instructions a word (compiler-builtins': about 90
// instructions for nine words); linked with --wrap (build.rs).
core::arch::global_asm!(include_str!("riscv_memcpy.s"), options(raw));

// The prologue and epilogue routines of the `save-restore` target feature (the size-optimised
// build); unreferenced, and so not linked, without it.
core::arch::global_asm!(include_str!("riscv_save_restore.s"), options(raw));

/// Nothing to start: the clock is the `minstret` counter.
pub fn init() {}

/// Sleeps forever.
#[cfg(not(feature = "qemu"))]
pub fn halt() -> ! {
    loop {
        riscv::asm::wfi();
    }
}

/// Stops with an illegal instruction.
#[cfg(not(feature = "qemu"))]
pub fn trap() -> ! {
    // SAFETY: `unimp` raises an illegal-instruction exception; it never returns.
    unsafe { core::arch::asm!("unimp", options(noreturn)) }
}

/// A semihosting call: operation `op`, parameter `arg` (usually the address of a block).
#[cfg(feature = "qemu")]
pub fn semihosting_call(op: usize, arg: usize) -> usize {
    let mut a0 = op;
    // SAFETY: the uncompressed `slli x0, x0, 0x1f; ebreak; srai x0, x0, 7` sequence traps to the
    // debugger / QEMU, which reads a0 and a1 and the memory `arg` points to (kept alive by the
    // caller) and writes the result to a0. The two shifts write x0: no effect otherwise.
    unsafe {
        core::arch::asm!(
            ".balign 16",
            ".option push",
            ".option norvc",
            "slli x0, x0, 0x1f",
            "ebreak",
            "srai x0, x0, 7",
            ".option pop",
            inout("a0") a0,
            in("a1") arg,
            options(nostack),
        )
    };
    a0
}

unsafe extern "C" {
    /// Top of the stack, from riscv-rt's link.x.
    #[link_name = "_stack_start"]
    pub static STACK_TOP: u32;
    /// Lowest address the stack may reach (end of static RAM and heap), from link.x.
    #[link_name = "__estack"]
    pub static STACK_BOTTOM: u32;
}

/// The current stack pointer.
pub fn stack_pointer() -> usize {
    let sp: usize;
    // SAFETY: reads a register.
    unsafe { core::arch::asm!("mv {}, sp", out(reg) sp, options(nomem, nostack)) };
    sp
}

/// Runs `f` with interrupts off (none are enabled: a plain call).
pub fn without_interrupts<R>(f: impl FnOnce() -> R) -> R {
    f()
}

/// Instructions per iteration of [`spin`].
#[allow(dead_code)]
pub const SPIN_INSTRUCTIONS: u64 = 2;

/// Runs `n` iterations of `addi; bnez` (plus a few instructions to enter).
#[inline(never)]
#[allow(dead_code)]
pub fn spin(n: u32) {
    // SAFETY: register-only loop.
    unsafe {
        core::arch::asm!("2:", "addi {0}, {0}, -1", "bnez {0}, 2b", inout(reg) n => _, options(nomem, nostack));
    }
}
