//! `hsid fleet`: many devices' checkpoints solved across cores into one JSON line per device;
//! `hsid fleet simulate` writes a simulated fleet, `hsid fleet report` its wear report.

use std::io::Write;
use std::path::PathBuf;
use std::time::Instant;

use clap::{Args, Subcommand};
use hsid_host::fleet::simulate::FleetSpec;
use hsid_host::fleet::solve::MAX_CHECKPOINT_BYTES;
use hsid_host::fleet::solve::{FleetError, FleetSettings, solve_dir_each, solve_one};
use hsid_host::fleet::wear::{ReportOptions, wear_report};
use hsid_host::fleet::write::write_fleet;
use hsid_host::io::{AtomicFile, read_file_limited};

use crate::args::finite_f64;
use crate::failure::{Failure, outln};

/// Arguments of `hsid fleet`.
#[derive(Args)]
#[command(args_conflicts_with_subcommands = true)]
pub struct FleetArgs {
    #[command(subcommand)]
    cmd: Option<FleetCmd>,
    #[command(flatten)]
    solve: SolveFleetArgs,
}

/// `hsid fleet simulate` and `hsid fleet report`.
#[derive(Subcommand)]
enum FleetCmd {
    /// Simulates a fleet: one checkpoint per device and week, written by the core's
    /// identifier as the firmware runs it, and the truth table.
    Simulate(SimulateFleetArgs),
    /// The wear report of a fleet's solved models (the JSON lines of `hsid fleet`). It
    /// follows each device over the weeks by its checkpoints' file names, which must be
    /// DEVICE-wWEEK.bin (e.g. pump17-w3.bin: device pump17, week 3), as `fleet simulate`
    /// writes them.
    Report(ReportArgs),
}

/// Solves every checkpoint of a directory.
#[derive(Args)]
struct SolveFleetArgs {
    /// Directory of checkpoints, one file per device (the file name is the device id; for
    /// `fleet report`, DEVICE-wWEEK.bin, e.g. pump17-w3.bin: device pump17, week 3).
    #[arg(long)]
    states: Option<PathBuf>,
    /// Output: one JSON line per device, its model or its error.
    #[arg(long)]
    out: Option<PathBuf>,
    /// Worker threads (default: one per core).
    #[arg(long)]
    threads: Option<usize>,
    /// A checkpoint of the fleet: every other one must have its settings (knots, horizons),
    /// a checkpoint with others is reported as foreign_settings.
    #[arg(long)]
    like: Option<PathBuf>,
}

#[derive(Args)]
struct SimulateFleetArgs {
    /// Devices.
    #[arg(long, default_value_t = 2000)]
    devices: usize,
    /// Weeks (one checkpoint per device and week).
    #[arg(long, default_value_t = 8)]
    weeks: usize,
    /// Directory to write the checkpoints into.
    #[arg(long)]
    out: PathBuf,
    /// The truth table (CSV: device, week, wearing, gap, damage).
    #[arg(long)]
    truth: PathBuf,
    /// Samples each device records per week (after its hold).
    #[arg(long, default_value_t = 4000)]
    samples: usize,
    /// Standard deviation of the white noise driving the paper's noise model.
    #[arg(long, default_value_t = 0.01, value_parser = finite_f64)]
    noise: f64,
    /// Seed of the fleet.
    #[arg(long, default_value_t = 2026)]
    seed: u64,
    /// Worker threads (default: one per core).
    #[arg(long)]
    threads: Option<usize>,
}

#[derive(Args)]
struct ReportArgs {
    /// The JSON lines of `hsid fleet`, whose device ids (the checkpoints' file names) are
    /// DEVICE-wWEEK.bin.
    #[arg(long)]
    models: PathBuf,
    /// The truth table of `hsid fleet simulate`, for the detection and false-flag rates.
    #[arg(long)]
    truth: Option<PathBuf>,
    /// Flag a device whose gap grows by more than this many standard errors of its slope.
    #[arg(long, default_value_t = 3.0, value_parser = finite_f64)]
    k: f64,
    /// Flag a device whose fitted gap in its last week exceeds this (input units).
    #[arg(long, value_parser = finite_f64)]
    limit: Option<f64>,
    /// Write the per-device report (CSV) here.
    #[arg(long)]
    csv: Option<PathBuf>,
}

/// `hsid fleet …`.
pub fn run(a: &FleetArgs) -> Result<(), Failure> {
    match &a.cmd {
        Some(FleetCmd::Simulate(s)) => simulate(s),
        Some(FleetCmd::Report(r)) => report(r),
        None => solve(&a.solve),
    }
}

fn solve(a: &SolveFleetArgs) -> Result<(), Failure> {
    let (Some(states), Some(out)) = (&a.states, &a.out) else {
        return Err(
            "give --states DIR and --out FILE (or a subcommand: simulate, report)"
                .to_string()
                .into(),
        );
    };
    let fleet = match &a.like {
        Some(path) => {
            let bytes = read_file_limited(path, MAX_CHECKPOINT_BYTES as u64)
                .map_err(|e| format!("{e} (the reference of --like)"))?;
            let r = solve_one("reference", &bytes, None);
            let solved = r
                .outcome
                .map_err(|e| format!("{} (the reference of --like): {e}", path.display()))?;
            Some(FleetSettings::of(&solved))
        }
        None => None,
    };
    let start = Instant::now();
    // The output is created with the first result, after the directory was listed: a batch
    // that cannot start leaves no file behind.
    // It is written beside `out` and renamed over it once every line is in: an interrupted
    // batch leaves the previous file as it was.
    let mut w: Option<AtomicFile> = None;
    let count = solve_dir_each(states, fleet.as_ref(), a.threads, &mut |r| {
        let w = match &mut w {
            Some(w) => w,
            None => w.insert(AtomicFile::create(out)?),
        };
        writeln!(w, "{}", r.to_json())
    })
    .map_err(|e| match e {
        FleetError::Output(_) => format!("{}: {e}", out.display()),
        e => e.to_string(),
    })?;
    match w {
        Some(w) => w.commit(),
        None => AtomicFile::create(out).and_then(AtomicFile::commit),
    }
    .map_err(|e| format!("{}: {e}", out.display()))?;
    let secs = start.elapsed().as_secs_f64();
    if count.devices == 0 {
        outln!(
            "no checkpoint in {} (its files are the checkpoints, for `fleet report` named \
             DEVICE-wWEEK.bin); wrote {} without a line",
            states.display(),
            out.display()
        )?;
    } else {
        outln!(
            "{} devices: {} models, {} errors, in {secs:.2} s ({:.0} checkpoints/s); wrote {}",
            count.devices,
            count.devices - count.failed,
            count.failed,
            count.devices as f64 / secs,
            out.display()
        )?;
    }
    for name in &count.skipped {
        outln!(
            "note: {}: skipped {name}: a subdirectory (the checkpoints are the files of the directory itself; subdirectories are not searched)",
            states.display()
        )?;
    }
    Ok(())
}

fn simulate(a: &SimulateFleetArgs) -> Result<(), Failure> {
    let spec = FleetSpec {
        samples: a.samples,
        noise: a.noise,
        seed: a.seed,
        ..FleetSpec::standard(a.devices, a.weeks)
    };
    let start = Instant::now();
    let truths = write_fleet(&spec, &a.out, &a.truth, a.threads).map_err(|e| e.to_string())?;
    let wearing = truths.iter().filter(|t| t.wearing).count();
    let damaged = truths.iter().filter(|t| t.damaged.is_some()).count();
    outln!(
        "{} devices × {} weeks ({wearing} wearing, {damaged} damaged checkpoints) in {:.1} s; wrote {} and {}",
        a.devices,
        a.weeks,
        start.elapsed().as_secs_f64(),
        a.out.display(),
        a.truth.display()
    )?;
    Ok(())
}

fn report(a: &ReportArgs) -> Result<(), Failure> {
    let opts = ReportOptions {
        k: a.k,
        limit: a.limit,
    };
    let text = wear_report(&a.models, a.truth.as_deref(), &opts, a.csv.as_deref())
        .map_err(|e| e.to_string())?;
    outln!("{text}")?;
    Ok(())
}
