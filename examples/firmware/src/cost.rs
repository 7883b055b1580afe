//! Deterministic cost measurement with SysTick.
//!
//! QEMU has no cycle counter (no DWT CYCCNT), but under `-icount shift=0` its virtual clock
//! advances exactly 1 ns per executed guest instruction, and SysTick (clock source = processor
//! clock, 25 MHz on the MPS2 boards) counts that virtual clock. So a SysTick tick is a fixed
//! number of instructions: [`INSTR_PER_TICK`] = 1 ns⁻¹ / 25 MHz = 40, verified by the
//! `calibrate` feature (a loop of known instruction count, see README.md).
//!
//! SysTick is a 24-bit down-counter; we let it run from reload 0xFF_FFFF and count its wraps in
//! the SysTick exception, which gives a monotonic 64-bit tick count ([`now`]).
//!
//! On real hardware the same module measures processor cycles instead (SysTick on the core
//! clock): a cycle count, not an instruction count, and then `INSTR_PER_TICK` does not apply.

use core::sync::atomic::{AtomicU32, Ordering};

use core::sync::atomic::compiler_fence;

use cortex_m::peripheral::{SCB, SYST, syst::SystClkSource};
use cortex_m_rt::exception;

/// SysTick reload value: the full 24-bit range.
const RELOAD: u32 = 0x00FF_FFFF;

/// Instructions per SysTick tick under QEMU `-icount shift=0` on MPS2 (25 MHz processor clock,
/// 1 ns of virtual time per instruction).
pub const INSTR_PER_TICK: u64 = 40;

/// Number of SysTick wraps (each one is `RELOAD + 1` ticks).
static WRAPS: AtomicU32 = AtomicU32::new(0);

/// Starts SysTick as a free-running tick counter on the processor clock.
pub fn init(mut syst: SYST) {
    syst.disable_counter();
    syst.set_clock_source(SystClkSource::Core);
    syst.set_reload(RELOAD);
    syst.clear_current();
    syst.enable_interrupt();
    syst.enable_counter();
}

/// Ticks since [`init`], 64-bit (wraps counted in the SysTick exception).
///
/// SysTick counts `RELOAD, …, 1, 0, RELOAD, …`: the exception is raised when it reaches 0,
/// one tick *before* the reload, so the position in the current period is
/// `(RELOAD − VAL + 1) mod 2²⁴` (VAL = 0 is already the first tick of the next period, whose
/// wrap the exception has counted). If the exception is pending but not yet taken (a few cycles
/// on hardware) and VAL has already reached 0 or reloaded, the wrap is added here.
#[inline(always)]
pub fn now() -> u64 {
    loop {
        let before = WRAPS.load(Ordering::Acquire);
        let val = SYST::get_current();
        let pending = SCB::is_pendst_pending();
        let after = WRAPS.load(Ordering::Acquire);
        // A wrap counted between the two loads pairs VAL with the wrong wrap count: retry.
        if before == after {
            let late_wrap = pending && (val == 0 || val > RELOAD / 2);
            let wraps = u64::from(before) + u64::from(late_wrap);
            let pos = u64::from((RELOAD - val + 1) & RELOAD);
            return (wraps << 24) + pos;
        }
    }
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

#[exception]
fn SysTick() {
    WRAPS.fetch_add(1, Ordering::AcqRel);
}
