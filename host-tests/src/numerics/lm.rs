//! Levenberg–Marquardt on a residual vector with forward-difference Jacobians, for fits on a
//! simulation error. Every iteration is bounded; a step is taken only if the model it gives is
//! admissible (e.g. stable) and simulates.

use std::fmt;

use nalgebra::{DMatrix, DVector};

/// What to do when a difference step leaves the region where the model simulates.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum JacobianFailure {
    /// Stop and return the best parameters so far.
    Stop,
    /// Give up: no result.
    Fail,
}

/// Why [`levenberg_marquardt`] gave no result.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LmFailure {
    /// The starting parameters do not simulate.
    StartDoesNotSimulate,
    /// A difference step left the region where the model simulates, with
    /// [`JacobianFailure::Fail`].
    DifferenceStepFailed {
        /// The parameter whose step failed.
        parameter: usize,
    },
}

impl fmt::Display for LmFailure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            LmFailure::StartDoesNotSimulate => {
                f.write_str("the starting parameters do not simulate: start from a stable model")
            }
            LmFailure::DifferenceStepFailed { parameter } => write!(
                f,
                "the difference step of parameter {parameter} left the region where the model simulates"
            ),
        }
    }
}

impl std::error::Error for LmFailure {}

/// Settings of [`levenberg_marquardt`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Settings {
    /// Jacobians computed at most.
    pub iterations: usize,
    /// Damping at the start (relative to the diagonal of `JᵀJ`).
    pub initial_damping: f64,
    /// Damping increases (×10) tried per iteration before it stops.
    pub tries: usize,
    /// It stops when a step lowers the squared error by less than this fraction.
    pub min_gain: f64,
    /// What a failed difference step does.
    pub jacobian_failure: JacobianFailure,
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            iterations: 30,
            initial_damping: 1e-2,
            tries: 8,
            min_gain: 1e-6,
            jacobian_failure: JacobianFailure::Stop,
        }
    }
}

/// Minimises `‖residual(θ)‖²` from `theta0`: `residual(θ)` is `None` where the model does not
/// simulate, `admissible(θ)` refuses steps (e.g. unstable models), `typical[j]` is the size of
/// `θ_j` for its difference step (`10⁻⁶ · max(|θ_j|, typical[j])`). Returns the best `θ` and
/// its residual; an [`LmFailure`] if `theta0` does not simulate, or a difference step fails
/// with [`JacobianFailure::Fail`].
pub fn levenberg_marquardt(
    theta0: &[f64],
    typical: &[f64],
    settings: &Settings,
    residual: &dyn Fn(&[f64]) -> Option<Vec<f64>>,
    admissible: &dyn Fn(&[f64]) -> bool,
) -> Result<(Vec<f64>, Vec<f64>), LmFailure> {
    let mut theta = theta0.to_vec();
    let mut r = residual(&theta).ok_or(LmFailure::StartDoesNotSimulate)?;
    let sse = |r: &[f64]| r.iter().map(|v| v * v).sum::<f64>();
    let mut best = sse(&r);
    let mut lambda = settings.initial_damping;
    let p = theta.len();
    'iterations: for _ in 0..settings.iterations {
        let mut jac = DMatrix::<f64>::zeros(r.len(), p);
        for j in 0..p {
            let step = 1e-6 * theta[j].abs().max(typical.get(j).copied().unwrap_or(1e-3));
            let mut tj = theta.clone();
            tj[j] += step;
            match residual(&tj) {
                Some(rj) if rj.len() == r.len() => {
                    for (t, (a, b)) in rj.iter().zip(&r).enumerate() {
                        jac[(t, j)] = (a - b) / step;
                    }
                }
                _ => match settings.jacobian_failure {
                    JacobianFailure::Stop => break 'iterations,
                    JacobianFailure::Fail => {
                        return Err(LmFailure::DifferenceStepFailed { parameter: j });
                    }
                },
            }
        }
        let jtj = jac.tr_mul(&jac);
        let jtr = jac.tr_mul(&DVector::from_column_slice(&r));
        let mut stepped = false;
        for _ in 0..settings.tries {
            let mut lhs = jtj.clone();
            for j in 0..p {
                lhs[(j, j)] += lambda * jtj[(j, j)].max(1e-12);
            }
            let Some(delta) = lhs.lu().solve(&(-&jtr)) else {
                lambda *= 10.0;
                continue;
            };
            let trial: Vec<f64> = theta.iter().zip(delta.iter()).map(|(a, d)| a + d).collect();
            // A diverging or refused step counts as an infinite error.
            if admissible(&trial)
                && let Some(rt) = residual(&trial)
            {
                let e = sse(&rt);
                if e < best {
                    let rel = (best - e) / best.max(1e-300);
                    theta = trial;
                    r = rt;
                    best = e;
                    lambda = (lambda / 3.0).max(1e-9);
                    stepped = rel > settings.min_gain;
                    break;
                }
            }
            lambda *= 10.0;
        }
        if !stepped {
            break;
        }
    }
    Ok((theta, r))
}

#[cfg(test)]
mod tests {
    use super::*;

    type Outcome = Result<(), Box<dyn std::error::Error>>;

    #[test]
    fn fits_an_exponential() -> Outcome {
        // y = 2 exp(−0.3 t) from the start (1, 0.1): the minimum is exact.
        let t: Vec<f64> = (0..30).map(f64::from).collect();
        let y: Vec<f64> = t.iter().map(|t| 2.0 * (-0.3 * t).exp()).collect();
        let res = |th: &[f64]| -> Option<Vec<f64>> {
            Some(
                t.iter()
                    .zip(&y)
                    .map(|(t, y)| th[0] * (-th[1] * t).exp() - y)
                    .collect(),
            )
        };
        let (th, r) = levenberg_marquardt(&[1.0, 0.1], &[1.0, 0.1], &long(), &res, &|_| true)?;
        assert!(
            (th[0] - 2.0).abs() < 1e-6 && (th[1] - 0.3).abs() < 1e-6,
            "{th:?}"
        );
        assert!(r.iter().all(|v| v.abs() < 1e-6));
        // A refused region is never entered: with b ≤ 0.2 admissible only, b stops at it.
        let (th, _) =
            levenberg_marquardt(&[1.0, 0.1], &[1.0, 0.1], &long(), &res, &|t| t[1] <= 0.2)?;
        assert!(th[1] <= 0.2, "{th:?}");
        Ok(())
    }

    fn long() -> Settings {
        Settings {
            iterations: 100,
            ..Settings::default()
        }
    }

    #[test]
    fn fits_a_rosenbrock_valley_to_its_known_minimum() -> Outcome {
        // r = (10 (b − a²), 1 − a): the minimum ‖r‖² = 0 at (1, 1), reached from (−1.2, 1)
        // along the curved valley.
        let res = |th: &[f64]| -> Option<Vec<f64>> {
            Some(vec![10.0 * (th[1] - th[0] * th[0]), 1.0 - th[0]])
        };
        let (th, r) = levenberg_marquardt(&[-1.2, 1.0], &[1.0, 1.0], &long(), &res, &|_| true)?;
        assert!(
            (th[0] - 1.0).abs() < 1e-5 && (th[1] - 1.0).abs() < 1e-5,
            "{th:?}"
        );
        assert!(r.iter().map(|v| v * v).sum::<f64>() < 1e-10, "{r:?}");
        Ok(())
    }

    #[test]
    fn a_failed_difference_step_stops_or_fails() {
        // The model does not simulate for θ > 1.5; the start is just below, so the first
        // difference step of the second start leaves the region.
        let res = |th: &[f64]| -> Option<Vec<f64>> { (th[0] <= 1.5).then(|| vec![th[0] - 3.0]) };
        let stop = Settings::default();
        let fail = Settings {
            jacobian_failure: JacobianFailure::Fail,
            ..stop
        };
        let from = [1.5];
        assert_eq!(
            levenberg_marquardt(&from, &[1.0], &stop, &res, &|_| true).map(|(t, _)| t),
            Ok(vec![1.5])
        );
        assert_eq!(
            levenberg_marquardt(&from, &[1.0], &fail, &res, &|_| true),
            Err(LmFailure::DifferenceStepFailed { parameter: 0 })
        );
        assert_eq!(
            levenberg_marquardt(&[2.0], &[1.0], &stop, &res, &|_| true),
            Err(LmFailure::StartDoesNotSimulate)
        );
    }
}
