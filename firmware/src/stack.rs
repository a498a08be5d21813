//! Peak stack use by stack painting: cortex-m-rt (feature `paint-stack`) fills the stack region
//! with 0xCCCCCCCC before `main`; the lowest word no longer holding the pattern marks the
//! high-water mark.

use core::ptr;

const PAINT: u32 = 0xCCCC_CCCC;

unsafe extern "C" {
    /// Top of the stack (initial SP), from cortex-m-rt's link.x.
    static _stack_start: u32;
    /// Lowest address the stack may reach (end of static RAM), from link.x.
    static _stack_end: u32;
}

/// Stack region: (bottom, top) addresses.
pub fn region() -> (usize, usize) {
    (ptr::addr_of!(_stack_end) as usize, ptr::addr_of!(_stack_start) as usize)
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
