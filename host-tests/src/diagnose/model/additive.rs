//! Additive output terms: a polynomial trend in time, an exponential settling and sinusoids.

use nalgebra::{DMatrix, DVector};
use serde::Serialize;

use crate::numerics::lstsq::lstsq_min_norm;

/// Additive output terms: a polynomial trend in normalised time, an exponential settling and
/// sinusoids.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Additive {
    /// Trend coefficients of `τ^k`, `τ = (t − center) / scale` (empty: no trend).
    pub trend: Vec<f64>,
    /// Exponential settling `c · exp(−(τ + 1)/k)` as `(k, c)`: time constant `k` in units of
    /// `scale`, starting at `τ = −1` (the estimation record's first sample).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub settling: Option<(f64, f64)>,
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
        self.trend.len() + usize::from(self.settling.is_some()) + 2 * self.frequencies.len()
    }

    /// The settling basis `exp(−(τ + 1)/k)` at normalised time `tau`.
    fn settling_basis(k: f64, tau: f64) -> f64 {
        (-(tau + 1.0) / k).exp()
    }

    pub(super) fn row(&self, t: f64, out: &mut Vec<f64>) {
        out.clear();
        let tau = (t - self.center) / self.scale;
        let mut p = 1.0;
        for _ in 0..self.trend.len() {
            out.push(p);
            p *= tau;
        }
        if let Some((k, _)) = self.settling {
            out.push(Self::settling_basis(k, tau));
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
        if let Some((k, c)) = self.settling {
            s += c * Self::settling_basis(k, tau);
        }
        for (&w, &(a, b)) in self.frequencies.iter().zip(&self.sin_cos) {
            s += a * (w * t).cos() + b * (w * t).sin();
        }
        s
    }

    /// Least squares of the coefficients on `r` at times `time`, leaving out flagged samples
    /// (the settling time constant held).
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
        let Some(beta) = lstsq_min_norm(&x, &y) else {
            return;
        };
        let mut nt = self.trend.len();
        for (c, v) in self.trend.iter_mut().enumerate() {
            *v = beta[c];
        }
        if let Some((_, c)) = self.settling.as_mut() {
            *c = beta[nt];
            nt += 1;
        }
        for (j, sc) in self.sin_cos.iter_mut().enumerate() {
            *sc = (beta[nt + 2 * j], beta[nt + 2 * j + 1]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An offset with an exponential settling of time constant 825 samples, a ramp and a
    /// sinusoid on a record of 3300 samples (half-length 1649.5, so `k = 825 / 1649.5`): the
    /// least squares recovers each coefficient from noise-free samples.
    #[test]
    fn the_settling_term_is_fitted_with_the_others() -> Result<(), String> {
        let n = 3300;
        let time: Vec<f64> = (0..n).map(|t| t as f64).collect();
        let r: Vec<f64> = time
            .iter()
            .map(|t| {
                0.3 + 0.1 * (t - 1649.5) / 1649.5 - 2.0 * (-t / 825.0).exp() + 0.5 * (0.2 * t).sin()
            })
            .collect();
        let mut a = Additive {
            trend: vec![0.0; 2],
            settling: Some((825.0 / 1649.5, 0.0)),
            frequencies: vec![0.2],
            sin_cos: vec![(0.0, 0.0)],
            center: 1649.5,
            scale: 1649.5,
        };
        a.fit(&r, &time, &vec![false; n]);
        let (_, c) = a.settling.ok_or("no settling term")?;
        let (cos, sin) = a.sin_cos[0];
        let err = [a.trend[0] - 0.3, a.trend[1] - 0.1, c + 2.0, cos, sin - 0.5];
        if err.iter().any(|e| e.abs() > 1e-9) {
            return Err(format!("coefficient errors {err:?}"));
        }
        // The settling is evaluated from the record's first sample.
        let at = |t: f64| 0.3 + 0.1 * (t - 1649.5) / 1649.5 - 2.0 * (-t / 825.0).exp();
        let e = a.eval(100.0) - 0.5 * 20f64.sin() - at(100.0);
        if e.abs() > 1e-9 {
            return Err(format!("eval at 100: error {e}"));
        }
        Ok(())
    }
}
