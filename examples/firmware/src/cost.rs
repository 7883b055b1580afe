//! Deterministic cost measurement with the board's tick counter (`board::now`).
//!
//! Under QEMU `-icount shift=0` a tick is a fixed number of instructions,
//! [`INSTR_PER_TICK`]: 40 on the Cortex-M4 (SysTick at 25 MHz, 1 ns of virtual time per
//! instruction), 1 on RISC-V (`minstret`). The `calibrate` feature checks it with a loop of
//! known instruction count (README.md).

use core::sync::atomic::{Ordering, compiler_fence};

pub use crate::board::INSTR_PER_TICK;
pub use crate::board::now;

/// Starts the tick counter.
pub fn init() {
    crate::board::init_counter();
}

/// Ticks spent running `f`.
#[inline(always)]
pub fn measure<F: FnOnce()>(f: F) -> u64 {
    let t0 = now();
    compiler_fence(Ordering::SeqCst);
    f();
    compiler_fence(Ordering::SeqCst);
    now() - t0
}

/// Ticks spent running `f`, with its result.
#[inline(always)]
pub fn measure_with<R, F: FnOnce() -> R>(f: F) -> (R, u64) {
    let t0 = now();
    compiler_fence(Ordering::SeqCst);
    let r = f();
    compiler_fence(Ordering::SeqCst);
    (r, now() - t0)
}

/// Converts ticks to instructions (QEMU `-icount shift=0` only).
pub const fn instructions(ticks: u64) -> u64 {
    ticks * INSTR_PER_TICK
}
