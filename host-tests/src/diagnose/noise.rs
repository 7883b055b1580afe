//! The AR noise model of the residual: its least-squares fit and its order by BIC.

use nalgebra::{DMatrix, DVector};
use serde::Serialize;

use super::stats::lstsq;

/// An AR noise model `v(t) = Σ_i a_i v(t − i) + e(t)`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ArNoise {
    /// Coefficients `a_1 … a_p`.
    pub a: Vec<f64>,
    /// Standard deviation of the innovations `e` on the estimation data.
    pub sigma: f64,
}

/// Fits an AR(`p`) model to `r` by least squares; `None` when there are too few samples.
pub fn fit_ar(r: &[f64], p: usize) -> Option<ArNoise> {
    let n = r.len();
    if p == 0 || n <= 3 * p + 10 {
        return None;
    }
    let rows = n - p;
    let x = DMatrix::from_fn(rows, p, |i, k| r[i + p - 1 - k]);
    let y = DVector::from_iterator(rows, (p..n).map(|t| r[t]));
    let a = lstsq(&x, &y)?;
    let e = &y - &x * &a;
    Some(ArNoise {
        a: a.iter().copied().collect(),
        sigma: (e.norm_squared() / rows as f64).sqrt(),
    })
}

/// AR order by BIC on the residual, `1 … max`.
pub fn ar_order_bic(r: &[f64], max: usize) -> Option<usize> {
    let n = r.len() as f64;
    let mut best: Option<(f64, usize)> = None;
    for p in 1..=max.min(r.len() / 50) {
        let Some(ar) = fit_ar(r, p) else { continue };
        let bic = n * (ar.sigma * ar.sigma).max(1e-300).ln() + p as f64 * n.ln();
        if best.is_none_or(|(b, _)| bic < b) {
            best = Some((bic, p));
        }
    }
    best.map(|(_, p)| p)
}
