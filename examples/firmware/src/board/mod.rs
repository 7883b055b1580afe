//! The board layer: everything that differs between the targets, chosen by `target_arch`.
//!
//! Each board module provides the same items, and the application (plant, "apply u, read y",
//! identification, export, report lines) uses only these:
//!
//! * `entry`: the runtime's entry attribute (cortex-m-rt, riscv-rt);
//! * `hprint!`, `hprintln!`, `syscall!`, `nr`, `debug`: semihosting (output, host files, exit);
//! * `init_counter`, `now`, `INSTR_PER_TICK`, `COUNTER`: the instruction counter
//!   (SysTick on the Cortex-M4, `minstret` on RISC-V), a monotonic 64-bit tick count;
//! * `stack_bottom`, `stack_top`, `stack_pointer`, `STACK_PAINT_VALUE`: the stack region and
//!   the marker it is painted with (see `stack.rs`);
//! * `halt`: stop for good after a failed semihosting exit;
//! * the fault handlers, which report `HSID fail ...` and exit.
//!
//! | target | board | counter | QEMU |
//! | --- | --- | --- | --- |
//! | `thumbv7em-none-eabihf` | [`cortex_m`] | SysTick, 40 instructions per tick | `qemu-system-arm -machine mps2-an386` |
//! | `riscv32imafc-unknown-none-elf` | [`riscv`] | `minstret`, 1 instruction per tick | `qemu-system-riscv32 -machine virt -bios none` |

#[cfg(target_arch = "arm")]
pub mod cortex_m;
#[cfg(target_arch = "arm")]
pub use self::cortex_m::*;

#[cfg(target_arch = "riscv32")]
pub mod riscv;
#[cfg(target_arch = "riscv32")]
pub use self::riscv::*;
