//! `hsid excite`: the Table I excitation as CSV on standard output.

use crate::args::finite_f64;
use crate::failure::Failure;
use clap::Args;
use hsid::Excitation;
use hsid_host::io::format_f64;
use hsid_host::simulate::check_excitation_length;
use rand_core::SeedableRng;
use rand_pcg::Pcg32;
use std::io::{BufWriter, Write};

/// Arguments of `hsid excite`.
#[derive(Args)]
pub struct ExciteArgs {
    /// Lower end of the input interval.
    #[arg(long, allow_hyphen_values = true, value_parser = finite_f64)]
    umin: f64,
    /// Upper end of the input interval.
    #[arg(long, allow_hyphen_values = true, value_parser = finite_f64)]
    umax: f64,
    /// Samples in all (hold included): more than the hold.
    #[arg(long)]
    samples: usize,
    /// Initial hold at u_min (samples).
    #[arg(long, default_value_t = 300)]
    hold: usize,
    /// Seed of the PCG32 generator.
    #[arg(long, default_value_t = 1)]
    seed: u64,
}

/// Prints `samples` values of the excitation in a column `u`, each as it is generated:
/// memory does not grow with `samples`, and a reader that stops (`| head`) stops the run.
pub fn run(a: &ExciteArgs) -> Result<(), Failure> {
    let excitation = Excitation::new(a.umin, a.umax, a.hold, Pcg32::seed_from_u64(a.seed))
        .map_err(|e| e.to_string())?;
    check_excitation_length(a.samples, a.hold).map_err(|e| e.to_string())?;
    let mut out = BufWriter::new(std::io::stdout().lock());
    writeln!(out, "u")?;
    for v in excitation.take(a.samples) {
        writeln!(out, "{}", format_f64(v))?;
    }
    out.flush()?;
    Ok(())
}
