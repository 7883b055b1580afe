//! The inner hold-out of the estimation record: each candidate model is refitted on the first
//! [`FIT_FRACTION`] of the record, from its estimate on the whole record, and simulated
//! through to the end; its score is the simulation NRMSE on the rest, which no refit saw.
//!
//! A prediction-error fit is refitted with its order, knots, feed-through and noise-model
//! order kept (the model scored is the kind of model reported: a Box–Jenkins fit's plant is
//! the one that predicts best with its noise model, an output-error fit's the one that
//! simulates best), and simulated with its initial state and borders as refitted
//! ([`simulate_fit`]). An element fitted by simulation error is
//! refitted with the held-out samples left out of its error ([`fit_hysteresis_skipping`]),
//! the whole input driving the element's state.

use crate::hysteresis::{ElementFitOptions, HysteresisError, Start, fit_hysteresis_skipping};
use crate::identify::{HostModel, IdentifyOptions};
use crate::refine::RefineError;
use crate::refine::pem::{Feedthrough, NoiseOrder, PemFit, PemOptions, refine, simulate_fit};
use crate::report;

/// Why a candidate has no hold-out score.
#[derive(Debug, thiserror::Error)]
pub enum HoldOutError {
    /// The prediction-error refit or its simulation failed.
    #[error("the hold-out refit failed: {0}")]
    Refine(#[from] RefineError),
    /// The element's refit failed.
    #[error("the element's hold-out refit failed: {0}")]
    Element(#[from] HysteresisError),
    /// The held-out output does not vary: no NRMSE.
    #[error("the held-out output is constant")]
    Constant,
}

/// The share of the record (after its start) the candidates are refitted on.
pub const FIT_FRACTION: f64 = 0.75;

/// Where the hold-out starts in a record of `len` samples whose fit starts at `start`.
pub fn holdout_start(len: usize, start: usize) -> usize {
    let used = len.saturating_sub(start) as f64;
    start + (FIT_FRACTION * used).round() as usize
}

/// `‖y − ŷ‖ / ‖y − ȳ‖` ([`report::fit`]); `None` where it is undefined (a constant or empty
/// `y`).
pub fn nrmse(y: &[f64], y_hat: &[f64]) -> Option<f64> {
    Some(report::fit(y, y_hat).nrmse).filter(|v| v.is_finite())
}

/// The hold-out NRMSE of a prediction-error fit on `(u, y)` (`opts`: its identification
/// options, for the start and initial state).
pub fn pem_holdout(
    u: &[f64],
    y: &[f64],
    fit: &PemFit,
    opts: &IdentifyOptions,
) -> Result<f64, HoldOutError> {
    let k = holdout_start(u.len(), fit.start);
    let pem = PemOptions {
        noise_order: NoiseOrder::Fixed(fit.layout.nv),
        feedthrough: match fit.layout.feedthrough {
            true => Feedthrough::Free,
            false => Feedthrough::Zero,
        },
        ..PemOptions::for_identify(opts)
    };
    let part = refine(&u[..k], &y[..k], &fit.model, &pem)?;
    let sim = simulate_fit(u, y, &part)?;
    let from = k - part.start;
    nrmse(&y[k..], sim.get(from..).unwrap_or(&[])).ok_or(HoldOutError::Constant)
}

/// The hold-out NRMSE of the element fitted by simulation error from `init` (`start`: which
/// estimate `init` is) with `opts`.
pub fn element_holdout(
    u: &[f64],
    y: &[f64],
    init: &HostModel,
    start: Start,
    opts: &ElementFitOptions,
) -> Result<f64, HoldOutError> {
    let k = holdout_start(u.len(), 0);
    let skip: Vec<bool> = (0..u.len()).map(|t| t >= k).collect();
    let fit = fit_hysteresis_skipping(u, y, &skip, init, start, opts)?;
    let sim = fit.simulate(u);
    nrmse(&y[k..], &sim[k..]).ok_or(HoldOutError::Constant)
}
