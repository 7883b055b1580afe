//! Why a hysteresis model could not be fitted.

use std::fmt;

use crate::numerics::lm::LmFailure;

/// Why [`fit_hysteresis`](super::fit_hysteresis) gave no model.
#[derive(Clone, Debug, PartialEq)]
pub enum HysteresisError {
    /// `u` and `y` differ in length.
    LengthMismatch {
        /// Samples of `u`.
        u: usize,
        /// Samples of `y`.
        y: usize,
    },
    /// The mask of samples left out of the error differs in length from the record.
    SkipMismatch {
        /// Samples of the record.
        samples: usize,
        /// Entries of the mask.
        skip: usize,
    },
    /// Fewer samples than a few per parameter.
    TooFewSamples {
        /// Samples given.
        have: usize,
        /// Samples needed.
        need: usize,
    },
    /// An input or output sample is not finite.
    NonFinite {
        /// `"u"` or `"y"`.
        signal: &'static str,
        /// Its index.
        index: usize,
    },
    /// The starting model cannot start the fit (what is wrong with it).
    InvalidStart(String),
    /// The starting model does not simulate (its `F(q)` is unstable or the borders cross).
    StartDoesNotSimulate,
    /// The starting model is stable, but has a pole at or beyond the radius the fit admits
    /// ([`FitOptions::max_pole_radius`](super::FitOptions::max_pole_radius)).
    StartTooSlow {
        /// The start's spectral radius.
        radius: f64,
        /// The radius admitted.
        limit: f64,
    },
    /// [`FitOptions::max_pole_radius`](super::FitOptions::max_pole_radius) is not in (0, 1].
    PoleRadius(f64),
    /// The parameters ran away or became non-finite.
    Diverged {
        /// Iteration (from 1).
        iteration: usize,
    },
    /// The Jacobian at the optimum is singular: the data do not determine every parameter.
    Singular,
}

impl fmt::Display for HysteresisError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            HysteresisError::LengthMismatch { u, y } => {
                write!(f, "u has {u} samples but y has {y}: give one y per u")
            }
            HysteresisError::SkipMismatch { samples, skip } => write!(
                f,
                "the record has {samples} samples but the mask of samples left out has {skip}: give one flag per sample, or none"
            ),
            HysteresisError::TooFewSamples { have, need } => write!(
                f,
                "too few samples for the hysteresis model: {have} given, at least {need} needed (a longer record, or fewer segments per path)"
            ),
            HysteresisError::NonFinite { signal, index } => write!(
                f,
                "{signal}[{index}] is not a finite number: remove or repair the sample"
            ),
            HysteresisError::InvalidStart(why) => write!(
                f,
                "the starting subspace model cannot start the hysteresis fit: {why}"
            ),
            HysteresisError::StartDoesNotSimulate => f.write_str(
                "the starting model does not simulate (unstable linear part, or crossing borders): start from a stable subspace estimate",
            ),
            HysteresisError::StartTooSlow { radius, limit } => write!(
                f,
                "the starting model has a pole of radius {radius:.6}, at or beyond the {limit:.6} admitted (a mode slower than the record can validate): a longer record, or a lower order"
            ),
            HysteresisError::PoleRadius(r) => write!(
                f,
                "the largest pole radius admitted is {r}, which is not in (0, 1]: give 1 to admit every stable linear part"
            ),
            HysteresisError::Diverged { iteration } => write!(
                f,
                "the simulation-error fit diverged at iteration {iteration}: try fewer segments per path or a lower order"
            ),
            HysteresisError::Singular => f.write_str(
                "the data do not determine every parameter of the hysteresis model (singular JᵀJ): the input must visit every segment in both directions; use fewer segments per path",
            ),
        }
    }
}

impl std::error::Error for HysteresisError {}

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
