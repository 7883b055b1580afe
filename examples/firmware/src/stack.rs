//! Peak stack use by stack painting.
//!
//! cortex-m-rt's `paint-stack` feature fills the whole stack region, from `_stack_end` (just
//! above `.bss`/`.uninit`) up to `_stack_start` (top of RAM, the initial MSP), with
//! [`cortex_m_rt::STACK_PAINT_VALUE`] in the reset handler, before any Rust code runs. The
//! stack grows down from `_stack_start`; the lowest word that no longer holds the paint marks
//! the deepest the stack has ever been ([`peak_bytes`]). [`repaint`] paints the free part
//! again, below the current stack pointer, so that the peak of a later phase can be measured
//! on its own.

use cortex_m_rt::STACK_PAINT_VALUE;

// Linker symbols from cortex-m-rt's link.x. Only their *addresses* are used (taking the address
// of an extern static with `&raw const` is safe); they are never read as `u32`s.
unsafe extern "C" {
    static _stack_end: u32;
    static _stack_start: u32;
}

/// Lowest address of the stack region (`_stack_end`).
pub fn bottom() -> usize {
    (&raw const _stack_end) as usize
}

/// Highest address (exclusive) of the stack region (`_stack_start`, the initial MSP).
pub fn top() -> usize {
    (&raw const _stack_start) as usize
}

/// Bytes available to the stack.
pub fn capacity_bytes() -> usize {
    top() - bottom()
}

/// Peak stack use so far, in bytes: distance from the top of the stack to the lowest word
/// that is not paint. Returns [`capacity_bytes`] if no paint is left (overflowed the region).
pub fn peak_bytes() -> usize {
    let top = top();
    let sp = cortex_m::register::msp::read() as usize;
    let mut addr = bottom();
    while addr < sp {
        // SAFETY: `addr` is word-aligned (the linker script asserts `_stack_end % 4 == 0`) and
        // lies in [_stack_end, MSP), inside the RAM region, below the live stack: plain memory
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
/// and the SysTick handler if SysTick fires while painting.
const REPAINT_MARGIN: usize = 256;

/// Paints the free stack again, from `_stack_end` up to `REPAINT_MARGIN` bytes below the
/// current stack pointer, so that the next [`peak_bytes`] reports the peak since this call
/// (measured from the top of the stack, so it includes the frames live now).
#[inline(never)]
pub fn repaint() {
    let sp = cortex_m::register::msp::read() as usize;
    let end = sp.saturating_sub(REPAINT_MARGIN) & !3;
    let mut addr = bottom();
    while addr < end {
        // SAFETY: `addr` is word-aligned and lies in [_stack_end, MSP − margin): the free part
        // of the stack region, below every live frame (this function's included) and below
        // the room an exception taken meanwhile would use. No reference points there.
        unsafe { core::ptr::write_volatile(addr as *mut u32, STACK_PAINT_VALUE) };
        addr += 4;
    }
}
