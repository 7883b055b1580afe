//! `hsid excite`: the Table I excitation as CSV on standard output.

use crate::args::finite_f64;
use crate::failure::Failure;
use clap::Args;
use hsid::Excitation;
use hsid_host::io::write_columns_to;
use rand_core::SeedableRng;
use rand_pcg::Pcg32;

/// Arguments of `hsid excite`.
#[derive(Args)]
pub struct ExciteArgs {
    /// Lower end of the input interval.
    #[arg(long, allow_hyphen_values = true, value_parser = finite_f64)]
    umin: f64,
    /// Upper end of the input interval.
    #[arg(long, allow_hyphen_values = true, value_parser = finite_f64)]
    umax: f64,
    /// Samples in all (hold included).
    #[arg(long)]
    samples: usize,
    /// Initial hold at u_min (samples).
    #[arg(long, default_value_t = 300)]
    hold: usize,
    /// Seed of the PCG32 generator.
    #[arg(long, default_value_t = 1)]
    seed: u64,
}

/// Prints `samples` values of the excitation in a column `u`.
pub fn run(a: &ExciteArgs) -> Result<(), Failure> {
    let u: Vec<f64> = Excitation::new(a.umin, a.umax, a.hold, Pcg32::seed_from_u64(a.seed))
        .map_err(|e| e.to_string())?
        .take(a.samples)
        .collect();
    let stdout = std::io::stdout();
    Ok(write_columns_to("<stdout>", stdout.lock(), &["u"], &[u])?)
}
