//! The diagnosis's settings: the nonlinearity kind, where the validation data come from, and
//! the options of the loop.

use std::ops::Range;

use serde::Serialize;

use super::DiagnoseError;
use super::model::InitialState;
use crate::identify::{IdentifyOptions, MAX_CHANNELS, max_segments};
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
    /// The record is an integrating plant's increments (`hsid diagnose --integrating`): the
    /// model's output is then the plant's velocity, which the friction finding
    /// ([`Finding::Friction`](super::Finding::Friction)) takes the sign of.
    pub increments: bool,
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

/// The largest extra input delay the diagnosis tries, in samples: each delay is a refit of
/// the model, and the cost grows faster than the delay (50 takes about a minute on a record of
/// 6,000 samples).
pub const MAX_DELAY: usize = 50;

/// The most effects a diagnosis adds.
pub const MAX_STEPS: usize = 16;

impl DiagnoseOptions {
    /// Checks the settings before any work: the delay, the steps, the segment range, the
    /// fractions and thresholds (finite, in range).
    pub fn check(&self) -> Result<(), DiagnoseError> {
        let setting =
            |name, value: String, why: String| Err(DiagnoseError::Setting { name, value, why });
        if self.max_delay > MAX_DELAY {
            return setting(
                "max_delay",
                self.max_delay.to_string(),
                format!("at most {MAX_DELAY} samples are tried (each is a refit of the model)"),
            );
        }
        if self.max_steps > MAX_STEPS {
            return setting(
                "max_steps",
                self.max_steps.to_string(),
                format!("at most {MAX_STEPS} effects are added"),
            );
        }
        let shared = self.nonlinearity == Element::Static;
        let most = max_segments(shared);
        let mut id = self.identify.clone();
        id.static_nonlinearity = shared;
        if shared {
            id.knots_desc = id.knots_asc.clone();
        }
        if id.channels() > MAX_CHANNELS {
            return setting(
                "segments",
                id.knots_asc.len().saturating_sub(1).to_string(),
                format!(
                    "at most {most} segments per path fit the largest capacity of \
                     {MAX_CHANNELS} channels (the diagnosis keeps the segments it is given)"
                ),
            );
        }
        if let Some(r) = &self.select_segments
            && (*r.start() < 1 || r.start() > r.end() || *r.end() > most)
        {
            return setting(
                "select_segments",
                format!("{}..{}", r.start(), r.end()),
                format!("need 1 <= MIN <= MAX <= {most} segments per path (the largest capacity)"),
            );
        }
        for (name, value, ok, why) in [
            (
                "min_gain",
                self.min_gain,
                (0.0..1.0).contains(&self.min_gain),
                "a relative reduction in [0, 1)",
            ),
            (
                "tie",
                self.tie,
                (0.0..1.0).contains(&self.tie),
                "a relative difference in [0, 1)",
            ),
            (
                "inner_fraction",
                self.inner_fraction,
                self.inner_fraction > 0.0 && self.inner_fraction < 1.0,
                "a fraction strictly between 0 and 1",
            ),
            (
                "outlier_k",
                self.outlier_k,
                self.outlier_k.is_finite() && self.outlier_k > 0.0,
                "a positive, finite number of robust standard deviations",
            ),
        ] {
            if !ok {
                return setting(name, value.to_string(), why.to_string());
            }
        }
        Ok(())
    }

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
            increments: false,
        }
    }
}
