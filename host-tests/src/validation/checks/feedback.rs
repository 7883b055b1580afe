//! Feedback in the record: is the input correlated with earlier residuals of an open-loop
//! model?
//!
//! In open loop the input is computed without looking at the output, so the residuals
//! `ε(t − k)`, `k ≥ 1`, of a model fitted to the record say nothing about `u(t)` that the
//! input's own past does not already say. A controller that computes `u(t)` from the measured
//! output feeds the noise back into the input, and earlier residuals then predict it. The
//! test (Ljung, *System Identification: Theory for the User*, "Testing for feedback", in its
//! regression form, a Granger test): regress `u(t)` on a constant, its own past
//! `u(t − 1 … t − L)` with `L = 2K` (which absorbs the input's colour and the Table I cycle),
//! the model's simulated output `ŷ(t − 1 … t − K)` (a controller acting on the noise-free
//! output is a function of past inputs, not feedback of the noise; this also absorbs what the
//! model's own error makes of past inputs) and the past residuals `ε(t − 1 … t − K)`, and
//! test the residuals' coefficients `β` together: the Wald statistic `χ² = βᵀ V⁻¹ β` with
//! `V` their heteroscedasticity-robust (White) covariance is `χ²(K)` under "no feedback";
//! the threshold is its 1 % quantile.

use nalgebra::{DMatrix, DVector};

use super::warning::{Check, Warning, warn};
use crate::closed_loop::Estimator;
use crate::identify::{IdentifyError, IdentifyOptions, identify};
use crate::numerics::lstsq::{Scaling, solve_normal};
use crate::validation::residual::result::LEVEL;
use crate::validation::stats::chi2_quantile;

/// Past residuals tested, `K`.
pub(crate) const LAGS: usize = 10;

/// The feedback test's outcome.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FeedbackTest {
    /// Wald `χ²` of the past residuals' coefficients in the regression of `u(t)`.
    pub statistic: f64,
    /// Its 1 % threshold, the `χ²(K)` quantile.
    pub threshold: f64,
    /// The lag `k` whose coefficient has the largest `|t|`: `u(t)` against `ε(t − k)`.
    pub lag: usize,
    /// Lags tested, `K`.
    pub lags: usize,
}

impl FeedbackTest {
    /// Whether the statistic exceeds its threshold.
    pub fn fires(&self) -> bool {
        self.statistic > self.threshold
    }
}

/// The test on an input, the model's simulated output and its residual `y − ŷ`, of one
/// length (the excitation part, without the hold), or `None` when there are fewer than
/// `10 (L + 2K + 1)` samples or the regression is degenerate.
pub fn feedback_test(u: &[f64], simulated: &[f64], residual: &[f64]) -> Option<FeedbackTest> {
    let n = u.len().min(residual.len()).min(simulated.len());
    let (k, l) = (LAGS, 2 * LAGS);
    let base = 1 + l + k;
    let cols = base + k;
    if n < 10 * cols {
        return None;
    }
    let rows = n - l;
    let x = DMatrix::from_fn(rows, cols, |i, j| {
        let t = i + l;
        match j {
            0 => 1.0,
            j if j <= l => u[t - j],
            j if j < base => simulated[t - (j - l)],
            j => residual[t - (j - base + 1)],
        }
    });
    let b = DVector::from_fn(rows, |i, _| u[i + l]);
    // One Gram for the coefficients and their covariance.
    let gram = x.transpose() * &x;
    let coef = solve_normal(&gram, &(x.transpose() * &b), Scaling::UnitDiagonal)?;
    let e = &b - &x * &coef;
    // Heteroscedasticity-robust (White) covariance of the coefficients: the input's innovation
    // is not of one variance over a Table I cycle.
    let inv = gram.try_inverse()?;
    let xe = DMatrix::from_fn(rows, cols, |i, j| x[(i, j)] * e[i]);
    let meat = xe.transpose() * xe;
    let cov = &inv * meat * &inv * (rows as f64 / (rows - cols) as f64);
    let v = cov.view((base, base), (k, k)).into_owned();
    let c = coef.rows(base, k).into_owned();
    let wald = (c.transpose() * v.clone().try_inverse()? * &c)[(0, 0)];
    if !wald.is_finite() {
        return None;
    }
    let lag = (0..k)
        .map(|j| (j + 1, c[j].abs() / v[(j, j)].sqrt()))
        .fold((0, 0.0), |a, b| if b.1 > a.1 { b } else { a })
        .0;
    Some(FeedbackTest {
        statistic: wald,
        threshold: chi2_quantile(1.0 - LEVEL, k as f64),
        lag,
        lags: k,
    })
}

/// The warning of a test that fires, for a model from `estimator`: with the open-loop
/// estimate, the advice to log the reference and take the closed-loop estimate; with the
/// closed-loop estimate from the reference, that the base model already is it.
pub fn feedback_warning(t: &FeedbackTest, estimator: Estimator) -> Option<Warning> {
    t.fires().then(|| {
        let (model, advice) = match estimator {
            Estimator::OpenLoop => (
                "open-loop",
                "which can bias the open-loop subspace estimate and the output-error fit, \
                 pulling the poles toward the controller's; record an open-loop experiment (an \
                 input not computed from the output, e.g. hsid excite) or, with the \
                 controller's reference logged as a column, take the closed-loop estimate: hsid \
                 identify --reference-column NAME (docs/closed-loop.md); a model far from the \
                 data (see the other warnings) can also look like feedback",
            ),
            Estimator::Reference => (
                "base",
                "as expected with a reference column: the base model and every refit are the \
                 closed-loop-consistent estimate from the reference (instruments from the \
                 reference, poles not refined by the output error; docs/closed-loop.md), so \
                 the feedback does not bias their poles; the input stays correlated with the \
                 earlier noise, which the controller feeds back",
            ),
        };
        let found = format!(
            "earlier residuals of the {model} model predict the input (χ² = {:.1} over {} lags, \
             threshold {:.1}; strongest at lag {}): the record looks closed-loop (the input \
             computed from the measured output)",
            t.statistic, t.lags, t.threshold, t.lag
        );
        warn(Check::Feedback, format!("{found}, {advice}"))
    })
}

/// The check on an input, the simulated output and the residual (the excitation part, without
/// the hold) of a model from `estimator`.
pub fn feedback(
    u: &[f64],
    simulated: &[f64],
    residual: &[f64],
    estimator: Estimator,
) -> Option<Warning> {
    feedback_test(u, simulated, residual)
        .as_ref()
        .and_then(|t| feedback_warning(t, estimator))
}

/// The simulated output `ŷ` and the residual `y − ŷ` of the open-loop identification of
/// `(u, y)` with `opts`, simulated from rest at `u_min`, after the hold (`opts.hold` samples).
pub(crate) fn open_loop_residual(
    u: &[f64],
    y: &[f64],
    opts: &IdentifyOptions,
) -> Result<(Vec<f64>, Vec<f64>), IdentifyError> {
    let model = identify(u, y, opts)?;
    let hold = opts.hold.min(u.len());
    let sim = model.simulate(u).split_off(hold);
    let e = y[hold..].iter().zip(&sim).map(|(a, b)| a - b).collect();
    Ok((sim, e))
}

/// The test on a whole record (hold included): identifies it open-loop with `opts` and tests
/// the input after the hold against that model's residual.
pub fn feedback_in_record(
    u: &[f64],
    y: &[f64],
    opts: &IdentifyOptions,
) -> Result<Option<FeedbackTest>, IdentifyError> {
    let (sim, e) = open_loop_residual(u, y, opts)?;
    Ok(feedback_test(&u[opts.hold.min(u.len())..], &sim, &e))
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use rand::SeedableRng;
    use rand_distr::{Distribution, StandardNormal};
    use rand_pcg::Pcg64;

    fn white(n: usize, seed: u64) -> Vec<f64> {
        let mut rng = Pcg64::seed_from_u64(seed);
        (0..n).map(|_| StandardNormal.sample(&mut rng)).collect()
    }

    #[test]
    fn an_input_made_of_earlier_residuals_fires_at_their_lag() {
        // u(t) = w(t) + 0.3 e(t − 3): the added variance 0.09 explains 0.09 / 1.09 of u, so
        // χ² ≈ N · 0.09 ≈ 270 at N = 3000 (threshold χ²(10) 1 % = 23.2).
        let (w, e) = (white(3000, 1), white(3000, 2));
        let u: Vec<f64> = (0..3000)
            .map(|t| w[t] + if t >= 3 { 0.3 * e[t - 3] } else { 0.0 })
            .collect();
        let t = feedback_test(&u, &white(3000, 5), &e).unwrap();
        assert_eq!(t.lag, 3);
        assert!(t.statistic > 200.0 && t.statistic < 350.0, "{t:?}");
        assert!((t.threshold - 23.21).abs() < 0.01, "{t:?}");
        assert!(feedback(&u, &white(3000, 5), &e, Estimator::OpenLoop).is_some());
    }

    #[test]
    fn a_residual_that_follows_the_input_is_not_feedback() {
        // ε(t) = u(t − 2) + noise, u an AR(1): the residual follows the input (a model
        // error), and u's own past explains what ε's past says about it.
        let (w, v) = (white(3000, 3), white(3000, 4));
        let mut u = vec![0.0; 3000];
        for t in 1..3000 {
            u[t] = 0.8 * u[t - 1] + w[t];
        }
        let e: Vec<f64> = (0..3000)
            .map(|t| v[t] + if t >= 2 { u[t - 2] } else { 0.0 })
            .collect();
        let t = feedback_test(&u, &white(3000, 6), &e).unwrap();
        assert!(!t.fires(), "{t:?}");
    }
}
