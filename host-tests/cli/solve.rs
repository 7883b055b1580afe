//! `hsid solve`: an identifier's checkpoint solved on the host.

use crate::failure::{Failure, outln};
use hsid_host::model::Element;
use std::path::PathBuf;

use clap::{Args, ValueEnum};
use hsid::{CheckpointError, Error};
use hsid_host::fleet::solve::MAX_CHECKPOINT_BYTES;
use hsid_host::identify::{IdentifyError, Solver, solve_checkpoint_with};
use hsid_host::io::read_file_limited;

use crate::args::ModelOut;

/// Arguments of `hsid solve`.
#[derive(Args)]
pub struct SolveArgs {
    /// Checkpoint file written by `Identifier::save` (the firmware's `hsid-state.bin`).
    #[arg(long)]
    state: PathBuf,
    /// Which of the core's solves: `dense` (the Gram's blocks; any settings) or `structured`
    /// (the Gram's displacement generator, as the firmware solves by default: its model bit
    /// for bit; PI-MOESP, μ0 not estimated, no forgetting).
    #[arg(long, value_enum, default_value_t = SolverArg::Dense)]
    solver: SolverArg,
    #[command(flatten)]
    out: ModelOut,
}

/// `--solver` of `hsid solve`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum SolverArg {
    /// `Identifier::solve`.
    Dense,
    /// `Identifier::solve_structured`.
    Structured,
}

impl SolverArg {
    /// The library's solve of this choice.
    fn solver(self) -> Solver {
        match self {
            SolverArg::Dense => Solver::Dense,
            SolverArg::Structured => Solver::Structured,
        }
    }
}

/// `hsid solve --state FILE [--solver dense|structured] [--json OUT]`.
pub fn run(a: &SolveArgs) -> Result<(), Failure> {
    let state = &a.state;
    let bytes = read_file_limited(state, MAX_CHECKPOINT_BYTES as u64).map_err(|e| e.to_string())?;
    let solver = a.solver.solver();
    let solved = solve_checkpoint_with(&bytes, solver).map_err(|e| {
        let hint = match e {
            IdentifyError::Core(Error::Checkpoint(CheckpointError::NotACheckpoint)) => {
                ": give the binary state file Identifier::save wrote (the firmware's hsid-state.bin), not the printed output"
            }
            _ => "",
        };
        format!("{} ({} bytes): {e}{hint}", state.display(), bytes.len())
    })?;
    let h = &solved.header;
    outln!(
        "{}: {} checkpoint, {} bytes, {} channels, f = {}, p = {}; solved in {} ({} solve)",
        state.display(),
        h.scalar_name(),
        bytes.len(),
        h.channels,
        h.f,
        h.p,
        h.scalar_name(),
        solver.name()
    )?;
    outln!("{}", solved.model.text())?;
    if let Some(path) = &a.out.json {
        // A checkpoint records one border (static) or two; which two-path element it is, it
        // does not record.
        let kind = solved.shared_knots.then_some(Element::Static);
        solved
            .model
            .to_json(kind)
            .save(path)
            .map_err(|e| e.to_string())?;
        outln!("wrote {}", path.display())?;
    }
    Ok(())
}
