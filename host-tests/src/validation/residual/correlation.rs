//! Cross-correlation of the residual with the prewhitened input, the direction δ and the
//! regressor channels.

use super::result::{LEVEL, ResidualInput, Test, TestSet, max_normal_p, result};
use crate::validation::stats::{acf, ccf, ccf_sigma, mean, normal_quantile};

/// The input, direction and regressor correlation tests on `inp` (autocorrelation `rho` of the
/// residual up to lag `k`), into `set` with their curves and strongest lags.
pub(crate) fn correlations(inp: &ResidualInput, rho: &[f64], k: usize, set: &mut TestSet) {
    let r = inp.residual;
    let z99 = normal_quantile(1.0 - LEVEL / 2.0);
    // Cross-correlations.
    let m_lags = 2 * k + 1;
    let crit = normal_quantile(1.0 - LEVEL / (2.0 * m_lags as f64));
    let (s_u, lag_u, c_u, b_u) = xcorr_test(inp.u, r, rho, k, false);
    let p_u = max_normal_p(s_u, m_lags);
    set.strongest_input_lag = lag_u;
    set.strongest_input_lag_significant = s_u > z99;
    set.tests.push(result(
        Test::InputCorrelation,
        s_u,
        crit,
        p_u,
        format!(
            "strongest input–residual correlation at lag {lag_u} ({s_u:.2} σ; positive lag: the residual follows the input)"
        ),
    ));
    let raw = ccf(inp.u, r, k);
    set.strongest_input_lag_raw = raw
        .iter()
        .enumerate()
        .skip(k)
        .max_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))
        .map_or(0, |(i, _)| i as i64 - k as i64);
    set.curves.ccf_input = c_u;
    set.curves.ccf_input_bound = b_u;
    let (s_d, lag_d, c_d, b_d) = xcorr_test(inp.delta, r, rho, k, false);
    set.tests.push(result(
        Test::DirectionCorrelation,
        s_d,
        crit,
        max_normal_p(s_d, m_lags),
        format!("strongest δ–residual correlation at lag {lag_d} ({s_d:.2} σ)"),
    ));
    set.curves.ccf_direction = c_d;
    set.curves.ccf_direction_bound = b_d;
    let mut best = (0.0, 0usize, 0i64);
    let mut tried = 0usize;
    for (i, z) in inp.regressor.iter().enumerate() {
        if z.iter().all(|&v| v == 0.0) {
            continue;
        }
        tried += k + 1;
        let (s, lag, _, _) = xcorr_test(z, r, rho, k, true);
        if s > best.0 {
            best = (s, i, lag);
        }
    }
    let tried = tried.max(1);
    set.strongest_regressor_lag = best.2;
    set.tests.push(result(
        Test::RegressorCorrelation,
        best.0,
        normal_quantile(1.0 - LEVEL / (2.0 * tried as f64)),
        max_normal_p(best.0, tried),
        format!(
            "strongest correlation with regressor channel z{} at lag {} ({:.2} σ)",
            best.1 + 1,
            best.2,
            best.0
        ),
    ));
}

/// Prewhitening (Box–Jenkins): an AR model of the input (order by BIC, at most 10) filters
/// both the input and the residual, so that the cross-correlation of the filtered pair is
/// that of a white input, with bounds near `±2.58/√N` and its peak at the input's delay.
pub(crate) fn prewhiten(x: &[f64], r: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let m = mean(x);
    let xc: Vec<f64> = x.iter().map(|v| v - m).collect();
    let Some(p) = crate::validation::noise::ar_order_bic(&xc, 10) else {
        return (x.to_vec(), r.to_vec());
    };
    let Some(ar) = crate::validation::noise::fit_ar(&xc, p) else {
        return (x.to_vec(), r.to_vec());
    };
    let filt = |v: &[f64]| -> Vec<f64> {
        (p..v.len())
            .map(|t| {
                v[t] - ar
                    .a
                    .iter()
                    .enumerate()
                    .map(|(k, a)| a * v[t - 1 - k])
                    .sum::<f64>()
            })
            .collect()
    };
    (filt(&xc), filt(r))
}

/// Largest normalised cross-correlation over lags, after prewhitening the input;
/// `(stat, lag, values, bounds)`.
pub(crate) fn xcorr_test(
    x: &[f64],
    r: &[f64],
    _rho_r: &[f64],
    k: usize,
    causal: bool,
) -> (f64, i64, Vec<f64>, Vec<f64>) {
    let (x, r) = prewhiten(x, r);
    let (x, r) = (&x[..], &r[..]);
    let n = r.len();
    let c = ccf(x, r, k);
    let rho_x = acf(x, k);
    let rho_r = acf(r, k);
    let rho_r = &rho_r[..];
    let sigma = ccf_sigma(rho_r, &rho_x, n);
    let z99 = normal_quantile(1.0 - LEVEL / 2.0);
    let bounds = vec![z99 * sigma; c.len()];
    let mut best = (0.0, 0i64);
    for (i, v) in c.iter().enumerate() {
        let lag = i as i64 - k as i64;
        if causal && lag < 0 {
            continue;
        }
        let s = v.abs() / sigma;
        if s > best.0 {
            best = (s, lag);
        }
    }
    (best.0, best.1, c, bounds)
}
