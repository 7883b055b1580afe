//! The RISC-V board (`riscv32imafc-unknown-none-elf`, QEMU `virt` with `-bios none`, machine
//! mode): riscv-rt, RISC-V semihosting, `minstret` as the instruction counter, the stack region
//! of riscv-rt's `link.x`, and the trap handlers.
//!
//! `minstret` counts retired instructions, on hardware as under QEMU, so [`INSTR_PER_TICK`] is
//! one. QEMU derives `mcycle` and `minstret` from its instruction counter under `-icount`; the
//! `calibrate` feature checks the count against a loop of known length (README.md).
//!
//! riscv-rt does not paint the stack: `main` paints the free stack first thing
//! (`stack::repaint`), before the experiment starts.

pub use riscv_rt::entry;
pub use riscv_semihosting::{debug, nr, syscall};
// Plain-text output; with the `defmt` feature every line goes through defmt instead.
#[cfg(not(feature = "defmt"))]
pub use riscv_semihosting::{hprint, hprintln};

use crate::{exit_failure, report::out};

/// The marker the free stack is painted with (the same as cortex-m-rt's).
pub const STACK_PAINT_VALUE: u32 = 0xCCCC_CCCC;

/// What the tick counter is, for the `HSID cost` line.
pub const COUNTER: &str = "minstret";

/// Instructions per tick: `minstret` counts instructions.
pub const INSTR_PER_TICK: u64 = 1;

/// Nothing to start: `minstret` runs from reset in machine mode.
pub fn init_counter() {}

/// Instructions retired since reset (`minstret`/`minstreth`, read consistently as 64 bits).
#[inline(always)]
pub fn now() -> u64 {
    riscv::register::minstret::read64()
}

// Linker symbols from riscv-rt's link.x: `__estack` is the start of its `.stack` section (just
// above `.bss`/`.uninit` and the empty `.heap`), `_stack_start` the initial stack pointer at the
// top of RAM. Only their *addresses* are used (taking the address of an extern static with
// `&raw const` is safe); they are never read as `u32`s.
unsafe extern "C" {
    static __estack: u32;
    static _stack_start: u32;
}

/// Lowest address of the stack region (`__estack`).
pub fn stack_bottom() -> usize {
    (&raw const __estack) as usize
}

/// Highest address (exclusive) of the stack region (`_stack_start`, the initial `sp`).
pub fn stack_top() -> usize {
    (&raw const _stack_start) as usize
}

/// The current stack pointer (`sp`).
#[inline(always)]
pub fn stack_pointer() -> usize {
    let sp: usize;
    // SAFETY: copies the stack pointer into a register; no memory is touched.
    unsafe { core::arch::asm!("mv {}, sp", out(reg) sp, options(nomem, nostack, preserves_flags)) };
    sp
}

/// Stops for good (after a semihosting exit the host did not honour).
pub fn halt() -> ! {
    loop {
        core::hint::spin_loop();
    }
}

/// An exception (illegal instruction, access fault, misaligned access, ...): report, fail.
/// riscv-rt calls `ExceptionHandler` for every exception without a handler of its own.
#[unsafe(export_name = "ExceptionHandler")]
fn exception_handler(frame: &riscv_rt::TrapFrame) -> ! {
    out!(
        "HSID fail exception mcause={:#x} mepc={:#x} mtval={:#x} ra={:#x}",
        riscv::register::mcause::read().bits(),
        riscv::register::mepc::read(),
        riscv::register::mtval::read(),
        frame.ra
    );
    exit_failure()
}

/// Any interrupt (none is enabled): report and fail instead of spinning forever.
#[unsafe(export_name = "DefaultHandler")]
fn default_handler() {
    out!(
        "HSID fail unexpected interrupt mcause={:#x}",
        riscv::register::mcause::read().bits()
    );
    exit_failure()
}
