//! The outcome of a diagnosis: the effects added step by step, those rejected, what stays
//! unexplained, and the models and tests before and after.

use crate::model::Element;
use std::ops::Range;

use serde::Serialize;

use super::delay;
use super::effects::{Effect, Significance};
use super::evidence::{Evidence, Tried};
use super::findings::Finding;
use super::inner::InnerValidation;
use super::model::{Evaluation, ExtendedModel, Metric};
use super::verdict::Verdict;
use crate::model::Record;
use crate::validation::checks::{CHECKS, Check, Warning};
use crate::validation::residual::TestSet;

/// One effect added.
#[derive(Clone, Debug)]
pub struct Step {
    /// The effect.
    pub effect: Effect,
    /// The tests that pointed at it, with their findings.
    pub evidence: Vec<Evidence>,
    /// Its setting.
    pub setting: String,
    /// Relative reduction of the inner hold-out MSE.
    pub inner_gain: f64,
    /// p-value of that reduction (by `inner_test`).
    pub inner_p: f64,
    /// The test behind `inner_p`.
    pub inner_test: Significance,
    /// Settings tried with their inner hold-out RMSE.
    pub tried: Vec<Tried>,
    /// Other effects evaluated at this step: `(effect, gain, p)`.
    pub competitors: Vec<(Effect, f64, f64)>,
    /// Metric of the errors below.
    pub metric: Metric,
    /// Validation error of the model before this step (same metric; outliers of the new
    /// model excluded when it is robust).
    pub error_before: f64,
    /// Validation error after this step, output units.
    pub error_after: f64,
    /// One-sided p-value that the step raised the validation error: a paired Diebold–Mariano
    /// test of the squared errors after against before, on the samples neither model
    /// excludes. A raise with a large p-value is within the validation record's noise.
    pub p_worse: f64,
    /// NRMSE after.
    pub nrmse_after: f64,
    /// Fit % after.
    pub fit_after: f64,
    /// Validation samples excluded as outliers after this step.
    pub excluded: usize,
    /// The model after this step.
    pub model: ExtendedModel,
}

/// An effect with evidence that was not added.
#[derive(Clone, Debug, Serialize)]
pub struct Rejected {
    /// The effect.
    pub effect: Effect,
    /// Tests that pointed at it.
    pub evidence: Vec<Evidence>,
    /// Relative inner hold-out MSE reduction of its extension.
    pub inner_gain: f64,
    /// Its p-value (by `inner_test`).
    pub inner_p: f64,
    /// The test behind `inner_p`.
    pub inner_test: Significance,
}

/// The outcome of [`diagnose`](super::diagnose).
#[derive(Clone, Debug)]
pub struct Diagnosis {
    /// Element kind.
    pub nonlinearity: Element,
    /// How estimation and validation data were formed.
    pub data_description: String,
    /// Estimation samples.
    pub estimation_samples: usize,
    /// Validation samples scored.
    pub validation_samples: usize,
    /// Data checks.
    pub warnings: Vec<Warning>,
    /// The paper's model.
    pub base: ExtendedModel,
    /// The model with every effect added.
    pub model: ExtendedModel,
    /// Effects added, in order.
    pub steps: Vec<Step>,
    /// Effects with evidence that were not added at the last step.
    pub rejected: Vec<Rejected>,
    /// Tests that still fire on the final estimation residual and that no catalog effect
    /// explained.
    pub unexplained: Vec<Finding>,
    /// One-paragraph conclusion.
    pub verdict: Verdict,
    /// Validation simulation of the paper's estimate alone (subspace identification, borders
    /// from the rank-1 split, no least-squares refit), when it could be computed.
    pub paper: Option<Evaluation>,
    /// Validation simulation of the base model (the paper's structure, borders, `B`, `D` and
    /// poles refit on the estimation data): the error before.
    pub before: Evaluation,
    /// The estimator of the Hammerstein part of the base model and of every refit.
    pub estimator: super::model::Estimator,
    /// Whether the reported models have their poles refined.
    pub poles_refined: bool,
    /// Validation simulation of the final model.
    pub after: Evaluation,
    /// Validation one-step prediction of the final model (with a noise model).
    pub after_prediction: Option<Evaluation>,
    /// Tests on the validation residual of the paper's model.
    pub tests_before: TestSet,
    /// Tests on the final validation residual (prediction residual with a noise model).
    pub tests_after: TestSet,
    /// Tests on the estimation residual (simulation) of the last deterministic model: what the
    /// decisions saw last.
    pub tests_estimation: TestSet,
    /// The record the validation simulation runs over.
    pub validation_record: Record,
    /// Its scored samples.
    pub validation_range: Range<usize>,
    /// The inner validation that chose every setting and effect.
    pub inner: InnerValidation,
    /// The dead time of the estimation data (ARX test), against the base model's.
    pub dead_time: delay::DeadTime,
}

impl Diagnosis {
    /// The data checks that ran, in order: [`CHECKS`], and the order check when it lowered
    /// the declared order (it runs on a declared order alone).
    pub fn checks_ran(&self) -> Vec<Check> {
        let mut ran = CHECKS.to_vec();
        if self.warnings.iter().any(|w| w.check == Check::Order) {
            ran.push(Check::Order);
        }
        ran
    }
}
