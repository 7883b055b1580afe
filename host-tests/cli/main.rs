//! `hsid`: identify backlash/switch Hammerstein systems from data, reproduce the paper.
//!
//! One file per subcommand; the argument groups they share are in `args.rs`. The library
//! (`hsid_host`) knows nothing of the command line: each subcommand turns its arguments into the
//! library's option structs, runs it and prints.

mod allocator;
mod args;
mod diagnose;
mod excite;
mod failure;
mod figures;
mod fleet;
mod identify;
mod interrupt;
mod locate;
mod paper;
mod progress;
mod simulate;
mod solve;
mod validate;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

#[derive(Parser)]
#[command(
    name = "hsid",
    version,
    about = "Subspace identification of Hammerstein systems with backlash or switch input nonlinearities"
)]
struct Cli {
    /// Show no stages on standard error while a long run goes on (they show only for runs
    /// longer than a second; errors and warnings are printed either way)
    #[arg(long, global = true)]
    quiet: bool,
    #[command(subcommand)]
    cmd: Cmd,
}

#[derive(Subcommand)]
enum Cmd {
    /// Reproduce Section IV: Monte Carlo on the switch and backlash examples.
    Paper(paper::PaperArgs),
    /// Print the Table I excitation as CSV (column `u`).
    Excite(excite::ExciteArgs),
    /// Identify a model from a CSV file with columns `u,y`.
    Identify(Box<identify::IdentifyArgs>),
    /// Close the loop: check the data, identify, test the validation residual, trace it to a
    /// missing effect, add it, and report the error before and after each step.
    Diagnose(Box<diagnose::DiagnoseArgs>),
    /// Solve an identifier's checkpoint (e.g. exported by the firmware) on the host, in the
    /// checkpoint's precision (f32 or f64), and print the model.
    Solve(solve::SolveArgs),
    /// Simulate a model on a CSV file with columns `u,y` and print the fit.
    Validate(Box<validate::ValidateArgs>),
    /// Drive a true plant (a specification) or an identified model by an input record and
    /// print the record with the output `y` as CSV (see docs/simulate.md).
    Simulate(Box<simulate::SimulateArgs>),
    /// Solve many devices' checkpoints across cores into one JSON line per device (its model or
    /// its error); `fleet simulate` writes a simulated wearing fleet, `fleet report` its wear
    /// report (see docs/fleet.md).
    Fleet(Box<fleet::FleetArgs>),
}

fn main() -> ExitCode {
    allocator::tune();
    let cli = Cli::parse();
    if let Err(e) = interrupt::install() {
        eprintln!(
            "hsid: warning: Ctrl-C and SIGTERM will stop the command without removing its \
             temporary files: {e}"
        );
    }
    let reporter = progress::reporter(cli.quiet);
    let result = progress::run(reporter.as_ref(), || match cli.cmd {
        Cmd::Paper(a) => paper::run(&a),
        Cmd::Excite(a) => excite::run(&a),
        Cmd::Identify(a) => identify::run(&a),
        Cmd::Diagnose(a) => diagnose::run(&a),
        Cmd::Solve(a) => solve::run(&a),
        Cmd::Validate(a) => validate::run(&a),
        Cmd::Simulate(a) => simulate::run(&a).map_err(failure::Failure::from),
        Cmd::Fleet(a) => fleet::run(&a),
    });
    match result {
        Ok(()) | Err(failure::Failure::OutputClosed) => ExitCode::SUCCESS,
        Err(failure::Failure::Message(e)) => {
            eprintln!("hsid: {}", failure::one_line(&e));
            ExitCode::FAILURE
        }
    }
}
