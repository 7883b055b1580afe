//! Heavy tails: samples beyond 5 robust standard deviations of the median.

use super::result::{LEVEL, ResidualInput, Test, TestSet, result};
use crate::validation::stats::{excess_kurtosis, mad_sigma, poisson_sf};

/// The heavy tails test on `inp`, into `set`.
pub(crate) fn heavy_tails(inp: &ResidualInput, set: &mut TestSet) {
    let r = inp.residual;
    let n = r.len();
    // Heavy tails: samples beyond 5 robust standard deviations of the median (for Gaussian
    // residuals, P(|Z| > 5) = 5.73e-7 per sample).
    let med = crate::validation::stats::median(r);
    let s: Vec<f64> = r.iter().map(|a| a - med).collect();
    let sigma = mad_sigma(&s).max(1e-300);
    let beyond = s.iter().filter(|v| v.abs() > 5.0 * sigma).count();
    let lambda = n as f64 * 5.733e-7;
    let p = poisson_sf(beyond, lambda);
    set.tests.push(result(
        Test::HeavyTails,
        beyond as f64,
        (0..).find(|&c| poisson_sf(c, lambda) < LEVEL).unwrap_or(1) as f64,
        p,
        format!(
            "{beyond} samples beyond 5 robust σ (1.4826 MAD) from the median, {lambda:.2e} expected; excess kurtosis {:.2}",
            excess_kurtosis(r)
        ),
    ));
}
