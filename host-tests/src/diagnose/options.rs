//! The diagnosis's settings: the nonlinearity kind, where the validation data come from, and
//! the options of the loop.

use std::ops::Range;

use serde::Serialize;

use super::model::InitialState;
use crate::identify::IdentifyOptions;
use crate::model::Element;
use crate::model::Record;

/// Where the validation data come from.
#[derive(Clone, Debug, PartialEq)]
pub enum Validation {
    /// A separate record, simulated from its own start; the first `skip` samples (its hold)
    /// are not scored.
    Separate {
        /// The record.
        record: Record,
        /// Samples not scored.
        skip: usize,
    },
    /// The record is split: the first `fraction` of the samples after the hold estimate, the
    /// rest validates (simulated from the start of the record, input only).
    Split(f64),
    /// A held-out range of the record validates; the rest (concatenated) estimates.
    Holdout(Range<usize>),
}

/// Diagnosis settings.
#[derive(Clone, Debug, PartialEq)]
pub struct DiagnoseOptions {
    /// Base identification options (knots, horizons, order, hold, μ0, static).
    pub identify: IdentifyOptions,
    /// Element kind (static sets `identify.static_nonlinearity`).
    pub nonlinearity: Element,
    /// Initial state of simulations (`None`: at rest with a hold, estimated without).
    pub initial: Option<InitialState>,
    /// Most effects added.
    pub max_steps: usize,
    /// Least relative reduction of the inner hold-out MSE for an effect to be added.
    pub min_gain: f64,
    /// Gains within this of the best count as ties (the simplest extension wins).
    pub tie: f64,
    /// Largest input delay tried (samples).
    pub max_delay: usize,
    /// Fraction of the estimation samples (after the hold) that fit in the inner hold-out.
    pub inner_fraction: f64,
    /// MAD rule threshold for outliers (robust standard deviations).
    pub outlier_k: f64,
    /// Where the poles are refined by the simulation error after the subspace step (see
    /// [`FitOptions::refine_poles`](super::model::FitOptions::refine_poles)).
    pub refine_poles: PoleRefinement,
    /// Choose the number of uniform segments per path in this range by the BIC of the
    /// estimation simulation error (the knots given are then replaced).
    pub select_segments: Option<std::ops::RangeInclusive<usize>>,
    /// Which effects a step proposes.
    pub proposing: Proposing,
}

/// Which deterministic effects a step of the diagnosis fits and scores.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Proposing {
    /// Those whose residual test fires on the estimation residual (and an output
    /// nonlinearity on an output the data checks find pinned at an extreme).
    WithEvidence,
    /// Every one, with or without evidence: a measurement of what the estimation data can
    /// show at all (what the inner hold-out gives the true effect where no test fires), at
    /// the cost of fitting every effect at every step. The step rule is the same.
    Every,
}

/// Where [`FitOptions::refine_poles`](super::model::FitOptions::refine_poles) is used.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum PoleRefinement {
    /// Never: every model is the subspace estimate with its borders, `B` and `D` refit.
    Never,
    /// In the models reported (the base model and the model after each step), not in the
    /// inner hold-out fits that choose the effects (they are many) — unless the base model
    /// fitted that way without the hold-out blocks simulates them worse than the minimum gain
    /// allows ([`inner::weak`](crate::diagnose::inner::weak)), or not within 3 × the in-sample
    /// error: then in those too.
    Final,
    /// In every fit.
    Always,
}

impl DiagnoseOptions {
    /// Defaults around the given identification options.
    pub fn new(identify: IdentifyOptions, nonlinearity: Element) -> Self {
        Self {
            identify,
            nonlinearity,
            initial: None,
            max_steps: 4,
            min_gain: 0.20,
            tie: 0.03,
            max_delay: 10,
            inner_fraction: 0.7,
            outlier_k: 5.0,
            refine_poles: PoleRefinement::Final,
            select_segments: None,
            proposing: Proposing::WithEvidence,
        }
    }
}
