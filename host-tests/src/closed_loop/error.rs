//! Why a closed-loop estimate from a reference could not be made.

use crate::reference::RefError;

/// Errors of the closed-loop estimate ([`crate::closed_loop::reference_iv`]).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ReferenceError {
    /// `u`, `y` and `r` differ in length.
    #[error("u has {u} samples, y {y} and the reference {r}: give one reference value per sample")]
    LengthMismatch {
        /// Samples of `u`.
        u: usize,
        /// Samples of `y`.
        y: usize,
        /// Samples of `r`.
        r: usize,
    },
    /// A reference value is not finite.
    #[error("the reference is not finite at sample {at}: log a number on every row")]
    NonFiniteReference {
        /// Its sample (from the record's start).
        at: usize,
    },
    /// The reference does not move over the excitation: it cannot be an instrument.
    #[error(
        "the reference is constant over the excitation: a closed-loop estimate needs a reference that moves (log the controller's setpoint, not a fixed value)"
    )]
    ConstantReference,
    /// Too few excitation samples for the instruments' block Hankel matrix.
    #[error(
        "{got} excitation samples, at least {needed} needed for the reference's instruments: record longer or use fewer knots or shorter horizons"
    )]
    TooShort {
        /// Excitation samples needed.
        needed: usize,
        /// Excitation samples given.
        got: usize,
    },
    /// Too few command samples (inside `]u_min, u_max[`) to fit the input's predictor.
    #[error(
        "{got} input samples inside ]u_min, u_max[, at least {needed} needed to predict the input from the reference: the controller's commands must fill the record"
    )]
    FewCommands {
        /// Command samples needed.
        needed: usize,
        /// Command samples found.
        got: usize,
    },
    /// A Gram matrix built from the reference is (numerically) singular: the reference does
    /// not excite the regressors it must stand in for.
    #[error(
        "{0}: singular, the reference does not excite the input enough (a richer reference, e.g. random rather than steps, or fewer knots)"
    )]
    RankDeficient(&'static str),
    /// A singular value decomposition did not converge.
    #[error("the SVD of {0} did not converge")]
    NoConvergence(&'static str),
    /// No hold to measure μ0 and no μ0 given.
    #[error("the closed-loop estimate needs μ0: record a hold at u_min (--hold) or give --mu0")]
    NoMuZero,
    /// The element has one static border; the closed-loop estimate is for two paths.
    #[error(
        "the closed-loop estimate is for a two-path element (backlash or switch), not --nonlinearity static"
    )]
    StaticElement,
    /// A step shared with the open-loop reference estimate failed.
    #[error(transparent)]
    Subspace(#[from] RefError),
}
