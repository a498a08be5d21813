//! How the firmware stops when something goes wrong: the panic handler, and the handler of a
//! HardFault (Cortex-M) or of an exception (RISC-V). Each reports where it happened and exits
//! with a status under QEMU, or traps on a board.

#[panic_handler]
fn panic(info: &core::panic::PanicInfo) -> ! {
    // The message is printed only when it is a plain string: formatting it would link core::fmt.
    let message = info.message().as_str().unwrap_or("(formatted message)");
    let (file, line) = info.location().map_or(("?", 0), |l| (l.file(), l.line()));
    #[cfg(feature = "rtt")]
    defmt::error!("panic at {=str}:{=u32}: {=str}", file, line, message);
    #[cfg(not(feature = "rtt"))]
    info!("panic at {}:{}: {}", file, line, message);
    #[cfg(feature = "qemu")]
    crate::semihosting::exit(crate::status::PANIC);
    #[cfg(not(feature = "qemu"))]
    crate::arch::trap()
}

/// A HardFault (Cortex-M) or an exception (RISC-V) at `pc`: report it and stop.
fn fault(pc: u32) -> ! {
    #[cfg(feature = "rtt")]
    defmt::error!("HardFault at pc {=u32:#x}", pc);
    #[cfg(not(feature = "rtt"))]
    info!("HardFault at pc {}", pc);
    #[cfg(feature = "qemu")]
    crate::semihosting::exit(crate::status::HARD_FAULT);
    #[cfg(not(feature = "qemu"))]
    crate::arch::trap()
}

#[cfg(target_arch = "arm")]
#[cortex_m_rt::exception]
unsafe fn HardFault(frame: &cortex_m_rt::ExceptionFrame) -> ! {
    fault(frame.pc())
}

/// Exceptions (illegal instruction, access faults...): report the faulting pc like a HardFault.
#[cfg(target_arch = "riscv32")]
#[unsafe(export_name = "ExceptionHandler")]
fn exception_handler(_frame: &riscv_rt::TrapFrame) -> ! {
    fault(riscv::register::mepc::read() as u32)
}
