//! Does the residual depend on the sign of the simulated velocity? Friction the model lacks
//! pushes the output one way while the drive moves up and the other way while it moves
//! down.
//!
//! [`velocity_sign_arx`] asks it of the model's equation: the output (an integrating plant's
//! increment) regressed on its own past, the element's past output, `sign(v̂(t − 1))` and `1`
//! (an ARX model of the model's order with the friction regressors, as the fit starts from);
//! the sign's coefficient is the Coulomb force times `G`'s gain, and its t statistic, with
//! Newey–West errors over `⌈4 (N/100)^{2/9}⌉` lags, is the test, together with its size: the
//! Coulomb force it implies (the coefficient over the element's gain, `Σ bᵢ`) has to be at
//! least 2 % of the element's output's spread ([`VelocitySign::MIN_FORCE_SHARE`]). On a long
//! record with little noise any small mismatch of the linear model is significant (a
//! frictionless body's record of 20,000 samples gives |t| near 3), but it implies no force a
//! drive would notice. [`velocity_sign`] asks it of a simulation's residual
//! directly, which drifts and so tests weakly:
//!
//! The residual `r(t)` (of an integrating plant: its increments, the error of the velocity)
//! is regressed on `1` and `sign(v̂(t))`, where `v̂` is the model's simulated velocity and the
//! samples where the model barely moves (`|v̂| < 5 %` of its RMS) are left out. The residual
//! of a simulation is strongly autocorrelated, so the coefficient's standard error is the
//! Newey–West one (Bartlett weights up to `⌈4 (N/100)^{2/9}⌉` lags, and at least the longest
//! run of one sign, so that a run counts as one observation, not as many); the test fires
//! when `|t| > 3`.

use crate::numerics::rms;
use crate::validation::stats::newey_west_var_of_mean;

/// The outcome of [`velocity_sign`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VelocitySign {
    /// Half the difference of the residual's mean moving up and moving down (output units).
    pub difference: f64,
    /// Its t statistic (Newey–West standard error).
    pub t: f64,
    /// Samples used.
    pub samples: usize,
    /// The Coulomb force the coefficient implies over the standard deviation of the element's
    /// output ([`velocity_sign_arx`]); `NaN` for [`velocity_sign`].
    pub force_share: f64,
}

impl VelocitySign {
    /// The threshold on `|t|`.
    pub const THRESHOLD: f64 = 3.0;

    /// The smallest force share that counts, where it is measured.
    pub const MIN_FORCE_SHARE: f64 = 0.02;

    /// Whether the residual depends on the direction of motion: significantly, and (where it
    /// is measured) by a force of at least [`MIN_FORCE_SHARE`](Self::MIN_FORCE_SHARE) of the
    /// element's output's spread.
    pub fn fires(&self) -> bool {
        self.t.abs() > Self::THRESHOLD
            && (self.force_share.is_nan() || self.force_share >= Self::MIN_FORCE_SHARE)
    }
}

/// The change of `x` per sample, `before` the value before its first sample: a velocity from
/// a position.
pub(crate) fn per_sample_change(x: &[f64], before: f64) -> Vec<f64> {
    x.iter()
        .scan(before, |last, &v| {
            let change = v - *last;
            *last = v;
            Some(change)
        })
        .collect()
}

/// [`per_sample_change`] of a record that starts at rest: the first change 0.
pub(crate) fn change_from_rest(x: &[f64]) -> Vec<f64> {
    per_sample_change(x, x.first().copied().unwrap_or(0.0))
}

/// The test in the model's equation: `s` the output (an integrating plant's increments), `h`
/// the element's output, `v` the simulated velocity, all of one length, `n` the order. `None`
/// when fewer than `2n + 22` samples move, all move one way, or the regression is singular.
pub fn velocity_sign_arx(s: &[f64], h: &[f64], v: &[f64], n: usize) -> Option<VelocitySign> {
    velocity_sign_on(s, s, h, v, n)
}

/// The test of [`velocity_sign_arx`] with the past outputs taken from `past` (of `s`'s
/// length): the model's simulated output makes it the model's output-error equation, whose
/// regressors hold no measurement noise. With the measured past (an ARX equation) on a plant
/// sampled fast beside its dynamics, the noise in the past outputs biases the AR terms, and the
/// sign of the velocity, which follows the output's recent change, takes up the bias: a mass
/// on a spring without friction, sampled at 100 times its 10 rad/s at 30 dB, tested at t =
/// 20.8 with a force of 58 % that way, and at |t| < 3 on its simulated past
/// (`tests/friction_spring.rs`).
pub fn velocity_sign_on(
    s: &[f64],
    past: &[f64],
    h: &[f64],
    v: &[f64],
    n: usize,
) -> Option<VelocitySign> {
    let len = s.len().min(past.len()).min(h.len()).min(v.len());
    let floor = 0.05 * rms(v);
    let rows: Vec<usize> = (n.max(1)..len)
        .filter(|&t| v[t - 1].abs() > floor)
        .collect();
    let up = rows.iter().filter(|&&t| v[t - 1] > 0.0).count();
    if up == 0 || up == rows.len() {
        return None;
    }
    let term = equation_term(s, past, h, &rows, |t| v[t - 1].signum(), n)?;
    // The Coulomb force the coefficient implies, against the spread of the element's output.
    let nf = rows.len() as f64;
    let hs: Vec<f64> = rows.iter().map(|&t| h[t - 1]).collect();
    let hm = hs.iter().sum::<f64>() / nf;
    let spread = (hs.iter().map(|v| (v - hm) * (v - hm)).sum::<f64>() / nf).sqrt();
    Some(VelocitySign {
        difference: term.coefficient,
        t: term.t,
        samples: rows.len(),
        force_share: (term.coefficient / term.gain).abs() / spread,
    })
}

/// An extra term's coefficient in a model's equation ([`equation_term`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct EquationTerm {
    /// The term's coefficient.
    pub coefficient: f64,
    /// Its t statistic (Newey–West standard error).
    pub t: f64,
    /// The equation's gain from the element's output, `Σ bᵢ`.
    pub gain: f64,
}

/// The extra regressor `extra(t)` in the equation `s(t) = −Σ aᵢ past(t − i) + Σ bᵢ h(t − i)
/// + β extra(t) + c` of order `n`, on the samples `rows` (each `≥ n`): its coefficient `β`
/// and t statistic, Newey–West errors over `⌈4 (N/100)^{2/9}⌉` lags. `None` with fewer than
/// `2n + 22` rows or a singular regression.
pub(crate) fn equation_term(
    s: &[f64],
    past: &[f64],
    h: &[f64],
    rows: &[usize],
    extra: impl Fn(usize) -> f64,
    n: usize,
) -> Option<EquationTerm> {
    use crate::numerics::lstsq::{Scaling, lstsq};
    use nalgebra::{DMatrix, DVector};
    let k = 2 * n + 2;
    if rows.len() < k + 20 {
        return None;
    }
    let x = DMatrix::from_fn(rows.len(), k, |r, j| {
        let t = rows[r];
        if j < n {
            -past[t - 1 - j]
        } else if j < 2 * n {
            h[t - 1 - (j - n)]
        } else if j == 2 * n {
            extra(t)
        } else {
            1.0
        }
    });
    let y = DVector::from_iterator(rows.len(), rows.iter().map(|&t| s[t]));
    let th = lstsq(&x, &y, Scaling::UnitDiagonal)?;
    let e = &y - &x * &th;
    // Newey–West covariance of the term's coefficient: (XᵀX)⁻¹ S (XᵀX)⁻¹, row 2n.
    let xtx_inv = x.tr_mul(&x).try_inverse()?;
    let c = xtx_inv.row(2 * n).transpose();
    // z_t = (cᵀ x_t) e_t: the coefficient's influence of each row.
    let z: Vec<f64> = (0..rows.len())
        .map(|r| x.row(r).dot(&c.transpose()) * e[r])
        .collect();
    let nf = rows.len() as f64;
    // Σ_t Σ_s w(|t − s|) z_t z_s = N² · the Newey–West variance of z's mean (z has mean 0:
    // the residual is orthogonal to the regressors).
    let lags = (4.0 * (nf / 100.0).powf(2.0 / 9.0)).ceil() as usize;
    let beta = th[2 * n];
    let se = nf * newey_west_var_of_mean(&z, lags).sqrt();
    Some(EquationTerm {
        coefficient: beta,
        t: beta / se,
        gain: th.iter().skip(n).take(n).sum(),
    })
}

/// The test on the residual `r` and the simulated velocity `v` (same length); `None` when
/// fewer than 20 samples move or all move one way.
pub fn velocity_sign(r: &[f64], v: &[f64]) -> Option<VelocitySign> {
    let floor = 0.05 * rms(v);
    let pairs: Vec<(f64, f64)> = r
        .iter()
        .zip(v)
        .filter(|(_, v)| v.abs() > floor)
        .map(|(r, v)| (*r, v.signum()))
        .collect();
    let n = pairs.len();
    let up = pairs.iter().filter(|(_, s)| *s > 0.0).count();
    if n < 20 || up == 0 || up == n {
        return None;
    }
    // OLS of r on [1, s].
    let nf = n as f64;
    let (sm, rm) = (
        pairs.iter().map(|p| p.1).sum::<f64>() / nf,
        pairs.iter().map(|p| p.0).sum::<f64>() / nf,
    );
    let sxx: f64 = pairs.iter().map(|(_, s)| (s - sm) * (s - sm)).sum();
    let sxy: f64 = pairs.iter().map(|(r, s)| (s - sm) * (r - rm)).sum();
    let beta = sxy / sxx;
    let alpha = rm - beta * sm;
    // Newey–West variance of beta: Σ_t Σ_s w(|t−s|) x_t e_t x_s e_s / sxx².
    let xe: Vec<f64> = pairs
        .iter()
        .map(|(r, s)| (s - sm) * (r - alpha - beta * s))
        .collect();
    let longest = pairs
        .chunk_by(|a, b| a.1 == b.1)
        .map(<[(f64, f64)]>::len)
        .max()
        .unwrap_or(1);
    let lags = ((4.0 * (nf / 100.0).powf(2.0 / 9.0)).ceil() as usize).max(longest);
    // Σ_t Σ_s w(|t − s|) xe_t xe_s = N² · the Newey–West variance of xe's mean (mean 0).
    let se = nf * newey_west_var_of_mean(&xe, lags).sqrt() / sxx;
    Some(VelocitySign {
        difference: beta,
        t: beta / se,
        samples: n,
        force_share: f64::NAN,
    })
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    /// A velocity reversing every 500 samples; a residual of ±0.1 with the sign, plus an
    /// AR(1) noise of its own (a recursion written here), against the noise alone.
    #[test]
    fn a_residual_that_follows_the_direction_fires_and_noise_does_not() {
        let n = 20_000;
        let v: Vec<f64> = (0..n)
            .map(|t| if (t / 500) % 2 == 0 { 1.0 } else { -1.0 })
            .collect();
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut e = 0.0;
        let noise: Vec<f64> = (0..n)
            .map(|_| {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                let g = (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
                e = 0.95 * e + g;
                e
            })
            .collect();
        let with: Vec<f64> = noise.iter().zip(&v).map(|(e, v)| e + 0.5 * v).collect();
        let fired = velocity_sign(&with, &v).unwrap();
        assert!(fired.fires(), "{fired:?}");
        assert!((fired.difference - 0.5).abs() < 0.15, "{fired:?}");
        let quiet = velocity_sign(&noise, &v).unwrap();
        assert!(!quiet.fires(), "{quiet:?}");
    }
}
