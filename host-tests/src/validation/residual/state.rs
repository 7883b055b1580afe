//! State dependence: the residual against the level times the increment of the simulated
//! output.

use super::correlation::xcorr_test;
use super::result::{LEVEL, ResidualInput, Test, TestSet, max_normal_p, result};
use crate::validation::stats::{mean, normal_quantile};

/// The state dependence test on `inp` (autocorrelation `rho` up to lag `k`), into `set`; none
/// for a constant simulated output.
pub fn state_dependence(inp: &ResidualInput, rho: &[f64], k: usize, set: &mut TestSet) {
    let r = inp.residual;
    // State-dependent dynamics: a response whose speed or gain changes with the level leaves
    // a residual driven by the level times the increment of the output. The product is made
    // orthogonal to 1, ŷ and Δŷ (a linear error correlates with those).
    if let Some(w) = level_times_increment(inp.simulated) {
        let (s_w, lag_w, _, _) = xcorr_test(&w, r, rho, k, true);
        let m_w = k + 1;
        set.tests.push(result(
            Test::StateDependence,
            s_w,
            normal_quantile(1.0 - LEVEL / (2.0 * m_w as f64)),
            max_normal_p(s_w, m_w),
            format!(
                "strongest correlation of the residual with (ŷ − ȳ)·Δŷ at lag {lag_w} ({s_w:.2} σ)"
            ),
        ));
    }
}

/// `(ŷ − ȳ)·Δŷ` with its least-squares fit on `1, ŷ, Δŷ` removed; `None` for a constant
/// simulated output.
pub(crate) fn level_times_increment(sim: &[f64]) -> Option<Vec<f64>> {
    let n = sim.len();
    if n < 10 {
        return None;
    }
    let m = mean(sim);
    let d: Vec<f64> = (0..n)
        .map(|t| if t == 0 { 0.0 } else { sim[t] - sim[t - 1] })
        .collect();
    let w: Vec<f64> = (0..n).map(|t| (sim[t] - m) * d[t]).collect();
    let x = nalgebra::DMatrix::from_fn(n, 3, |t, c| match c {
        0 => 1.0,
        1 => sim[t] - m,
        _ => d[t],
    });
    let y = nalgebra::DVector::from_column_slice(&w);
    let beta = crate::numerics::lstsq::lstsq_min_norm(&x, &y)?;
    let e = &y - &x * beta;
    let out: Vec<f64> = e.iter().copied().collect();
    (crate::validation::stats::variance(&out) > 0.0 && out.iter().all(|v| v.is_finite()))
        .then_some(out)
}
