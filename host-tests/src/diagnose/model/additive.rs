//! Additive output terms: a polynomial trend in time and sinusoids.

use nalgebra::{DMatrix, DVector};
use serde::Serialize;

use crate::numerics::lstsq::lstsq_min_norm;

/// Additive output terms: a polynomial trend in normalised time and sinusoids.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Additive {
    /// Trend coefficients of `τ^k`, `τ = (t − center) / scale` (empty: no trend).
    pub trend: Vec<f64>,
    /// Sinusoid frequencies, radians per sample.
    pub frequencies: Vec<f64>,
    /// `(a, b)` of `a cos ωt + b sin ωt` per frequency.
    pub sin_cos: Vec<(f64, f64)>,
    /// Time centre (samples).
    pub center: f64,
    /// Time scale (samples).
    pub scale: f64,
}

impl Additive {
    pub(super) fn columns(&self) -> usize {
        self.trend.len() + 2 * self.frequencies.len()
    }

    pub(super) fn row(&self, t: f64, out: &mut Vec<f64>) {
        out.clear();
        let tau = (t - self.center) / self.scale;
        let mut p = 1.0;
        for _ in 0..self.trend.len() {
            out.push(p);
            p *= tau;
        }
        for &w in &self.frequencies {
            out.push((w * t).cos());
            out.push((w * t).sin());
        }
    }

    /// The additive output at time `t`.
    pub fn eval(&self, t: f64) -> f64 {
        let tau = (t - self.center) / self.scale;
        let mut s = 0.0;
        let mut p = 1.0;
        for c in &self.trend {
            s += c * p;
            p *= tau;
        }
        for (&w, &(a, b)) in self.frequencies.iter().zip(&self.sin_cos) {
            s += a * (w * t).cos() + b * (w * t).sin();
        }
        s
    }

    /// Least squares of the terms on `r` at times `time`, leaving out flagged samples.
    pub(super) fn fit(&mut self, r: &[f64], time: &[f64], skip: &[bool]) {
        let k = self.columns();
        if k == 0 {
            return;
        }
        let rows: Vec<usize> = (0..r.len()).filter(|&i| !skip[i]).collect();
        let mut x = DMatrix::<f64>::zeros(rows.len(), k);
        let mut buf = Vec::with_capacity(k);
        for (ri, &i) in rows.iter().enumerate() {
            self.row(time[i], &mut buf);
            for (c, v) in buf.iter().enumerate() {
                x[(ri, c)] = *v;
            }
        }
        let y = DVector::from_iterator(rows.len(), rows.iter().map(|&i| r[i]));
        if let Some(beta) = lstsq_min_norm(&x, &y) {
            let nt = self.trend.len();
            for (c, v) in self.trend.iter_mut().enumerate() {
                *v = beta[c];
            }
            for (j, sc) in self.sin_cos.iter_mut().enumerate() {
                *sc = (beta[nt + 2 * j], beta[nt + 2 * j + 1]);
            }
        }
    }
}
