//! Machine-parseable output: every line starts with `HSID `, then a tag, then space-separated
//! values or `key=value` pairs (format in README.md).
//!
//! Two back ends, chosen at build time:
//! - default: plain text over semihosting (`hprintln!`). `f32` values are printed in Rust's
//!   shortest round-trip decimal form (parsing them as `f32` gives the exact bits back);
//!   samples as the hex bit patterns of the `f32`s.
//! - feature `defmt`: defmt frames over semihosting, decoded on the host by
//!   `defmt-print -e ELF`. The lines read the same, except that vectors print as defmt
//!   slices, `[v, v, …]`, instead of space-separated values.

use hsid::{Direction, Model};

use crate::cost;

/// One output line: `hprintln!` or, with the `defmt` feature, `defmt::println!`. The format
/// string must suit both (plain `{}` with values that are `Display` and `defmt::Format`).
macro_rules! out {
    ($($t:tt)*) => {{
        #[cfg(not(feature = "defmt"))]
        $crate::board::hprintln!($($t)*);
        #[cfg(feature = "defmt")]
        defmt::println!($($t)*);
    }};
}
pub(crate) use out;

/// The experiment's configuration (`HSID config ...`), everything the host needs to repeat
/// the identification on the same samples.
pub struct Config {
    pub u_min: f32,
    pub u_max: f32,
    pub segments: usize,
    pub f: usize,
    pub p: usize,
    pub hold: usize,
    pub settle: usize,
    pub samples: usize,
    pub excitation_seed: u64,
    pub noise_seed: u64,
    pub noise_amplitude: f32,
    pub workspace_len: usize,
    /// Which solve runs: `structured` (`Identifier::solve_structured`) or `dense`
    /// (`Identifier::solve`, the `dense-solve` feature).
    pub solve: &'static str,
}

/// `HSID config u_min=.. u_max=.. segments=.. f=.. p=.. hold=.. settle=.. samples=.. ...`
#[inline(never)]
pub fn config(c: &Config) {
    out!(
        "HSID config u_min={} u_max={} segments={} f={} p={} hold={} settle={} samples={} excitation_seed={} noise_seed={} noise_amplitude={} workspace_len={} solve={}",
        c.u_min,
        c.u_max,
        c.segments,
        c.f,
        c.p,
        c.hold,
        c.settle,
        c.samples,
        c.excitation_seed,
        c.noise_seed,
        c.noise_amplitude,
        c.workspace_len,
        c.solve
    );
}

/// `HSID s <t> <u bits> <y bits>`: one sample, the `f32` bit patterns in hex (8 digits).
#[cfg(feature = "dump-samples")]
pub fn sample(t: usize, u: f32, y: f32) {
    #[cfg(not(feature = "defmt"))]
    crate::board::hprintln!("HSID s {} {:08x} {:08x}", t, u.to_bits(), y.to_bits());
    #[cfg(feature = "defmt")]
    defmt::println!(
        "HSID s {} {=u32:08x} {=u32:08x}",
        t,
        u.to_bits(),
        y.to_bits()
    );
}

/// The exported checkpoint (`HSID state ...`).
pub struct State<'a> {
    /// Bytes of the checkpoint.
    pub bytes: usize,
    /// The checkpoint's own CRC-32 (its last four bytes): `hsid::crc32` of the bytes before it.
    pub crc: u32,
    /// Ticks spent in `Identifier::save`.
    pub save_ticks: u64,
    /// Where the checkpoint was written on the target: `"workspace"` (the idle solve
    /// workspace) or `"static"` (a buffer of its own).
    pub buffer: &'a str,
    /// Host file name.
    pub file: &'a str,
    /// Whether the host took the file, or why not.
    pub written: Result<(), &'static str>,
}

/// `HSID state bytes=<n> crc=<8 hex digits> save_instr=<n> buffer=<workspace|static>
/// file=<name|none>`, preceded by
/// `HSID warn state export: <why>` if the host did not take the file.
#[inline(never)]
pub fn state(s: &State) {
    let file = match s.written {
        Ok(()) => s.file,
        Err(why) => {
            out!("HSID warn state export: {}: {}", s.file, why);
            "none"
        }
    };
    let save_instr = cost::instructions(s.save_ticks);
    #[cfg(not(feature = "defmt"))]
    crate::board::hprintln!(
        "HSID state bytes={} crc={:08x} save_instr={} buffer={} file={}",
        s.bytes,
        s.crc,
        save_instr,
        s.buffer,
        file
    );
    #[cfg(feature = "defmt")]
    defmt::println!(
        "HSID state bytes={} crc={=u32:08x} save_instr={} buffer={=str} file={=str}",
        s.bytes,
        s.crc,
        save_instr,
        s.buffer,
        file
    );
}

/// Ticks spent in [`hsid::Identifier::push`] over the accumulation samples (the hold's
/// pushes are not counted), and the cost of an empty measurement for the same samples.
#[derive(Default)]
pub struct PushCost {
    samples: u64,
    ticks: u64,
    overhead_ticks: u64,
    max_ticks: u64,
}

impl PushCost {
    /// Records one push that took `ticks`, and an empty measurement that took `overhead`.
    pub fn add(&mut self, ticks: u64, overhead: u64) {
        self.samples += 1;
        self.ticks += ticks;
        self.overhead_ticks += overhead;
        self.max_ticks = self.max_ticks.max(ticks);
    }

    /// Ticks in push, net of the measurement overhead.
    fn net_ticks(&self) -> u64 {
        self.ticks.saturating_sub(self.overhead_ticks)
    }
}

/// Everything `HSID cost` reports.
pub struct Cost<'a> {
    pub push: &'a PushCost,
    pub solve_ticks: u64,
    /// Peak from reset to the end of the accumulation (includes building the identifier).
    pub stack_peak_accumulation_bytes: usize,
    /// Peak during the solve (from the top of the stack: includes `main`'s frame).
    pub stack_peak_solve_bytes: usize,
    pub stack_capacity_bytes: usize,
    pub identifier_bytes: usize,
    pub workspace_bytes: usize,
}

/// `HSID cost samples=.. per_sample_ticks=.. per_sample_instr=.. per_sample_max_instr=..
/// solve_ticks=.. solve_instr=.. stack_peak_bytes=.. ... counter=..` (instructions = ticks ×
/// `instr_per_tick`, 40 with SysTick on the Cortex-M4 and 1 with `minstret` on RISC-V, under
/// QEMU `-icount shift=0`; `per_sample_*` over the accumulation samples).
#[inline(never)]
pub fn cost(c: &Cost) {
    let n = c.push.samples.max(1);
    let net = c.push.net_ticks();
    let milli = net * 1000 / n;
    let (whole, frac) = (milli / 1000, milli % 1000);
    // Three decimals, zero-padded by hand (the same in both back ends).
    let pad = if frac < 10 {
        "00"
    } else if frac < 100 {
        "0"
    } else {
        ""
    };
    out!(
        "HSID cost samples={} per_sample_ticks={}.{}{} per_sample_instr={} per_sample_max_instr={} solve_ticks={} solve_instr={} stack_peak_bytes={} stack_peak_accumulation_bytes={} stack_peak_solve_bytes={} stack_capacity_bytes={} identifier_bytes={} workspace_bytes={} instr_per_tick={} counter={}",
        c.push.samples,
        whole,
        pad,
        frac,
        cost::instructions(net) / n,
        cost::instructions(c.push.max_ticks),
        c.solve_ticks,
        cost::instructions(c.solve_ticks),
        c.stack_peak_accumulation_bytes
            .max(c.stack_peak_solve_bytes),
        c.stack_peak_accumulation_bytes,
        c.stack_peak_solve_bytes,
        c.stack_capacity_bytes,
        c.identifier_bytes,
        c.workspace_bytes,
        cost::INSTR_PER_TICK,
        crate::board::COUNTER
    );
}

/// `HSID <tag> v v v ...` (defmt: `HSID <tag> [v, v, ...]`).
fn row(tag: &str, values: &[f32]) {
    #[cfg(not(feature = "defmt"))]
    {
        use crate::board::{hprint, hprintln};
        hprint!("HSID {}", tag);
        for v in values {
            hprint!(" {}", v);
        }
        hprintln!();
    }
    #[cfg(feature = "defmt")]
    defmt::println!("HSID {=str} {=[?]}", tag, values);
}

/// The model: `HSID model order=.. ...`, `HSID A <i> ...` (one line per row), `HSID B`,
/// `HSID C`, `HSID D`, `HSID mu0`, the knots and the border values at the knots of both
/// paths, and the singular values (plain and noise-whitened).
#[inline(never)]
pub fn model<const M: usize, const H: usize>(m: &Model<f32, M, H>) {
    let n = m.order();
    out!(
        "HSID model order={} horizon={} columns={} mu0={} static_gain={}",
        n,
        m.horizon(),
        m.columns(),
        m.mu0(),
        m.static_gain()
    );
    let mut a_row = [0.0f32; H];
    for i in 0..n {
        for (j, v) in a_row.iter_mut().enumerate().take(n) {
            *v = m.a(i, j);
        }
        #[cfg(not(feature = "defmt"))]
        {
            use crate::board::{hprint, hprintln};
            hprint!("HSID A {}", i);
            for v in &a_row[..n] {
                hprint!(" {}", v);
            }
            hprintln!();
        }
        #[cfg(feature = "defmt")]
        defmt::println!("HSID A {=usize} {=[?]}", i, &a_row[..n]);
    }
    row("B", m.b());
    row("C", m.c());
    row("D", &[m.d()]);
    row("mu0", &[m.mu0()]);
    row("knots ascending", m.knots().path(Direction::Ascending));
    row("knots descending", m.knots().path(Direction::Descending));
    row("border ascending", m.border_values(Direction::Ascending));
    row("border descending", m.border_values(Direction::Descending));
    row("sv", m.singular_values());
    row("sv_white", m.whitened_singular_values());
}
