//! Autoregressive noise models `D(q) r(t) = e(t)`, `D(q) = 1 + d_1 q⁻¹ + … + d_p q⁻ᵖ`, fitted
//! by least squares on the lagged record, and the order chosen by BIC.

use super::lstsq::{Scaling, normal_by_rows, solve_normal, solve_normal_min_norm};

/// A fitted AR(p) model.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Ar {
    /// `d_1 … d_p` of `D(q)`: `r(t) = −Σ d_i r(t − i) + e(t)`.
    pub d: Vec<f64>,
    /// Mean square of the innovations over the fitted samples `p … N − 1`.
    pub sigma2: f64,
}

impl Ar {
    /// The innovations `e(t) = D(q) r(t)` for `t ≥ p`, and 0 before (where the lags are
    /// missing).
    pub fn innovations(&self, r: &[f64]) -> Vec<f64> {
        let p = self.d.len();
        let mut e = vec![0.0; r.len()];
        for t in p..r.len() {
            e[t] = r[t] + (0..p).map(|i| self.d[i] * r[t - 1 - i]).sum::<f64>();
        }
        e
    }
}

/// How [`fit_ar_with`] solves the least-squares problem.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum ArSolver {
    /// The normal equations by Cholesky (unscaled): no result if the lagged record is rank
    /// deficient.
    Cholesky,
    /// The minimum-norm solution of the equilibrated normal equations
    /// ([`lstsq_min_norm`](super::lstsq::lstsq_min_norm)).
    MinimumNorm,
}

/// Settings of [`fit_ar_with`]: the solver, and the samples an order `p` needs (more than
/// `per_order · p + extra`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct ArSettings {
    /// The least-squares solver.
    pub solver: ArSolver,
    /// Samples needed per coefficient.
    pub per_order: usize,
    /// Samples needed beyond `per_order · p`.
    pub extra: usize,
}

impl Default for ArSettings {
    /// Cholesky, any record longer than `p`.
    fn default() -> Self {
        Self {
            solver: ArSolver::Cholesky,
            per_order: 1,
            extra: 0,
        }
    }
}

/// Fits an AR(`p`) model to `r` (zero mean) by least squares over `t = p … N − 1`; `None` if
/// `p` is 0, the record is not longer than `p`, or the lagged record is rank deficient.
pub(crate) fn fit_ar(r: &[f64], p: usize) -> Option<Ar> {
    fit_ar_with(r, p, &ArSettings::default())
}

/// [`fit_ar`] with `settings`: `None` if `p` is 0, the record has no more than
/// `per_order · p + extra` samples, or the solver finds no solution.
pub(crate) fn fit_ar_with(r: &[f64], p: usize, settings: &ArSettings) -> Option<Ar> {
    let n = r.len();
    if p == 0 || n <= settings.per_order * p + settings.extra {
        return None;
    }
    let rows = n - p;
    if r.iter().any(|v| !v.is_finite()) {
        return None;
    }
    // Row t: the lags −r(t + p − 1 − i) of r(t + p).
    let lagged = |t: usize, x: &mut [f64]| {
        for (i, xi) in x.iter_mut().enumerate() {
            *xi = -r[t + p - 1 - i];
        }
        r[t + p]
    };
    let (g, b) = normal_by_rows(rows, p, lagged);
    let d = match settings.solver {
        ArSolver::Cholesky => solve_normal(&g, &b, Scaling::None)?,
        ArSolver::MinimumNorm => solve_normal_min_norm(&g, &b)?,
    };
    // The innovations e(t) = r(t) + Σ d_i r(t − i), t ≥ p.
    let mut x = vec![0.0; p];
    let sse: f64 = (0..rows)
        .map(|t| {
            let y = lagged(t, &mut x);
            let fit: f64 = x.iter().zip(d.iter()).map(|(a, b)| a * b).sum();
            (y - fit).powi(2)
        })
        .sum();
    Some(Ar {
        d: d.iter().copied().collect(),
        sigma2: sse / rows as f64,
    })
}

#[cfg(test)]
mod tests {
    use rand_core::SeedableRng;
    use rand_distr::{Distribution, StandardNormal};
    use rand_pcg::Pcg32;

    use super::*;

    /// `r(t) = 1.2 r(t−1) − 0.5 r(t−2) + e(t)`, `e` white with variance 0.25.
    fn ar2(n: usize, seed: u64) -> Vec<f64> {
        let mut rng = Pcg32::seed_from_u64(seed);
        let mut r = vec![0.0f64; n + 200];
        for t in 2..r.len() {
            let e: f64 = StandardNormal.sample(&mut rng);
            r[t] = 1.2 * r[t - 1] - 0.5 * r[t - 2] + 0.5 * e;
        }
        r.split_off(200)
    }

    #[test]
    fn recovers_known_coefficients_from_a_long_record() {
        let r = ar2(100_000, 7);
        let ar = fit_ar(&r, 2).unwrap_or_else(|| Ar {
            d: vec![],
            sigma2: f64::NAN,
        });
        // D(q) = 1 − 1.2 q⁻¹ + 0.5 q⁻²; standard error ≈ sqrt((1 − 0.5²)/N) ≈ 0.003.
        assert!((ar.d[0] + 1.2).abs() < 0.015, "{:?}", ar.d);
        assert!((ar.d[1] - 0.5).abs() < 0.015, "{:?}", ar.d);
        assert!((ar.sigma2 - 0.25).abs() < 0.01, "{}", ar.sigma2);
        // The innovations whiten the record: lag-1 autocorrelation near 0.
        let e = ar.innovations(&r);
        let e = &e[2..];
        let c0: f64 = e.iter().map(|v| v * v).sum();
        let c1: f64 = e.windows(2).map(|w| w[0] * w[1]).sum();
        assert!((c1 / c0).abs() < 0.02, "{}", c1 / c0);
    }

    #[test]
    fn too_short_or_order_zero_is_refused() {
        assert!(fit_ar(&[1.0, 2.0], 2).is_none());
        assert!(fit_ar(&[1.0, 2.0, 3.0], 0).is_none());
    }
    #[test]
    fn both_solvers_agree_and_the_sample_rule_is_kept() {
        let r = ar2(5_000, 3);
        let chol = fit_ar(&r, 3).map(|a| a.d).unwrap_or_default();
        let settings = ArSettings {
            solver: ArSolver::MinimumNorm,
            per_order: 3,
            extra: 10,
        };
        let mn = fit_ar_with(&r, 3, &settings)
            .map(|a| a.d)
            .unwrap_or_default();
        assert_eq!(chol.len(), 3);
        assert!(
            chol.iter().zip(&mn).all(|(a, b)| (a - b).abs() < 1e-9),
            "{chol:?} {mn:?}"
        );
        // 3 · 3 + 10 = 19 samples are not enough, 20 are.
        assert!(fit_ar_with(&r[..19], 3, &settings).is_none());
        assert!(fit_ar_with(&r[..20], 3, &settings).is_some());
    }
}
