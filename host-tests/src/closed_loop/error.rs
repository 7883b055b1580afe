//! Why a closed-loop estimate from a reference could not be made.

use std::fmt;

use crate::reference::RefError;

/// Errors of the closed-loop estimate ([`crate::closed_loop::reference_iv`]).
#[derive(Clone, Debug, PartialEq)]
pub enum ReferenceError {
    /// `u`, `y` and `r` differ in length.
    LengthMismatch {
        /// Samples of `u`.
        u: usize,
        /// Samples of `y`.
        y: usize,
        /// Samples of `r`.
        r: usize,
    },
    /// A reference value is not finite.
    NonFiniteReference {
        /// Its sample (from the record's start).
        at: usize,
    },
    /// The reference does not move over the excitation: it cannot be an instrument.
    ConstantReference,
    /// Too few excitation samples for the instruments' block Hankel matrix.
    TooShort {
        /// Excitation samples needed.
        needed: usize,
        /// Excitation samples given.
        got: usize,
    },
    /// Too few command samples (inside `]u_min, u_max[`) to fit the input's predictor.
    FewCommands {
        /// Command samples needed.
        needed: usize,
        /// Command samples found.
        got: usize,
    },
    /// A Gram matrix built from the reference is (numerically) singular: the reference does
    /// not excite the regressors it must stand in for.
    RankDeficient(&'static str),
    /// A singular value decomposition did not converge.
    NoConvergence(&'static str),
    /// No hold to measure μ0 and no μ0 given.
    NoMuZero,
    /// The element has one static border; the closed-loop estimate is for two paths.
    StaticElement,
    /// A step shared with the open-loop reference estimate failed.
    Subspace(RefError),
}

impl fmt::Display for ReferenceError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ReferenceError::LengthMismatch { u, y, r } => write!(
                f,
                "u has {u} samples, y {y} and the reference {r}: give one reference value per sample"
            ),
            ReferenceError::NonFiniteReference { at } => write!(
                f,
                "the reference is not finite at sample {at}: log a number on every row"
            ),
            ReferenceError::ConstantReference => write!(
                f,
                "the reference is constant over the excitation: a closed-loop estimate needs a reference that moves (log the controller's setpoint, not a fixed value)"
            ),
            ReferenceError::TooShort { needed, got } => write!(
                f,
                "{got} excitation samples, at least {needed} needed for the reference's instruments: record longer or use fewer knots or shorter horizons"
            ),
            ReferenceError::FewCommands { needed, got } => write!(
                f,
                "{got} input samples inside ]u_min, u_max[, at least {needed} needed to predict the input from the reference: the controller's commands must fill the record"
            ),
            ReferenceError::RankDeficient(which) => write!(
                f,
                "{which}: singular, the reference does not excite the input enough (a richer reference, e.g. random rather than steps, or fewer knots)"
            ),
            ReferenceError::NoConvergence(which) => {
                write!(f, "the SVD of {which} did not converge")
            }
            ReferenceError::NoMuZero => write!(
                f,
                "the closed-loop estimate needs μ0: record a hold at u_min (--hold) or give --mu0"
            ),
            ReferenceError::StaticElement => write!(
                f,
                "the closed-loop estimate is for a two-path element (backlash or switch), not --nonlinearity static"
            ),
            ReferenceError::Subspace(e) => write!(f, "{e}"),
        }
    }
}

impl std::error::Error for ReferenceError {}

impl From<RefError> for ReferenceError {
    fn from(e: RefError) -> Self {
        ReferenceError::Subspace(e)
    }
}
