//! Trend and offset of the residual over time, Newey–West standard errors.

use super::result::{LEVEL, ResidualInput, Test, TestSet, result};
use crate::validation::stats::{mean, newey_west_var_of_mean, normal_quantile, normal_sf};

/// The trend and offset test on `inp`, into `set`.
pub(crate) fn trend(inp: &ResidualInput, set: &mut TestSet) {
    let r = inp.residual;
    let n = r.len();
    // Trend and offset, Newey–West.
    let lags = ((n as f64).powf(1.0 / 3.0) * 1.5).ceil() as usize;
    let tc = (n as f64 - 1.0) / 2.0;
    let tau: Vec<f64> = (0..n).map(|t| (t as f64 - tc) / tc.max(1.0)).collect();
    let stt: f64 = tau.iter().map(|v| v * v).sum();
    let m = mean(r);
    let slope = tau.iter().zip(r).map(|(a, b)| a * (b - m)).sum::<f64>() / stt;
    let e: Vec<f64> = r.iter().zip(&tau).map(|(v, t)| v - m - slope * t).collect();
    // Var(Σ τ ε) = N² Var(mean of τ ε), long-run (Newey–West).
    let w: Vec<f64> = tau.iter().zip(&e).map(|(t, e)| t * e).collect();
    let var_slope = newey_west_var_of_mean(&w, lags) * (n as f64) * (n as f64) / (stt * stt);
    let t_slope = slope / var_slope.sqrt().max(1e-300);
    let t_mean = m / newey_west_var_of_mean(r, lags).sqrt().max(1e-300);
    let stat = t_slope.abs().max(t_mean.abs());
    set.tests.push(result(
        Test::Trend,
        stat,
        normal_quantile(1.0 - LEVEL / 4.0),
        (4.0 * normal_sf(stat)).min(1.0),
        format!(
            "offset {m:.4} (t = {t_mean:.2}), slope {:.4} per record half-length (t = {t_slope:.2}), Newey–West with {lags} lags",
            slope
        ),
    ));
}
