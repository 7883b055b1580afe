//! Friction on a model's velocity: Coulomb friction and an offset on the output's change,
//! fed back into `G`'s input, fitted with `G` by simulation error from the current model
//! ([`crate::friction`]).
//!
//! Proposed only where its own evidence is: the sign of the current model's simulated
//! velocity, put beside the terms of its output-error equation, explains the output beyond
//! `|t| = 3` ([`friction_evidence`]). The residual tests the other effects answer to
//! (direction dependence, whiteness) fire for many causes; this one asks the question
//! friction answers.

use super::candidate::Candidate;
use super::catalog::Effect;
use super::proposal::Proposal;
use crate::diagnose::error::DiagnoseError;
use crate::diagnose::findings::friction_evidence;
use crate::diagnose::model::{Dynamics, Metric};
use crate::friction::VelocitySign;

impl Proposal<'_> {
    /// Friction on a model without an element with memory, stores or an output map (the
    /// friction model simulates the element and `G` alone), of a plant's output (not of an
    /// integrating plant's increments, whose model is not a position's), when the direction
    /// of the model's simulated motion explains its equation error ([`friction_evidence`] on
    /// the estimation record). The output may be a position, whose change is the velocity, or
    /// a speed (a motor's), the velocity itself: each reading whose evidence fires is tried
    /// and the better on the hold-out kept, among the fits whose Coulomb level opposes the
    /// motion (`F_c > 0`).
    pub fn friction(&self) -> Result<Option<Candidate>, DiagnoseError> {
        let c = self.current;
        let plain = c.element.is_none()
            && c.output_map_segments.is_none()
            && c.dynamics == Dynamics::Linear
            && !c.friction
            && !c.play_between
            && !self.increments;
        if !plain {
            return Ok(None);
        }
        let readings = [
            (
                false,
                "Coulomb friction and an offset on the output's change (a position's velocity)",
            ),
            (
                true,
                "Coulomb friction and an offset on the output's sign (the output a speed)",
            ),
        ];
        // Each reading scored on its own: one whose force helps the motion along (a negative
        // Coulomb level, a feedback of the output's sign that is no friction) or is too small
        // to matter (under the evidence's 2 % of the element's output's spread: an offset and
        // a delay in friction's clothes) is not friction and does not stand in for the other.
        let mut best: Option<Candidate> = None;
        let mut tried = Vec::new();
        for (speed, label) in readings {
            if !self.moves_by_direction(speed) {
                continue;
            }
            let structure = self.with(|s| {
                s.friction = true;
                s.friction_on_speed = speed;
            });
            let opts = vec![(label.to_string(), structure)];
            let Some(c) = self.best_of(Effect::Friction, opts, Metric::Simulation)? else {
                continue;
            };
            tried.extend(c.tried.iter().cloned());
            let opposes = c.inner_model.friction.as_ref().is_some_and(|f| {
                // The element's output's spread on the estimation record, in the units of the
                // fitted model's force (its element scaled with `G(1) = 1`).
                let est = self.holdout.est;
                let h = f.plant.element_output_from(&est.u, f.plant.u_min());
                let spread = crate::validation::stats::variance(&h).sqrt();
                f.friction.coulomb >= VelocitySign::MIN_FORCE_SHARE * spread
            });
            if opposes
                && best
                    .as_ref()
                    .is_none_or(|b| c.evaluation.rmse < b.evaluation.rmse)
            {
                best = Some(c);
            }
        }
        Ok(best.map(|c| Candidate { tried, ..c }))
    }

    /// Whether the current model's output-error equation on the estimation record depends on
    /// the sign of its simulated velocity ([`friction_evidence`]): the simulated output itself
    /// when `speed`, else its change.
    fn moves_by_direction(&self, speed: bool) -> bool {
        let est = self.holdout.est;
        friction_evidence(self.inner_model, est, est.hold, speed).is_some()
    }
}
