//! Peak stack use by stack painting: cortex-m-rt (feature `paint-stack`) fills the stack region
//! with 0xCCCCCCCC before `main` (on RISC-V, [`init`] does it at the start of `main`); the
//! lowest word no longer holding the pattern marks the high-water mark.

use core::ptr;

const PAINT: u32 = 0xCCCC_CCCC;

/// Stack region: (bottom, top) addresses, from the link script's symbols (`arch`).
pub fn region() -> (usize, usize) {
    (ptr::addr_of!(crate::arch::STACK_BOTTOM) as usize, ptr::addr_of!(crate::arch::STACK_TOP) as usize)
}

/// Paints the free stack where the runtime has not (riscv-rt does not paint it before `main`;
/// cortex-m-rt does): called first thing in `main`, so that [`peak`] measures from there.
pub fn init() {
    if cfg!(target_arch = "riscv32") {
        repaint();
    }
}

/// Bytes of stack used so far (high-water mark), and the stack region's size.
pub fn peak() -> (u32, u32) {
    let (bottom, top) = region();
    let mut p = bottom;
    // SAFETY: every word in [bottom, top) is RAM reserved for the stack.
    while p < top && unsafe { ptr::read_volatile(p as *const u32) } == PAINT {
        p += 4;
    }
    ((top - p) as u32, (top - bottom) as u32)
}

/// Bytes kept unpainted below the stack pointer by [`repaint`]: this function's own frame and an
/// exception frame (with FPU state) that may land there.
const REPAINT_MARGIN: usize = 256;

/// Paints the free stack again (all of it below the current stack pointer minus a margin), so
/// that a later [`peak`] reports the high-water mark of what runs after this call only.
#[inline(never)]
pub fn repaint() {
    let (bottom, _) = region();
    crate::arch::without_interrupts(|| {
        let sp = crate::arch::stack_pointer();
        let end = sp.saturating_sub(REPAINT_MARGIN) & !3;
        let mut p = bottom;
        while p < end {
            // SAFETY: [bottom, sp - margin) is stack memory below every live frame, and no
            // exception can push a frame while interrupts are off.
            unsafe { ptr::write_volatile(p as *mut u32, PAINT) };
            p += 4;
        }
    });
}
