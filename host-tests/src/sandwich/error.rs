//! Why the two-mass model could not be fitted.

use crate::numerics::lm::LmFailure;

/// Why [`fit_two_mass`](super::fit_two_mass) gave no model.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SandwichError {
    /// `u` and `y` differ in length.
    #[error("u has {u} samples but y has {y}: give one y per u")]
    LengthMismatch {
        /// Samples of `u`.
        u: usize,
        /// Samples of `y`.
        y: usize,
    },
    /// Fewer samples than a few per parameter.
    #[error("too few samples for the two-mass model: {have} given, at least {need} needed")]
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
    /// The output does not move, or the input does not.
    #[error("the {0} does not change: nothing to fit a two-mass model to")]
    Constant(&'static str),
    /// Integration steps per sample must be at least one.
    #[error("the simulation needs at least one integration step per sample")]
    NoSubsteps,
    /// No start simulated the record.
    #[error(
        "no start of the two-mass model simulates the record (the current model's poles give no admissible start)"
    )]
    NoStart,
    /// The minimisation failed from every start.
    #[error("the two-mass fit: {0}")]
    Minimise(#[from] LmFailure),
}
