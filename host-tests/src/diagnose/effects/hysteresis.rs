//! An element with memory on a static model: the play operator and the relay with borders on
//! the static model's knots, each fitted with `G` by simulation error from the static
//! estimate.
//!
//! The element's fit refits `G` by simulation error as well, so its inner hold-out gain over
//! the current model can come from the refit of `G` alone, with borders that barely differ:
//! a static plant whose current fit is poor on the inner hold-out would then be named
//! hysteretic. The gain must be the memory's: the fitted element is scored again with its
//! two borders collapsed onto their mean (the same `G`, the same static curve, no memory),
//! and the element is proposed only if it beats that collapse significantly (one-sided
//! Diebold–Mariano at the catalog's level). The size of the gain is still judged against the
//! current model (`effects::choose`); a real element whose fit also improves `G` keeps the
//! whole gain.

use super::candidate::Candidate;
use super::catalog::Effect;
use super::proposal::Proposal;
use crate::diagnose::error::DiagnoseError;
use crate::diagnose::model::{Dynamics, Metric};
use crate::model::MemoryElement;

impl Proposal<'_> {
    /// The play operator (backlash), then the relay with borders (switch), on a static model
    /// without stores and without an output map other than the output saturation alone (the
    /// element's fit holds `G` and the borders, and the clamp at the pinned levels); on an
    /// output pinned at a level, each first with the output saturation. `None` when the
    /// element's memory does not carry its gain (see the module doc).
    pub fn hysteresis(&self) -> Result<Option<Candidate>, DiagnoseError> {
        let c = self.current;
        let saturation_only = c.output_map_segments == Some(1)
            && (self.holdout.opts.saturation.any() || c.end_stop.is_some());
        let plain = (c.output_map_segments.is_none() || saturation_only)
            && c.dynamics == Dynamics::Linear
            && !c.play_between;
        if !self.holdout.opts.identify.static_nonlinearity || !plain {
            return Ok(None);
        }
        // On an output pinned at a level, each element first through the output saturation
        // (its simulation clamped there, `G` and the borders fitted through the clamp; no
        // parameter more, the levels are the data check's): the pinned samples would
        // otherwise pull the element's fit. Without the clamp it is kept only if it scores
        // better.
        let clamps: &[bool] = if self.holdout.opts.saturation.any() && !saturation_only {
            &[true, false]
        } else {
            &[false]
        };
        let mut opts = Vec::new();
        for (label, kind) in [
            ("play operator (backlash)", MemoryElement::Play),
            ("relay with borders (switch)", MemoryElement::Relay),
        ] {
            for &clamp in clamps {
                let label = if clamp {
                    format!("{label} with the output saturation")
                } else {
                    label.to_string()
                };
                opts.push((
                    label,
                    self.with(|s| {
                        s.element = Some(kind);
                        if clamp {
                            s.output_map_segments = Some(1);
                        }
                    }),
                ));
            }
        }
        let cand = self.best_of(Effect::Hysteresis, opts, Metric::Simulation)?;
        Ok(cand.filter(|c| self.memory_carries_gain(c)))
    }

    /// Whether the candidate's element beats its own memoryless collapse on the first fold's
    /// block significantly (see the module doc).
    fn memory_carries_gain(&self, cand: &Candidate) -> bool {
        let mut collapsed = cand.inner_model.clone();
        let Some(ch) = collapsed.hysteresis.as_mut() else {
            return true;
        };
        for (a, d) in ch.border_asc.iter_mut().zip(ch.border_desc.iter_mut()) {
            let mid = 0.5 * (*a + *d);
            (*a, *d) = (mid, mid);
        }
        self.beats_on_block(&cand.inner_model, &collapsed)
    }
}
