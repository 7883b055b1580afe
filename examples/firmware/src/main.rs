//! Onboard identification of a servo with backlash, on a Cortex-M4F (`thumbv7em-none-eabihf`)
//! or a RISC-V RV32IMAFC (`riscv32imafc-unknown-none-elf`).
//!
//! The whole pipeline runs on the target: the Table I excitation (core's [`Excitation`], seeded
//! [`Pcg32`]), the plant behind the "apply u, read y" interface ([`plant`]), the streaming
//! accumulation sample by sample ([`Identifier::push`]), and the final solve with a statically
//! allocated workspace. Before the solve, the accumulated state is saved as a checkpoint and
//! written to the host file `hsid-state.bin` through semihosting, so that the host can solve
//! it too (`hsid solve --state hsid-state.bin`). The model and the costs are printed through
//! semihosting as `HSID ...` lines (format in README.md); QEMU's exit status is 0 if the solve
//! succeeded, 1 otherwise. What differs between the targets (runtime, semihosting, instruction
//! counter, stack bounds, fault handlers) is in [`board`]; the rest is shared.
#![no_std]
#![no_main]

mod board;
mod buildcfg;
mod cost;
mod hostfile;
mod plant;
mod report;
#[cfg(feature = "store")]
mod resume;
mod stack;

use core::panic::PanicInfo;
use core::sync::atomic::{Ordering, compiler_fence};

use board::debug;
#[cfg(not(feature = "store"))]
use hsid::Excitation;
#[cfg(not(feature = "dense-solve"))]
use hsid::structured_workspace_len;
#[cfg(feature = "dense-solve")]
use hsid::workspace_len;
use hsid::{Identifier, Knots, Model, MuZero, Settings};
#[cfg(not(feature = "store"))]
use rand_core::SeedableRng;
#[cfg(not(feature = "store"))]
use rand_pcg::Pcg32;
use static_cell::ConstStaticCell;

#[cfg(not(feature = "store"))]
use plant::Plant;
use report::out;

#[cfg(feature = "defmt")]
use defmt_semihosting as _; // the defmt global logger

/// Working interval `[u_min, u_max]` of the input (paper, Section IV).
const U_MIN: f32 = -3.0;
const U_MAX: f32 = 3.0;
/// Uniform segments per path (`n_p`); `M` regressor channels in all. The paper's 7 unless the
/// build sets `HSID_FW_SEGMENTS` ([`buildcfg`]).
const SEGMENTS: usize = buildcfg::number(
    "HSID_FW_SEGMENTS must be a decimal number",
    option_env!("HSID_FW_SEGMENTS"),
    7,
);
const M: usize = 2 * SEGMENTS;
/// Future and past horizons; `K = f + p` block rows. The paper's 10 and 10 unless the build
/// sets `HSID_FW_F`, `HSID_FW_P` ([`buildcfg`]).
const F: usize = buildcfg::number(
    "HSID_FW_F must be a decimal number",
    option_env!("HSID_FW_F"),
    10,
);
const P: usize = buildcfg::number(
    "HSID_FW_P must be a decimal number",
    option_env!("HSID_FW_P"),
    10,
);
const K: usize = F + P;
/// Hankel columns `j`.
const J: usize = 4000;
/// Samples of the initial hold at `u_min` (μ0 is the mean output over the last
/// `HOLD_LEN − HOLD_SETTLE` of them; the plant's slowest mode, |z| = √0.9048 ≈ 0.951, decays
/// by 5·10⁻⁴ over the settling part).
const HOLD_LEN: usize = 300;
const HOLD_SETTLE: usize = 150;
/// Samples after the hold: `j + f + p − 1`.
const EXCITATION_LEN: usize = J + K - 1;
/// Seed of the excitation's [`Pcg32`] (`Pcg32::seed_from_u64`).
const EXCITATION_SEED: u64 = 1;

/// How the identifier sums: plain `f32` sums (the default), or with the `compensated` feature
/// compensated output sums, which keep `f32` accurate over records of 10^6 samples and more
/// (`hsid::Compensated`; more RAM and instructions per sample, see `docs/reliability.md`).
#[cfg(not(feature = "compensated"))]
type Summation = hsid::Plain;
#[cfg(feature = "compensated")]
type Summation = hsid::Compensated;
/// The identifier type: `f32`, exact capacities (channels, block rows and the horizon `f`),
/// the chosen summation.
type Id = Identifier<f32, M, K, Summation, F>;

/// Scalars of the solve workspace: the structured solve's (`Identifier::solve_structured`,
/// the Gram's displacement generator, 40 KB at the paper's configuration), or with the
/// `dense-solve` feature the dense solve's (`Identifier::solve`, the Gram's blocks, 132 KB).
#[cfg(not(feature = "dense-solve"))]
const WORKSPACE_LEN: usize = structured_workspace_len(M, F, P);
#[cfg(feature = "dense-solve")]
const WORKSPACE_LEN: usize = workspace_len(M, F, P);
/// The solve workspace, in `.bss` (zero-initialised at compile time, handed out once).
static WORKSPACE: ConstStaticCell<[f32; WORKSPACE_LEN]> =
    ConstStaticCell::new([0.0; WORKSPACE_LEN]);

/// Bytes of the largest checkpoint of the identifier ([`Identifier::save`]).
const CHECKPOINT_CAPACITY: usize = Id::CHECKPOINT_CAPACITY;
/// The checkpoint is written into the solve workspace when it fits: the workspace is idle
/// until the solve, which overwrites it, so the export costs no RAM. Otherwise it gets a
/// static buffer of its own ([`CHECKPOINT_BUFFER`]).
const CHECKPOINT_IN_WORKSPACE: bool = WORKSPACE_LEN * size_of::<f32>() >= CHECKPOINT_CAPACITY;
/// Bytes of [`CHECKPOINT_BUFFER`]: none while the workspace can hold the checkpoint.
const CHECKPOINT_BUFFER_LEN: usize = if CHECKPOINT_IN_WORKSPACE {
    0
} else {
    CHECKPOINT_CAPACITY
};
/// The checkpoint's own buffer, used only if the workspace is too small for it.
static CHECKPOINT_BUFFER: ConstStaticCell<[u8; CHECKPOINT_BUFFER_LEN]> =
    ConstStaticCell::new([0; CHECKPOINT_BUFFER_LEN]);
/// Host file (relative to QEMU's or the debugger's working directory) the checkpoint goes to,
/// NUL-terminated for semihosting.
const STATE_FILE: &[u8] = b"hsid-state.bin\0";

/// The identifier (the accumulated statistics), in `.bss`.
/// The identifier lives in a static from the start (`Identifier::EMPTY` is a constant), so
/// nothing as large as its ~18 KB state is ever built on the stack.
static IDENTIFIER: ConstStaticCell<Id> = ConstStaticCell::new(Identifier::EMPTY);

/// Configures the identifier in place.
#[inline(never)]
fn identifier() -> &'static mut Id {
    let knots =
        Knots::uniform(U_MIN, U_MAX, SEGMENTS, SEGMENTS).unwrap_or_else(|e| fail_with("knots", &e));
    let mu0 = MuZero::Hold {
        len: HOLD_LEN,
        settle: HOLD_SETTLE,
    };
    let id = IDENTIFIER.take();
    if let Err(e) = id.reset(Settings::new(knots, F, P, mu0)) {
        fail_with("settings", &e);
    }
    id
}

/// Saves the accumulated state as a checkpoint, writes it to the host file [`STATE_FILE`]
/// and prints `HSID state bytes=.. crc=.. save_instr=.. buffer=.. file=..`. The bytes go into
/// the solve workspace `ws` (which the solve overwrites afterwards) when they fit. A host that
/// refuses the file is reported (`file=none` and an `HSID warn` line) but does not stop the
/// solve.
#[inline(never)]
fn export_state(id: &Id, ws: &mut [f32]) {
    let buf: &mut [u8] = if CHECKPOINT_IN_WORKSPACE {
        bytemuck::cast_slice_mut(ws)
    } else {
        CHECKPOINT_BUFFER.take()
    };
    let (len, ticks) = cost::measure_with(|| id.save(buf));
    let len = len.unwrap_or_else(|e| fail_with("save", &e));
    let bytes = buf.get(..len).unwrap_or_else(|| fail("save: length"));
    let written = hostfile::write(STATE_FILE, bytes);
    let name = STATE_FILE.split_last().map_or(&[][..], |(_, n)| n);
    report::state(&report::State {
        bytes: len,
        crc: stored_crc(bytes),
        save_ticks: ticks,
        buffer: if CHECKPOINT_IN_WORKSPACE {
            "workspace"
        } else {
            "static"
        },
        file: core::str::from_utf8(name).unwrap_or("?"),
        written: written.map_err(hostfile::HostFileError::as_str),
    });
}

/// The CRC-32 a checkpoint ends with (little-endian): `hsid::crc32` of all its other bytes.
/// (The CRC-32 of a whole checkpoint, its CRC included, is the same constant for every
/// checkpoint, `0x2144df1c`, so it identifies nothing.)
fn stored_crc(bytes: &[u8]) -> u32 {
    let mut last = [0u8; 4];
    if let Some(tail) = bytes.len().checked_sub(4).and_then(|at| bytes.get(at..)) {
        last.copy_from_slice(tail);
    }
    u32::from_le_bytes(last)
}

/// The final solve. Not inlined, like [`identifier`]: the solve's temporaries live in this
/// frame only while it runs, and the model is built in the caller's slot (no copy on the
/// stack).
#[inline(never)]
fn solve(id: &Id, ws: &mut [f32]) -> Result<Model<f32, M, F>, hsid::Error> {
    #[cfg(not(feature = "dense-solve"))]
    return id.solve_structured(ws);
    #[cfg(feature = "dense-solve")]
    return id.solve(ws);
}

#[board::entry]
fn main() -> ! {
    // RISC-V: riscv-rt does not paint the stack, so paint it before anything else runs (on the
    // Cortex-M4 cortex-m-rt's reset handler has painted it already).
    #[cfg(target_arch = "riscv32")]
    stack::repaint();
    cost::init();

    #[cfg(feature = "calibrate")]
    calibrate();

    let id = identifier();
    report::config(&report::Config {
        u_min: U_MIN,
        u_max: U_MAX,
        segments: SEGMENTS,
        f: F,
        p: P,
        hold: HOLD_LEN,
        settle: HOLD_SETTLE,
        samples: HOLD_LEN + EXCITATION_LEN,
        excitation_seed: EXCITATION_SEED,
        noise_seed: plant::NOISE_SEED,
        noise_amplitude: plant::NOISE_AMPLITUDE,
        workspace_len: WORKSPACE_LEN,
        solve: if cfg!(feature = "dense-solve") {
            "dense"
        } else {
            "structured"
        },
    });

    // The experiment: one sample per period, apply u(t), read y(t), accumulate.
    let mut push = report::PushCost::default();
    #[cfg(not(feature = "store"))]
    experiment(id, &mut push);
    // With the `store` feature: the same experiment, checkpointed into the store, interrupted
    // by a power loss and resumed from the store.
    #[cfg(feature = "store")]
    let ws = resume::experiment(id, &mut push, WORKSPACE.take());
    if let Some(e) = id.fault() {
        fail_with("push", &e);
    }
    let stack_peak_accumulation = stack::peak_bytes();

    // Export the accumulated state (checkpoint) to the host, then the final solve with the
    // static workspace.
    #[cfg(not(feature = "store"))]
    let ws = WORKSPACE.take();
    export_state(id, ws);
    finish(id, ws, &push, stack_peak_accumulation)
}

/// The experiment: the excitation applied to the servo sample by sample, each `(u, y)` pushed
/// into the identifier and its cost measured. Not inlined: the generator's and the plant's
/// state live in this frame only while the experiment runs, not during the solve.
#[cfg(not(feature = "store"))]
#[inline(never)]
fn experiment(id: &mut Id, push: &mut report::PushCost) {
    let mut excitation = Excitation::new(
        U_MIN,
        U_MAX,
        HOLD_LEN,
        Pcg32::seed_from_u64(EXCITATION_SEED),
    )
    .unwrap_or_else(|e| fail_with("excitation", &e));
    let mut servo = plant::plant();
    for t in 0..HOLD_LEN + EXCITATION_LEN {
        let u = excitation.next().unwrap_or(U_MIN); // endless iterator: never None
        servo.apply(u);
        let y = servo.read();
        #[cfg(feature = "dump-samples")]
        report::sample(t, u, y);
        let ticks = cost::measure(|| id.push(u, y));
        let overhead = cost::measure(|| {});
        if t >= HOLD_LEN {
            push.add(ticks, overhead);
        }
    }
}

/// The final solve with the static workspace, its stack peak measured on its own, and the
/// report: costs, then the model (`HSID ok`, exit status 0) or the failure.
#[inline(never)]
fn finish(id: &Id, ws: &mut [f32], push: &report::PushCost, stack_peak_accumulation: usize) -> ! {
    stack::repaint();
    let t0 = cost::now();
    compiler_fence(Ordering::SeqCst);
    let model = solve(id, ws);
    compiler_fence(Ordering::SeqCst);
    let solve_ticks = cost::now() - t0;
    let stack_peak_solve = stack::peak_bytes();
    report::cost(&report::Cost {
        push,
        solve_ticks,
        stack_peak_accumulation_bytes: stack_peak_accumulation,
        stack_peak_solve_bytes: stack_peak_solve,
        stack_capacity_bytes: stack::capacity_bytes(),
        identifier_bytes: core::mem::size_of_val(id),
        workspace_bytes: core::mem::size_of_val(ws),
    });
    match &model {
        Ok(model) => {
            report::model(model);
            out!("HSID ok");
            debug::exit(debug::EXIT_SUCCESS);
            fail("semihosting exit returned")
        }
        Err(e) => fail_with("solve", e),
    }
}

/// Calibration of SysTick ticks against instructions: a loop whose instruction count is read
/// from the disassembly (`calib_loop`, see README.md), and a monotonicity check of the 64-bit
/// tick count across two SysTick wraps.
#[cfg(feature = "calibrate")]
fn calibrate() {
    use core::hint::black_box;
    const N: u32 = 1_000_000;
    let t_small = cost::measure(|| {
        black_box(calib_loop(black_box(1000)));
    });
    let t_big = cost::measure(|| {
        black_box(calib_loop(black_box(1000 + N)));
    });
    out!(
        "HSID calib iterations={} ticks={} ticks_small={}",
        N,
        t_big - t_small,
        t_small
    );

    let start = cost::now();
    let mut prev = start;
    let mut max_step = 0u64;
    let mut backwards = 0u32;
    while prev - start < 2 * (1 << 24) + 1000 {
        let t = cost::now();
        if t < prev {
            backwards += 1;
        } else {
            max_step = max_step.max(t - prev);
        }
        prev = t;
    }
    out!(
        "HSID calib wrap_test ticks={} backwards={} max_step={}",
        prev - start,
        backwards,
        max_step
    );
}

/// Counts down from `n`; the loop's instruction count is checked in the disassembly.
#[cfg(feature = "calibrate")]
#[inline(never)]
fn calib_loop(n: u32) -> u32 {
    let mut i = n;
    let mut acc = 0u32;
    while i != 0 {
        acc = acc.wrapping_add(i ^ (acc >> 3));
        i -= 1;
    }
    acc
}

/// Prints `HSID fail <what>: <error>` and exits QEMU with a failure status.
fn fail_with(what: &str, e: &hsid::Error) -> ! {
    // With the `defmt` feature this goes through the core's `defmt::Format` derive.
    out!("HSID fail {}: {}", what, e);
    exit_failure()
}

/// Prints `HSID fail <why>` and exits QEMU with a failure status.
pub(crate) fn fail(why: &str) -> ! {
    out!("HSID fail {}", why);
    exit_failure()
}

/// Exits QEMU with a failure status.
pub(crate) fn exit_failure() -> ! {
    debug::exit(debug::EXIT_FAILURE);
    board::halt()
}

/// Prints `HSID panic <file>:<line>: <message>` and exits QEMU with a failure status.
#[panic_handler]
fn panic(info: &PanicInfo) -> ! {
    #[cfg(not(feature = "defmt"))]
    match info.location() {
        Some(at) => board::hprintln!("HSID panic {}:{}: {}", at.file(), at.line(), info.message()),
        None => board::hprintln!("HSID panic {}", info.message()),
    }
    #[cfg(feature = "defmt")]
    match info.location() {
        Some(at) => defmt::println!(
            "HSID panic {=str}:{=u32}: {}",
            at.file(),
            at.line(),
            defmt::Display2Format(&info.message())
        ),
        None => defmt::println!("HSID panic {}", defmt::Display2Format(&info.message())),
    }
    exit_failure()
}
