//! Peak stack use by stack painting.
//!
//! The stack region runs from the board's `stack_bottom` (just above `.bss`/`.uninit`) up to
//! `stack_top` (top of RAM, the initial stack pointer). It is painted with the board's
//! `STACK_PAINT_VALUE` before the experiment: on the Cortex-M4 by cortex-m-rt's `paint-stack`
//! in the reset handler, before any Rust code runs; on RISC-V by [`repaint`], first thing in
//! `main`. The stack grows down from the top; the lowest word that no longer holds the paint marks
//! the deepest the stack has ever been ([`peak_bytes`]). [`repaint`] paints the free part
//! again, below the current stack pointer, so that the peak of a later phase can be measured
//! on its own.

use crate::board::{STACK_PAINT_VALUE, stack_bottom as bottom, stack_pointer, stack_top as top};

/// Bytes available to the stack.
pub fn capacity_bytes() -> usize {
    top() - bottom()
}

/// Peak stack use so far, in bytes: distance from the top of the stack to the lowest word
/// that is not paint. Returns [`capacity_bytes`] if no paint is left (overflowed the region).
pub fn peak_bytes() -> usize {
    let top = top();
    let sp = stack_pointer();
    let mut addr = bottom();
    while addr < sp {
        // SAFETY: `addr` is word-aligned (both runtimes' linker scripts align the stack bottom to 4) and
        // lies in [stack bottom, SP), inside the RAM region, below the live stack: plain memory
        // that nothing else references. A volatile read keeps the compiler from assuming
        // anything about it.
        let word = unsafe { core::ptr::read_volatile(addr as *const u32) };
        if word != STACK_PAINT_VALUE {
            break;
        }
        addr += 4;
    }
    top - addr
}

/// Bytes left unpainted below the stack pointer by [`repaint`]: room for an exception frame
/// and the SysTick handler (Cortex-M4) if SysTick fires while painting.
const REPAINT_MARGIN: usize = 256;

/// Paints the free stack again, from the stack bottom up to `REPAINT_MARGIN` bytes below the
/// current stack pointer, so that the next [`peak_bytes`] reports the peak since this call
/// (measured from the top of the stack, so it includes the frames live now).
#[inline(never)]
pub fn repaint() {
    let sp = stack_pointer();
    let end = sp.saturating_sub(REPAINT_MARGIN) & !3;
    let mut addr = bottom();
    while addr < end {
        // SAFETY: `addr` is word-aligned and lies in [stack bottom, SP − margin): the free part
        // of the stack region, below every live frame (this function's included) and below
        // the room an exception taken meanwhile would use. No reference points there.
        unsafe { core::ptr::write_volatile(addr as *mut u32, STACK_PAINT_VALUE) };
        addr += 4;
    }
}
