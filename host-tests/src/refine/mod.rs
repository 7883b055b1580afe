//! Beyond the paper: the noise model, a prediction-error refinement, uncertainty and the knot
//! count.
//!
//! The subspace estimate of the core (PI-MOESP, eq. 11) is consistent but not efficient: it
//! ignores the colour of the noise and splits the over-parameterised `[D; B]` by a rank-1 SVD.
//! This module starts from it and goes as far as the data allow:
//!
//! * [`stochastic`]: the noise model of Remark 6. The residual of the simulated model is fitted
//!   by an ARMA model (Hannan–Rissanen), which gives the innovation form `(A, B, C, D, K)`,
//!   `σ_e²` and one-step-ahead predictions.
//! * [`bilinear`]: Remark 5, `B` and `μ` separately once `A` and `C` are known: alternating
//!   least squares on the whole record instead of the rank-1 split of eq. (14).
//! * [`pem`]: the prediction-error refinement of the whole structured model — the plant
//!   `G(q) = B(q)/F(q)` with `G(1) = 1`, `μ0`, the border values, the noise model
//!   `C(q)/D(q)` and optionally the initial state — by Levenberg–Marquardt with an analytic
//!   Jacobian. Asymptotically efficient when the noise model order is right.
//! * [`uncertainty`]: standard deviations of the poles, the Bode magnitude and the border
//!   values from the refinement's asymptotic covariance `σ_e² (JᵀJ)⁻¹`.
//! * [`knots`]: the knot count from the data (BIC of the refined model).
//!
//! The Cramér–Rao bound of the paper's example and the comparison of every method on the
//! paper's Monte Carlo are part of the paper's evaluation, [`crate::paper`].
//!
//! Everything here is host side (`std`, `f64`, `nalgebra`); the core is untouched.

use std::fmt;

pub mod bilinear;
pub mod knots;
pub mod pem;
pub mod poly;
pub mod signal;
pub mod stochastic;
pub mod uncertainty;

pub use pem::{PemFit, PemInitialState, PemOptions, identify_pem, refine};
pub use stochastic::NoiseOrder;
pub use stochastic::{InnovationForm, NoiseModel};

/// Which polynomial of the predictor lost stability.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Unstable {
    /// The plant denominator `F(q)`: the simulated output of `G` grows without bound.
    Plant,
    /// The noise numerator `C(q)`: the predictor filter `D(q)/C(q)` is unstable.
    Noise,
}

impl fmt::Display for Unstable {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Unstable::Plant => "plant denominator F(q)",
            Unstable::Noise => "noise numerator C(q) (predictor)",
        })
    }
}

/// Why a refinement, a noise-model fit or a bound could not be computed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum RefineError {
    /// The starting model (or the true system given for a bound) has an unstable predictor:
    /// a root of the named polynomial lies on or outside the unit circle.
    #[error("unstable predictor: the {which} has a root of modulus {radius:.6} (must be < 1)")]
    UnstablePredictor {
        /// The polynomial.
        which: Unstable,
        /// Largest root modulus.
        radius: f64,
    },
    /// The cost became non-finite or the parameters blew up.
    #[error("the prediction-error refinement diverged at iteration {iteration}")]
    Diverged {
        /// Iteration at which it happened.
        iteration: usize,
    },
    /// The iteration limit was reached before the convergence test passed.
    #[error(
        "the prediction-error refinement did not converge in {iterations} iterations (last relative decrease {last_decrease:.3e})"
    )]
    NoConvergence {
        /// Iterations done.
        iterations: usize,
        /// Relative cost decrease of the last accepted step.
        last_decrease: f64,
    },
    /// Too few samples for the number of parameters.
    #[error("too few samples: {have} given, at least {need} needed")]
    TooFewSamples {
        /// Samples available after the start index.
        have: usize,
        /// Samples needed.
        need: usize,
    },
    /// `u` and `y` differ in length.
    #[error("u has {u} samples but y has {y}: give one y per u")]
    LengthMismatch {
        /// Samples of `u`.
        u: usize,
        /// Samples of `y`.
        y: usize,
    },
    /// An input, output or parameter is not finite.
    #[error("non-finite input, output or parameter")]
    NonFinite,
    /// The model has order 0 or its matrices have inconsistent sizes.
    #[error("invalid model: {0}")]
    InvalidModel(&'static str),
    /// The normal equations are singular: the data do not determine every parameter.
    #[error("singular normal equations ({0}): the data do not determine every parameter")]
    Singular(&'static str),
    /// The knots are not strictly increasing from `u_min` to `u_max`, or an input lies outside.
    #[error("invalid knots: {0}")]
    InvalidKnots(&'static str),
    /// The subspace identification that starts a refinement failed.
    #[error("subspace identification failed: {0}")]
    Identify(String),
}

impl From<crate::identify::IdentifyError> for RefineError {
    fn from(e: crate::identify::IdentifyError) -> Self {
        RefineError::Identify(e.to_string())
    }
}
