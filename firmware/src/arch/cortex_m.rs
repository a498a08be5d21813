//! Cortex-M (thumbv7em, thumbv6m): the entry point comes from cortex-m-rt (which also paints the
//! stack before `main`), the clock is SysTick (clock.rs), semihosting is `bkpt 0xab`; the
//! HardFault handler is in fault.rs.

/// Starts the clock (SysTick).
pub fn init() {
    if let Some(p) = cortex_m::Peripherals::take() {
        crate::clock::start(p.SYST);
    }
}

/// Sleeps forever.
#[cfg(not(feature = "qemu"))]
pub fn halt() -> ! {
    loop {
        cortex_m::asm::wfi();
    }
}

/// Stops with an undefined instruction (a debugger reports it with a backtrace).
#[cfg(not(feature = "qemu"))]
pub fn trap() -> ! {
    cortex_m::asm::udf()
}

/// A semihosting call: operation `op`, parameter `arg` (usually the address of a block).
#[cfg(feature = "qemu")]
pub fn semihosting_call(op: usize, arg: usize) -> usize {
    let mut r0 = op;
    // SAFETY: `bkpt 0xab` traps to the debugger / QEMU, which reads r0 and r1 and the memory
    // `arg` points to (kept alive by the caller) and writes the result to r0.
    unsafe { core::arch::asm!("bkpt 0xab", inout("r0") r0, in("r1") arg, options(nostack)) };
    r0
}

unsafe extern "C" {
    /// Top of the stack (initial SP), from cortex-m-rt's link.x.
    #[link_name = "_stack_start"]
    pub static STACK_TOP: u32;
    /// Lowest address the stack may reach (end of static RAM), from link.x.
    #[link_name = "_stack_end"]
    pub static STACK_BOTTOM: u32;
}

/// The current stack pointer.
pub fn stack_pointer() -> usize {
    cortex_m::register::msp::read() as usize
}

/// Runs `f` with interrupts off.
pub fn without_interrupts<R>(f: impl FnOnce() -> R) -> R {
    cortex_m::interrupt::free(|_| f())
}

/// Instructions per iteration of [`spin`].
#[allow(dead_code)]
pub const SPIN_INSTRUCTIONS: u64 = 2;

/// Runs `n` iterations of `subs; bne` (plus a few instructions to enter).
#[inline(never)]
#[allow(dead_code)]
pub fn spin(n: u32) {
    // SAFETY: register-only loop.
    unsafe {
        core::arch::asm!("2:", "subs r0, #1", "bne 2b", inout("r0") n => _, options(nomem, nostack));
    }
}
