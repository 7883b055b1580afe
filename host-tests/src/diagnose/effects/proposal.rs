//! The proposal of an effect's extension: the settings of each effect (one file per effect)
//! scored on the inner validation, the simplest of the best kept.

use super::candidate::{Candidate, Significance, compare};
use super::catalog::Effect;
use super::holdout::Holdout;
use crate::diagnose::error::DiagnoseError;
use crate::diagnose::evidence::{Tried, Unscored};
use crate::diagnose::model::{Evaluation, ExtendedModel, Metric, Structure, evaluate};
use crate::validation::residual::LEVEL;
use crate::validation::residual::TestSet;

/// What a proposal needs.
pub struct Proposal<'a> {
    /// The inner hold-out.
    pub holdout: &'a Holdout<'a>,
    /// The current structure.
    pub current: &'a Structure,
    /// Its inner hold-out evaluation (simulation).
    pub baseline: &'a Evaluation,
    /// The current structure fitted on the inner hold-out's fitting part.
    pub inner_model: &'a ExtendedModel,
    /// Order of the current model.
    pub order: usize,
    /// Future horizon (orders stay below it).
    pub f: usize,
    /// Largest delay tried.
    pub max_delay: usize,
    /// The least relative MSE reduction a step needs ([`DiagnoseOptions::min_gain`](crate::diagnose::DiagnoseOptions::min_gain)).
    pub min_gain: f64,
    /// In-sample residual of the current model on the estimation record (after the hold).
    pub residual: &'a [f64],
    /// Input over the same samples.
    pub input: &'a [f64],
    /// The current model's tests on that residual.
    pub tests: &'a TestSet,
    /// The record holds an integrating plant's increments
    /// ([`DiagnoseOptions::increments`](crate::diagnose::DiagnoseOptions::increments)).
    pub increments: bool,
    /// Every effect is proposed, with or without its evidence
    /// ([`Proposing::Every`](crate::diagnose::Proposing::Every)).
    pub every: bool,
}

impl Proposal<'_> {
    /// The current structure changed by `f`.
    pub fn with(&self, f: impl Fn(&mut Structure)) -> Structure {
        let mut s = self.current.clone();
        f(&mut s);
        s
    }

    /// Scores every setting (given in increasing complexity) on the inner hold-out and keeps
    /// the simplest whose RMSE is within 0.5 % of the best.
    pub(crate) fn best_of(
        &self,
        effect: Effect,
        options: Vec<(String, Structure)>,
        metric: Metric,
    ) -> Result<Option<Candidate>, DiagnoseError> {
        let mut scored: Vec<(Structure, ExtendedModel, Evaluation)> = Vec::new();
        let mut tried = Vec::new();
        // The settings are independent: scored across the cores, kept in their order.
        let scores = crate::progress::map(&options, |_, (_, s)| self.holdout.score(s, metric));
        for ((label, s), score) in options.into_iter().zip(scores) {
            let (m, ev) = match score {
                Ok(Some(v)) => v,
                Ok(None) => {
                    tried.push(Tried::Unscored {
                        label,
                        why: Unscored::TooSlow,
                    });
                    continue;
                }
                Err(DiagnoseError::Identify(e)) => {
                    tried.push(Tried::Unscored {
                        label,
                        why: Unscored::Identify(e),
                    });
                    continue;
                }
                Err(DiagnoseError::Dynamics(e)) => {
                    tried.push(Tried::Unscored {
                        label,
                        why: Unscored::Dynamics(e),
                    });
                    continue;
                }
                Err(e) => return Err(e),
            };
            tried.push(Tried::Scored {
                label,
                rmse: ev.rmse,
            });
            if ev.rmse.is_finite() {
                scored.push((s, m, ev));
            }
        }
        let best = scored
            .iter()
            .map(|(_, _, e)| e.rmse)
            .fold(f64::INFINITY, f64::min);
        let Some((s, m, ev)) = scored.into_iter().find(|(_, _, e)| e.rmse <= best * 1.005) else {
            return Ok(None);
        };
        let (gain, p_value) = compare(self.baseline, &ev);
        Ok(Some(Candidate {
            effect,
            complexity: effect.complexity(&s, self.order),
            structure: s,
            inner_model: m,
            evaluation: ev,
            gain,
            p_value,
            significance: Significance::DieboldMariano,
            tried,
        }))
    }

    /// Whether `with` simulates the first fold's block significantly better than `without`
    /// (one-sided Diebold–Mariano at the catalog's level): an extension's own part against
    /// the same model with that part taken out (an element's memory, a play).
    pub(crate) fn beats_on_block(&self, with: &ExtendedModel, without: &ExtendedModel) -> bool {
        let (est, range) = (self.holdout.est, &self.holdout.range);
        let with = evaluate(with, est, range.clone(), Metric::Simulation);
        let without = evaluate(without, est, range.clone(), Metric::Simulation);
        compare(&without, &with).1 < LEVEL
    }

    /// Proposes the effect's extension with its best setting, or `None` when it has nothing
    /// to add (already in the model, no setting left, no fit).
    pub fn propose(&self, effect: Effect) -> Result<Option<Candidate>, DiagnoseError> {
        if effect.is_in(self.current) {
            return Ok(None);
        }
        match effect {
            Effect::InputDelay => self.input_delay(),
            Effect::UnmodeledDynamics => self.unmodeled_dynamics(),
            Effect::OffsetDrift => self.offset_drift(),
            Effect::OutputNonlinearity => self.output_nonlinearity(),
            Effect::PeriodicDisturbance => self.periodic_disturbance(),
            Effect::Outliers => self.outliers(),
            Effect::StateDependentDynamics => self.state_dependent_dynamics(),
            Effect::ColoredNoise => self.colored_noise(),
            Effect::Hysteresis => self.hysteresis(),
            Effect::Friction => self.friction(),
            Effect::PlayBetween => self.play_between(),
        }
    }
}
