//! Levenberg–Marquardt on a residual vector, for fits on a simulation or prediction error.
//! Every iteration is bounded; a step is taken only if the model it gives is admissible (e.g.
//! stable) and simulates.
//!
//! One iteration: the Jacobian `J` at `θ` (forward differences, or the caller's analytic one),
//! then damped steps `(JᵀJ + λ diag) δ = −Jᵀr` with growing `λ` until one lowers `‖r‖²`
//! ([`StepSolver`], [`Damping`]); it stops when no damping gives a decrease or the relative
//! decrease falls to `min_gain`. [`Settings::default`] is the diagnosis's fit on a simulation
//! error; [`Settings::prediction_error`] the prediction-error refinement's.

use nalgebra::{DMatrix, DVector};

/// What to do when a difference step leaves the region where the model simulates.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum JacobianFailure {
    /// Stop and return the best parameters so far.
    Stop,
    /// Give up: no result.
    Fail,
}

/// Why [`minimise`] gave no result.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
pub enum LmFailure {
    /// The starting parameters do not simulate.
    #[error("the starting parameters do not simulate: start from a stable model")]
    StartDoesNotSimulate,
    /// A difference step left the region where the model simulates, with
    /// [`JacobianFailure::Fail`].
    #[error(
        "the difference step of parameter {parameter} left the region where the model simulates"
    )]
    DifferenceStepFailed {
        /// The parameter whose step failed.
        parameter: usize,
    },
    /// A step was not finite or the parameters grew past the bound of [`Divergence::Fail`].
    #[error("Levenberg–Marquardt diverged at iteration {iteration}")]
    Diverged {
        /// The iteration (from 1) at which it happened.
        iteration: usize,
    },
    /// The iteration limit was reached with [`Exhausted::Fail`] before the gain test passed.
    #[error(
        "Levenberg–Marquardt did not converge in {iterations} iterations (last relative decrease {last_gain:.3e})"
    )]
    NoConvergence {
        /// Iterations done.
        iterations: usize,
        /// Relative decrease of `‖r‖²` by the last accepted step (infinite if none).
        last_gain: f64,
    },
}

/// How the damped normal equations are solved.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StepSolver {
    /// `(JᵀJ + λ diag(max(JᵀJ_jj, 10⁻¹²))) δ = −Jᵀr` by LU.
    Lu,
    /// `(JᵀJ + λ diag(max(JᵀJ_jj, 10⁻¹² (1 + |JᵀJ_jj|)))) δ = −Jᵀr` by Cholesky.
    Cholesky,
}

impl StepSolver {
    /// The step for damping `lambda`; `None` if the damped matrix is singular (LU) or not
    /// positive definite (Cholesky).
    fn step(self, jtj: &DMatrix<f64>, jtr: &DVector<f64>, lambda: f64) -> Option<Vec<f64>> {
        let mut lhs = jtj.clone();
        match self {
            StepSolver::Lu => {
                for j in 0..lhs.nrows() {
                    lhs[(j, j)] += lambda * jtj[(j, j)].max(1e-12);
                }
                lhs.lu().solve(&(-jtr)).map(|d| d.iter().copied().collect())
            }
            StepSolver::Cholesky => {
                for j in 0..lhs.nrows() {
                    let d = jtj[(j, j)].max(1e-12 * (1.0 + jtj[(j, j)].abs()));
                    lhs[(j, j)] += lambda * d;
                }
                lhs.cholesky()
                    .map(|c| (-c.solve(jtr)).iter().copied().collect())
            }
        }
    }
}

/// When an iteration gives up increasing the damping.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DampingLimit {
    /// After this many damped steps in one iteration.
    Tries(usize),
    /// When the damping reaches this value (it is not reset between iterations).
    Ceiling(f64),
}

/// The damping `λ` and how it moves: ×`increase` after a refused step, ÷`decrease` (not below
/// `floor`) after an accepted one.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Damping {
    /// `λ` at the start (relative to the diagonal of `JᵀJ`).
    pub initial: f64,
    /// Factor after a refused step.
    pub increase: f64,
    /// Divisor after an accepted step.
    pub decrease: f64,
    /// Smallest `λ`.
    pub floor: f64,
    /// When an iteration stops trying.
    pub limit: DampingLimit,
}

/// What counts as divergence.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Divergence {
    /// Nothing: a step that does not simulate is refused like any other.
    Ignore,
    /// A step with a non-finite entry, or parameters whose norm exceeds
    /// `growth · (1 + ‖θ₀‖)`, is [`LmFailure::Diverged`].
    Fail {
        /// The bound on the parameters' norm relative to `1 + ‖θ₀‖`.
        growth: f64,
    },
}

/// What the end of the iteration budget gives.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Exhausted {
    /// The best parameters so far.
    ReturnBest,
    /// [`LmFailure::NoConvergence`].
    Fail,
}

/// Settings of [`minimise`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Settings {
    /// Jacobians computed at most.
    pub iterations: usize,
    /// The damping policy.
    pub damping: Damping,
    /// It stops when a step lowers the squared error by no more than this fraction.
    pub min_gain: f64,
    /// What a failed difference step does.
    pub jacobian_failure: JacobianFailure,
    /// How the damped step is solved.
    pub solver: StepSolver,
    /// What counts as divergence.
    pub divergence: Divergence,
    /// What the end of the iteration budget gives.
    pub exhausted: Exhausted,
}

impl Default for Settings {
    /// The fit on a simulation error: 30 iterations, `λ` from 10⁻² (×10 up to 8 times per
    /// iteration, ÷3 down to 10⁻⁹), LU steps, the best parameters at the end.
    fn default() -> Self {
        Self {
            iterations: 30,
            damping: Damping {
                initial: 1e-2,
                increase: 10.0,
                decrease: 3.0,
                floor: 1e-9,
                limit: DampingLimit::Tries(8),
            },
            min_gain: 1e-6,
            jacobian_failure: JacobianFailure::Stop,
            solver: StepSolver::Lu,
            divergence: Divergence::Ignore,
            exhausted: Exhausted::ReturnBest,
        }
    }
}

impl Settings {
    /// The fit of a model with its own simulation (the element with memory, friction):
    /// [`Settings::default`] with `iterations`, a stop when a step gains less than 10⁻⁹ of the
    /// error, and up to 14 damped steps per iteration (a simulated element's error surface has
    /// kinks the damping has to step over).
    pub fn simulation_fit(iterations: usize) -> Self {
        let base = Self::default();
        Self {
            iterations,
            min_gain: 1e-9,
            damping: Damping {
                limit: DampingLimit::Tries(14),
                ..base.damping
            },
            ..base
        }
    }

    /// The prediction-error refinement: `λ` from 10⁻³ (×10 until 10¹², ÷10 down to 10⁻¹²),
    /// Cholesky steps, divergence past `10⁸ (1 + ‖θ₀‖)`, and a failure when `iterations` pass
    /// without the relative decrease falling below `min_gain`.
    pub fn prediction_error(iterations: usize, min_gain: f64) -> Self {
        Self {
            iterations,
            damping: Damping {
                initial: 1e-3,
                increase: 10.0,
                decrease: 10.0,
                floor: 1e-12,
                limit: DampingLimit::Ceiling(1e12),
            },
            min_gain,
            jacobian_failure: JacobianFailure::Fail,
            solver: StepSolver::Cholesky,
            divergence: Divergence::Fail { growth: 1e8 },
            exhausted: Exhausted::Fail,
        }
    }
}

/// How the Jacobian of the residual is obtained.
#[derive(Clone, Copy)]
pub enum Jacobian<'a> {
    /// Forward differences with step `10⁻⁶ · max(|θ_j|, typical[j])` (`10⁻³` for a missing
    /// `typical[j]`).
    ForwardDifference {
        /// The size of each parameter.
        typical: &'a [f64],
    },
    /// The caller's analytic Jacobian at `θ` (one row per residual).
    Analytic(&'a dyn Fn(&[f64]) -> DMatrix<f64>),
    /// The caller's normal equations `(JᵀJ, Jᵀr)` at `θ` with `r` the residual there: for a
    /// long record, where the iteration is not to hold a Jacobian of a row per sample.
    Normal(&'a dyn Fn(&[f64], &[f64]) -> NormalEquations),
}

/// `(JᵀJ, Jᵀr)`.
pub type NormalEquations = (DMatrix<f64>, DVector<f64>);

/// A least-squares problem: the residual, where steps are admissible, and its Jacobian.
#[derive(Clone, Copy)]
pub struct Problem<'a> {
    /// `r(θ)`, `None` where the model does not simulate.
    pub residual: &'a dyn Fn(&[f64]) -> Option<Vec<f64>>,
    /// Refuses steps (e.g. unstable models).
    pub admissible: &'a dyn Fn(&[f64]) -> bool,
    /// How the Jacobian is obtained.
    pub jacobian: Jacobian<'a>,
}

/// The result of [`minimise`].
#[derive(Clone, Debug, PartialEq)]
pub struct Minimum {
    /// The best parameters.
    pub theta: Vec<f64>,
    /// The residual at `theta`.
    pub residual: Vec<f64>,
    /// Iterations begun (Jacobians asked for).
    pub iterations: usize,
    /// The relative decrease of `‖r‖²` by the last accepted step when the iteration budget
    /// ended before the gain test passed ([`Exhausted::ReturnBest`]); `None` when it stopped
    /// on its own.
    pub unconverged: Option<f64>,
}

/// The normal equations `(JᵀJ, Jᵀr)` at `theta` with residual `r`; `Err(j)` if the
/// difference step of parameter `j` does not simulate.
fn normal_at(problem: &Problem<'_>, theta: &[f64], r: &[f64]) -> Result<NormalEquations, usize> {
    let jac = match problem.jacobian {
        Jacobian::Normal(normal) => return Ok(normal(theta, r)),
        Jacobian::Analytic(jac) => jac(theta),
        Jacobian::ForwardDifference { typical } => jacobian_at(typical, problem, theta, r)?,
    };
    Ok((jac.tr_mul(&jac), jac.tr_mul(&DVector::from_column_slice(r))))
}

/// The forward-difference Jacobian at `theta` with residual `r`; `Err(j)` if the difference
/// step of parameter `j` does not simulate.
fn jacobian_at(
    typical: &[f64],
    problem: &Problem<'_>,
    theta: &[f64],
    r: &[f64],
) -> Result<DMatrix<f64>, usize> {
    let p = theta.len();
    let mut jac = DMatrix::<f64>::zeros(r.len(), p);
    for j in 0..p {
        let step = 1e-6 * theta[j].abs().max(typical.get(j).copied().unwrap_or(1e-3));
        let mut tj = theta.to_vec();
        tj[j] += step;
        match (problem.residual)(&tj) {
            Some(rj) if rj.len() == r.len() => {
                for (t, (a, b)) in rj.iter().zip(r).enumerate() {
                    jac[(t, j)] = (a - b) / step;
                }
            }
            _ => return Err(j),
        }
    }
    Ok(jac)
}

/// Minimises `‖r(θ)‖²` of `problem` from `theta0` with `settings`. Returns the best `θ`, its
/// residual and the iterations; an [`LmFailure`] if `theta0` does not simulate, a difference
/// step fails with [`JacobianFailure::Fail`], the iteration diverges
/// ([`Divergence::Fail`]) or the budget ends with [`Exhausted::Fail`].
pub fn minimise(
    problem: &Problem<'_>,
    theta0: &[f64],
    settings: &Settings,
) -> Result<Minimum, LmFailure> {
    let mut theta = theta0.to_vec();
    let mut r = (problem.residual)(&theta).ok_or(LmFailure::StartDoesNotSimulate)?;
    let sse = |r: &[f64]| r.iter().map(|v| v * v).sum::<f64>();
    let norm = |t: &[f64]| t.iter().map(|v| v * v).sum::<f64>().sqrt();
    let scale0 = 1.0 + norm(&theta);
    let mut best = sse(&r);
    let damping = settings.damping;
    let mut lambda = damping.initial;
    let mut last_gain = f64::INFINITY;
    for it in 1..=settings.iterations {
        let (jtj, jtr) = match normal_at(problem, &theta, &r) {
            Ok(normal) => normal,
            Err(parameter) => match settings.jacobian_failure {
                JacobianFailure::Stop => {
                    return Ok(Minimum {
                        theta,
                        residual: r,
                        iterations: it,
                        unconverged: None,
                    });
                }
                JacobianFailure::Fail => {
                    return Err(LmFailure::DifferenceStepFailed { parameter });
                }
            },
        };
        let mut stepped = false;
        let mut tries = 0;
        while match damping.limit {
            DampingLimit::Tries(n) => tries < n,
            DampingLimit::Ceiling(c) => lambda < c,
        } {
            tries += 1;
            let Some(delta) = settings.solver.step(&jtj, &jtr, lambda) else {
                lambda *= damping.increase;
                continue;
            };
            let trial: Vec<f64> = theta.iter().zip(&delta).map(|(a, d)| a + d).collect();
            if matches!(settings.divergence, Divergence::Fail { .. })
                && trial.iter().any(|v| !v.is_finite())
            {
                return Err(LmFailure::Diverged { iteration: it });
            }
            // A diverging or refused step counts as an infinite error.
            if (problem.admissible)(&trial)
                && let Some(rt) = (problem.residual)(&trial)
            {
                let e = sse(&rt);
                if e < best {
                    last_gain = (best - e) / best.max(1e-300);
                    theta = trial;
                    r = rt;
                    best = e;
                    lambda = (lambda / damping.decrease).max(damping.floor);
                    stepped = last_gain > settings.min_gain;
                    break;
                }
            }
            lambda *= damping.increase;
        }
        if let Divergence::Fail { growth } = settings.divergence
            && (!best.is_finite() || norm(&theta) > growth * scale0)
        {
            return Err(LmFailure::Diverged { iteration: it });
        }
        if !stepped {
            return Ok(Minimum {
                theta,
                residual: r,
                iterations: it,
                unconverged: None,
            });
        }
    }
    match settings.exhausted {
        Exhausted::ReturnBest => Ok(Minimum {
            theta,
            residual: r,
            iterations: settings.iterations,
            unconverged: Some(last_gain),
        }),
        Exhausted::Fail => Err(LmFailure::NoConvergence {
            iterations: settings.iterations,
            last_gain,
        }),
    }
}

/// [`minimise`] with forward-difference Jacobians: `typical[j]` is the size of `θ_j` for its
/// difference step. Returns the best `θ` and its residual.
pub fn levenberg_marquardt(
    theta0: &[f64],
    typical: &[f64],
    settings: &Settings,
    residual: &dyn Fn(&[f64]) -> Option<Vec<f64>>,
    admissible: &dyn Fn(&[f64]) -> bool,
) -> Result<(Vec<f64>, Vec<f64>), LmFailure> {
    let problem = Problem {
        residual,
        admissible,
        jacobian: Jacobian::ForwardDifference { typical },
    };
    minimise(&problem, theta0, settings).map(|m| (m.theta, m.residual))
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
    #[test]
    fn an_analytic_jacobian_with_the_prediction_error_settings_reaches_the_known_minimum() -> Outcome
    {
        // y = 2 exp(−0.3 t); J = [exp(−b t), −a t exp(−b t)].
        let t: Vec<f64> = (0..30).map(f64::from).collect();
        let y: Vec<f64> = t.iter().map(|t| 2.0 * (-0.3 * t).exp()).collect();
        let residual = |th: &[f64]| -> Option<Vec<f64>> {
            Some(
                t.iter()
                    .zip(&y)
                    .map(|(t, y)| th[0] * (-th[1] * t).exp() - y)
                    .collect(),
            )
        };
        let jacobian = |th: &[f64]| {
            DMatrix::from_fn(t.len(), 2, |i, j| {
                let e = (-th[1] * t[i]).exp();
                if j == 0 { e } else { -th[0] * t[i] * e }
            })
        };
        let problem = Problem {
            residual: &residual,
            admissible: &|_| true,
            jacobian: Jacobian::Analytic(&jacobian),
        };
        let min = minimise(
            &problem,
            &[1.0, 0.1],
            &Settings::prediction_error(100, 1e-12),
        )?;
        assert!(
            (min.theta[0] - 2.0).abs() < 1e-8 && (min.theta[1] - 0.3).abs() < 1e-8,
            "{:?}",
            min.theta
        );
        assert!(
            min.iterations > 1 && min.iterations < 100,
            "{}",
            min.iterations
        );
        // One iteration is not enough: with the budget failing, no result.
        let short = Settings::prediction_error(1, 1e-12);
        assert!(matches!(
            minimise(&problem, &[1.0, 0.1], &short),
            Err(LmFailure::NoConvergence { iterations: 1, .. })
        ));
        // The normal equations of the same Jacobian take the same steps: the same iterate,
        // bit for bit, after the same number of iterations.
        let normal = |th: &[f64], r: &[f64]| {
            let j = jacobian(th);
            (j.tr_mul(&j), j.tr_mul(&DVector::from_column_slice(r)))
        };
        let by_normal = Problem {
            jacobian: Jacobian::Normal(&normal),
            ..problem
        };
        let same = minimise(
            &by_normal,
            &[1.0, 0.1],
            &Settings::prediction_error(100, 1e-12),
        )?;
        assert_eq!(same, min);
        Ok(())
    }

    #[test]
    fn parameters_running_away_diverge_only_when_asked() {
        // r = 1/θ: each Gauss–Newton step doubles θ, the error falls towards 0 at infinity.
        let residual = |th: &[f64]| -> Option<Vec<f64>> { Some(vec![1.0 / th[0]]) };
        let jacobian = |th: &[f64]| DMatrix::from_element(1, 1, -1.0 / (th[0] * th[0]));
        let problem = Problem {
            residual: &residual,
            admissible: &|_| true,
            jacobian: Jacobian::Analytic(&jacobian),
        };
        // Bound 10 (1 + 1) = 20: θ ≈ 1, 2, 4, 8, 16, 32 passes it at the fifth step.
        let bounded = Settings {
            divergence: Divergence::Fail { growth: 10.0 },
            ..Settings::prediction_error(50, 1e-9)
        };
        assert_eq!(
            minimise(&problem, &[1.0], &bounded),
            Err(LmFailure::Diverged { iteration: 5 })
        );
        // Without the bound the budget ends with the best θ so far (≈ 2¹⁰ after 10 steps).
        let free = Settings {
            iterations: 10,
            divergence: Divergence::Ignore,
            exhausted: Exhausted::ReturnBest,
            ..bounded
        };
        let min = minimise(&problem, &[1.0], &free).map(|m| m.theta[0]);
        assert!(min.is_ok_and(|th| th > 500.0 && th < 2048.0), "{min:?}");
    }
}
