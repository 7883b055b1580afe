//! The three kinds of fits of a diagnosis and their options: the inner hold-out fits that
//! choose the effects, the models reported, and the paper's estimate alone.

use super::model::{FitOptions, InitialState};
use super::options::{DiagnoseOptions, PoleRefinement};
use crate::identify::IdentifyOptions;
use crate::model::Record;
use crate::validation::checks;

/// Fit options of one diagnosis.
#[derive(Clone, Debug)]
pub(crate) struct FitPlan {
    /// The inner hold-out fits (poles refined only with [`PoleRefinement::Always`]).
    pub inner: FitOptions,
    /// The models reported: the base model and the model after each step.
    pub reported: FitOptions,
    /// The paper's estimate alone: subspace, borders from the rank-1 split, no refit.
    pub paper: FitOptions,
}

impl FitPlan {
    /// The options for identification options `id` (knots chosen) on the estimation record.
    pub fn new(opts: &DiagnoseOptions, id: &IdentifyOptions, est: &Record) -> Self {
        let (tmin, tmax) = est
            .time
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &t| {
                (a.min(t), b.max(t))
            });
        let inner = FitOptions {
            initial: opts.initial.unwrap_or(if id.hold > 0 {
                InitialState::Rest
            } else {
                InitialState::Estimated
            }),
            identify: id.clone(),
            time_center: 0.5 * (tmin + tmax),
            time_scale: 0.5 * (tmax - tmin),
            outlier_k: opts.outlier_k,
            rounds: 3,
            refit: true,
            refine_poles: opts.refine_poles == PoleRefinement::Always,
            saturation: checks::saturation(&est.y),
        };
        let reported = FitOptions {
            refine_poles: opts.refine_poles != PoleRefinement::Never,
            ..inner.clone()
        };
        let paper = FitOptions {
            refit: false,
            refine_poles: false,
            ..inner.clone()
        };
        Self {
            inner,
            reported,
            paper,
        }
    }
}
