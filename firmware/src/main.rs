//! picomis firmware: renders a built-in scene with the picomis kernel into an Rgb565
//! framebuffer in static memory, tile by tile, and logs progress and statistics.
//!
//! Boards: STM32F405 (Cortex-M4F, `thumbv7em-none-eabihf`, QEMU `netduinoplus2`), nRF51822
//! (Cortex-M0, `thumbv6m-none-eabi`, QEMU `microbit`) and FE310 (RISC-V RV32IMC,
//! `riscv32imc-unknown-none-elf`, QEMU `sifive_e`). Features: `qemu` (default: semihosting
//! text logs, framebuffer written to the host, exit status), `rtt` (defmt logs over RTT, the
//! kernel's defmt support), `measure` (instruction counts per camera sample with SysTick),
//! `softfloat-check` (the soft-float routines checked instead of a render, fpcheck.rs) and
//! `fixed` (the ray queries in fixed point). See firmware/README.md.
#![cfg_attr(target_os = "none", no_std)]
#![cfg_attr(target_os = "none", no_main)]

/// A host build (`cargo build --workspace`) gets this stub; the firmware needs `--target`.
/// `picomis-firmware softfloat-digest` prints the host's digests of the soft-float check
/// (see fpcheck.rs), which `scripts/firmware.sh test` compares with the firmware's.
#[cfg(not(target_os = "none"))]
fn main() {
    if std::env::args().nth(1).as_deref() == Some("softfloat-digest") {
        let d = fpcheck::digests(|_, _, _, _| {});
        println!(
            "softfloat digest: {} pairs, add {} sub {} mul {} cmp {} lmul {}; {} division pairs, div {}",
            fpcheck::PAIRS,
            d.add,
            d.sub,
            d.mul,
            d.cmp,
            d.lmul,
            fpcheck::DIV_PAIRS,
            d.div
        );
        println!("softfloat dot digest: {} pairs, dot {}", fpcheck::DOTS, d.dot);
        return;
    }
    eprintln!(
        "picomis-firmware runs on a microcontroller: build it in firmware/ (target thumbv7em-none-eabihf \
         by default) or with --target thumbv6m-none-eabi; see firmware/README.md"
    );
    std::process::exit(2);
}

// Logging: defmt over RTT with `rtt` (at info level: `DEFMT_LOG`, set to `info` in
// .cargo/config.toml, filters it), else semihosting text with `qemu`, else nothing.
#[cfg(all(target_os = "none", feature = "rtt"))]
macro_rules! info {
    ($($t:tt)*) => { defmt::info!($($t)*) };
}
#[cfg(all(target_os = "none", not(feature = "rtt"), feature = "qemu"))]
macro_rules! info {
    ($fmt:literal $(, $arg:expr)* $(,)?) => {
        $crate::textlog::print($fmt, &[$(&$arg as &dyn $crate::textlog::Arg),*])
    };
}
#[cfg(all(target_os = "none", not(feature = "rtt"), not(feature = "qemu")))]
macro_rules! info {
    ($fmt:literal $(, $arg:expr)* $(,)?) => {{ $( let _ = &$arg; )* }};
}

// The defmt global logger: RTT, read by probe-rs (or nobody, under QEMU).
#[cfg(all(target_os = "none", feature = "rtt"))]
use defmt_rtt as _;
// Hand-written soft float for the cores without an FPU (Cortex-M0; RV32IMC, with the --wrap
// flags of build.rs); empty on the M4F.
#[cfg(target_os = "none")]
use picomis_softfloat as _;

#[cfg(target_os = "none")]
mod app;
// What differs between Cortex-M and RISC-V: entry, clock, semihosting trap, stack bounds.
#[cfg(all(target_os = "none", target_arch = "arm"))]
#[path = "arch/cortex_m.rs"]
mod arch;
#[cfg(all(target_os = "none", target_arch = "riscv32"))]
#[path = "arch/riscv.rs"]
mod arch;
#[cfg(target_os = "none")]
mod board;
#[cfg(all(target_os = "none", target_arch = "arm"))]
mod clock;
#[cfg(all(target_os = "none", target_arch = "riscv32"))]
#[path = "arch/riscv_clock.rs"]
mod clock;
#[cfg(all(target_os = "none", feature = "qemu"))]
mod digest;
#[cfg(target_os = "none")]
mod fault;
mod fpcheck;
#[cfg(all(target_os = "none", feature = "measure"))]
mod measure;
#[cfg(all(target_os = "none", feature = "qemu"))]
mod semihosting;
#[cfg(target_os = "none")]
mod stack;
#[cfg(target_os = "none")]
mod status;
#[cfg(all(target_os = "none", not(feature = "rtt"), feature = "qemu"))]
mod textlog;
