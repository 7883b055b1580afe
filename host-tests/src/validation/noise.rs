//! The AR noise model of the residual: its least-squares fit and its order by BIC.

use serde::Serialize;

use crate::numerics::ar::{ArSettings, ArSolver, fit_ar_with};
use crate::numerics::select::{Criterion, best};

/// An AR noise model `v(t) = Σ_i a_i v(t − i) + e(t)`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ArNoise {
    /// Coefficients `a_1 … a_p`.
    pub a: Vec<f64>,
    /// Standard deviation of the innovations `e` on the estimation data.
    pub sigma: f64,
}

/// How the diagnosis fits: the minimum-norm solution, and more than `3p + 10` samples.
const SETTINGS: ArSettings = ArSettings {
    solver: ArSolver::MinimumNorm,
    per_order: 3,
    extra: 10,
};

/// Fits an AR(`p`) model to `r` by least squares; `None` when there are too few samples.
pub(crate) fn fit_ar(r: &[f64], p: usize) -> Option<ArNoise> {
    fit_ar_with(r, p, &SETTINGS).map(|ar| ArNoise {
        a: ar.d.iter().map(|d| -d).collect(),
        sigma: ar.sigma2.sqrt(),
    })
}

/// AR order by BIC on the residual, `1 … max`.
pub(crate) fn ar_order_bic(r: &[f64], max: usize) -> Option<usize> {
    let n = r.len() as f64;
    let scores: Vec<(usize, f64)> = (1..=max.min(r.len() / 50))
        .filter_map(|p| {
            let ar = fit_ar_with(r, p, &SETTINGS)?;
            Some((p, Criterion::Bic.score(n, ar.sigma2, p as f64)))
        })
        .collect();
    best(&scores)
}
