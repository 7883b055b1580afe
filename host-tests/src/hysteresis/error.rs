//! Why a hysteresis model could not be fitted.

use crate::numerics::lm::LmFailure;

/// Why [`fit_hysteresis`](super::fit_hysteresis) gave no model.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum HysteresisError {
    /// `u` and `y` differ in length.
    #[error("u has {u} samples but y has {y}: give one y per u")]
    LengthMismatch {
        /// Samples of `u`.
        u: usize,
        /// Samples of `y`.
        y: usize,
    },
    /// The mask of samples left out of the error differs in length from the record.
    #[error(
        "the record has {samples} samples but the mask of samples left out has {skip}: give one flag per sample, or none"
    )]
    SkipMismatch {
        /// Samples of the record.
        samples: usize,
        /// Entries of the mask.
        skip: usize,
    },
    /// Fewer samples than a few per parameter.
    #[error(
        "too few samples for the hysteresis model: {have} given, at least {need} needed (a longer record, or fewer segments per path)"
    )]
    TooFewSamples {
        /// Samples given.
        have: usize,
        /// Samples needed.
        need: usize,
    },
    /// An input or output sample is not finite.
    #[error("{signal}[{index}] is not a finite number: remove or repair the sample")]
    NonFinite {
        /// `"u"` or `"y"`.
        signal: &'static str,
        /// Its index.
        index: usize,
    },
    /// The starting model cannot start the fit (what is wrong with it).
    #[error("the starting subspace model cannot start the hysteresis fit: {0}")]
    InvalidStart(String),
    /// The starting model does not simulate (its `F(q)` is unstable or the borders cross).
    #[error(
        "the starting model does not simulate (unstable linear part, or crossing borders): start from a stable subspace estimate"
    )]
    StartDoesNotSimulate,
    /// The starting model is stable, but has a pole at or beyond the radius the fit admits
    /// ([`ElementFitOptions::max_pole_radius`](super::ElementFitOptions::max_pole_radius)).
    #[error(
        "the starting model has a pole of radius {radius:.6}, at or beyond the {limit:.6} admitted (a mode slower than the record can validate): a longer record, or a lower order"
    )]
    StartTooSlow {
        /// The start's spectral radius.
        radius: f64,
        /// The radius admitted.
        limit: f64,
    },
    /// [`ElementFitOptions::max_pole_radius`](super::ElementFitOptions::max_pole_radius) is not in (0, 1].
    #[error(
        "the largest pole radius admitted is {0}, which is not in (0, 1]: give 1 to admit every stable linear part"
    )]
    PoleRadius(f64),
    /// The parameters ran away or became non-finite.
    #[error(
        "the simulation-error fit diverged at iteration {iteration}: try fewer segments per path or a lower order"
    )]
    Diverged {
        /// Iteration (from 1).
        iteration: usize,
    },
    /// The Jacobian at the optimum is singular: the data do not determine every parameter.
    #[error(
        "the data do not determine every parameter of the hysteresis model (singular JᵀJ): the input must visit every segment in both directions; use fewer segments per path"
    )]
    Singular,
}

impl From<LmFailure> for HysteresisError {
    fn from(e: LmFailure) -> Self {
        match e {
            LmFailure::StartDoesNotSimulate => HysteresisError::StartDoesNotSimulate,
            LmFailure::DifferenceStepFailed { parameter } => {
                HysteresisError::InvalidStart(format!(
                    "parameter {parameter} sits on the edge of the region where the model simulates"
                ))
            }
            LmFailure::Diverged { iteration } => HysteresisError::Diverged { iteration },
            LmFailure::NoConvergence { iterations, .. } => HysteresisError::Diverged {
                iteration: iterations,
            },
        }
    }
}
