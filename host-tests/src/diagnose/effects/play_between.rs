//! Play between two dynamic parts: the two-mass drive of [`crate::sandwich`] in place of `G`
//! and any input element, fitted by simulation error from `G`'s poles.
//!
//! Proposed on the evidence of a deterministic error that depends on the direction of motion
//! (direction dependence, or a residual that is not white), on a model of order at most
//! [`MAX_ORDER`] (the two-mass drive replaces a `G` with a rigid-body mode and a shaft
//! resonance). The two-mass drive with the teeth always in contact is a third-order linear
//! model: on a plant whose order the current model lacks, its gain would come from the order
//! alone. So the gain must be the play's, as an element's must be its memory's
//! ([`super::hysteresis`]): the fitted drive is scored again with its play closed (the same
//! parameters, `α = 0`), and the step is proposed only if the play beats its closure
//! significantly (one-sided Diebold–Mariano at the catalog's level).

use super::candidate::Candidate;
use super::catalog::Effect;
use super::proposal::Proposal;
use crate::diagnose::error::DiagnoseError;
use crate::diagnose::model::{Dynamics, Metric};

/// The largest order of the current model the two-mass drive replaces.
pub const MAX_ORDER: usize = 3;

impl Proposal<'_> {
    /// The two-mass drive with play, on a model of a plant's output (not an integrating
    /// plant's increments) of order at most [`MAX_ORDER`], without stores, an output map or
    /// friction; `None` when the play does not carry its gain (see the module doc).
    pub fn play_between(&self) -> Result<Option<Candidate>, DiagnoseError> {
        let c = self.current;
        let plain = c.output_map_segments.is_none()
            && c.dynamics == Dynamics::Linear
            && !c.friction
            && !c.play_between
            && !self.increments
            && self.order <= MAX_ORDER;
        if !plain {
            return Ok(None);
        }
        let opts = vec![(
            "two-mass drive with play between motor and load".to_string(),
            self.with(|s| {
                s.play_between = true;
                s.element = None;
            }),
        )];
        let cand = self.best_of(Effect::PlayBetween, opts, Metric::Simulation)?;
        Ok(cand.filter(|c| self.play_carries_gain(c)))
    }

    /// Whether the candidate's drive beats its own closed play on the first fold's block
    /// significantly (see the module doc).
    fn play_carries_gain(&self, cand: &Candidate) -> bool {
        let mut closed = cand.inner_model.clone();
        let Some(tm) = closed.two_mass.as_mut() else {
            return false;
        };
        tm.model.half_width = 0.0;
        self.beats_on_block(&cand.inner_model, &closed)
    }
}
