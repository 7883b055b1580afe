//! The Cortex-M4F board (`thumbv7em-none-eabihf`, QEMU `mps2-an386`): cortex-m-rt, ARM
//! semihosting, SysTick as the instruction counter, the stack region of cortex-m-rt's
//! `link.x`, and the fault handlers.
//!
//! QEMU has no cycle counter here (no DWT CYCCNT), but under `-icount shift=0` its virtual
//! clock advances exactly 1 ns per executed guest instruction, and SysTick (clock source =
//! processor clock, 25 MHz on the MPS2 boards) counts that virtual clock. So a SysTick tick is
//! a fixed number of instructions: [`INSTR_PER_TICK`] = 1 ns⁻¹ / 25 MHz = 40, verified by the
//! `calibrate` feature (a loop of known instruction count, see README.md).
//!
//! SysTick is a 24-bit down-counter; we let it run from reload 0xFF_FFFF and count its wraps in
//! the SysTick exception, which gives a monotonic 64-bit tick count ([`now`]).
//!
//! On real hardware the same code measures processor cycles instead (SysTick on the core
//! clock): a cycle count, not an instruction count, and then `INSTR_PER_TICK` does not apply.

use core::sync::atomic::{AtomicU32, Ordering};

use cortex_m::peripheral::{SCB, SYST, syst::SystClkSource};
use cortex_m_rt::{ExceptionFrame, exception};

pub use cortex_m_rt::{STACK_PAINT_VALUE, entry};
pub use cortex_m_semihosting::{debug, nr, syscall};
// Plain-text output; with the `defmt` feature every line goes through defmt instead.
#[cfg(not(feature = "defmt"))]
pub use cortex_m_semihosting::{hprint, hprintln};

use crate::{exit_failure, fail, report::out};

/// What the tick counter is, for the `HSID cost` line.
pub const COUNTER: &str = "systick";

/// SysTick reload value: the full 24-bit range.
const RELOAD: u32 = 0x00FF_FFFF;

/// Instructions per SysTick tick under QEMU `-icount shift=0` on MPS2 (25 MHz processor clock,
/// 1 ns of virtual time per instruction).
pub const INSTR_PER_TICK: u64 = 40;

/// Number of SysTick wraps (each one is `RELOAD + 1` ticks).
static WRAPS: AtomicU32 = AtomicU32::new(0);

/// Starts SysTick as a free-running tick counter on the processor clock.
pub fn init_counter() {
    let cp = cortex_m::Peripherals::take().unwrap_or_else(|| fail("peripherals already taken"));
    let mut syst = cp.SYST;
    syst.disable_counter();
    syst.set_clock_source(SystClkSource::Core);
    syst.set_reload(RELOAD);
    syst.clear_current();
    syst.enable_interrupt();
    syst.enable_counter();
}

/// Ticks since [`init_counter`], 64-bit (wraps counted in the SysTick exception).
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

#[exception]
fn SysTick() {
    WRAPS.fetch_add(1, Ordering::AcqRel);
}

// Linker symbols from cortex-m-rt's link.x. Only their *addresses* are used (taking the address
// of an extern static with `&raw const` is safe); they are never read as `u32`s.
unsafe extern "C" {
    static _stack_end: u32;
    static _stack_start: u32;
}

/// Lowest address of the stack region (`_stack_end`, just above `.bss`/`.uninit`). cortex-m-rt's
/// `paint-stack` has painted the whole region in the reset handler.
pub fn stack_bottom() -> usize {
    (&raw const _stack_end) as usize
}

/// Highest address (exclusive) of the stack region (`_stack_start`, the initial MSP).
pub fn stack_top() -> usize {
    (&raw const _stack_start) as usize
}

/// The current stack pointer (MSP).
#[inline(always)]
pub fn stack_pointer() -> usize {
    cortex_m::register::msp::read() as usize
}

/// Stops for good (after a semihosting exit the host did not honour).
pub fn halt() -> ! {
    loop {
        cortex_m::asm::bkpt();
    }
}

// The `unsafe` on the two handlers below is cortex-m-rt's contract for defining them (they
// may run at any time); they only print, read the stacked frame they are given, and exit.

/// A fault (bus error, bad instruction, stack overflow into unmapped memory, ...): report, fail.
#[exception]
unsafe fn HardFault(frame: &ExceptionFrame) -> ! {
    out!(
        "HSID fail hardfault pc={:#x} lr={:#x}",
        frame.pc(),
        frame.lr()
    );
    exit_failure()
}

/// Any exception or interrupt nobody expects: report and fail instead of spinning forever.
#[exception]
unsafe fn DefaultHandler(irqn: i16) {
    out!("HSID fail unexpected exception irqn={}", irqn);
    exit_failure()
}
