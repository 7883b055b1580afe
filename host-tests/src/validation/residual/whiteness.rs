//! Whiteness: the Ljung–Box test on the autocorrelation.

use super::result::{LEVEL, ResidualInput, Test, TestSet, result};
use crate::validation::stats::{chi2_quantile, chi2_sf, normal_quantile};

/// The Ljung–Box whiteness test over `k` lags of `rho`, into `set` with the autocorrelation.
pub(crate) fn whiteness(inp: &ResidualInput, rho: &[f64], k: usize, set: &mut TestSet) {
    let r = inp.residual;
    let n = r.len();
    let z99 = normal_quantile(1.0 - LEVEL / 2.0);
    // Whiteness: Ljung–Box.
    let q: f64 = n as f64
        * (n as f64 + 2.0)
        * (1..=k)
            .map(|j| rho[j] * rho[j] / (n - j) as f64)
            .sum::<f64>();
    let outside = (1..=k)
        .filter(|&j| rho[j].abs() > z99 / (n as f64).sqrt())
        .count();
    set.tests.push(result(
        Test::Whiteness,
        q,
        chi2_quantile(1.0 - LEVEL, k as f64),
        chi2_sf(q, k as f64),
        format!(
            "Ljung–Box over {k} lags; {outside} of {k} autocorrelations outside ±2.58/√N; ρ(1) = {:.3}",
            rho[1]
        ),
    ));
    set.curves.acf = rho.to_vec();
    set.curves.acf_bound = z99 / (n as f64).sqrt();
}
