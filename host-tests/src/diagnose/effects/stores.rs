//! State-dependent dynamics: level-dependent stores, scored against the same stores with
//! linear outflows.

use super::candidate::Candidate;
use super::candidate::compare;
use super::catalog::Effect;
use super::proposal::Proposal;
use crate::diagnose::error::DiagnoseError;
use crate::diagnose::evidence::Tried;
use crate::diagnose::model::{Dynamics, Metric};

impl Proposal<'_> {
    /// The level-dependent stores (with the output map reduced, if any), against linear stores.
    pub fn state_dependent_dynamics(&self) -> Result<Option<Candidate>, DiagnoseError> {
        let effect = Effect::StateDependentDynamics;
        // The element with memory is fitted with the linear `G`.
        if self.current.element.is_some() {
            return Ok(None);
        }
        // With stores the steady-state curve bends by itself: the output map, if
        // any, is also tried reduced to its affine part and clip.
        let mut opts = Vec::new();
        if self.current.output_map_segments.is_some_and(|k| k > 1) {
            opts.push((
                "stores, output map reduced to 1 segment".to_string(),
                self.with(|s| {
                    s.dynamics = Dynamics::Stores;
                    s.output_map_segments = Some(1);
                }),
            ));
        }
        opts.push((
            "stores".to_string(),
            self.with(|s| s.dynamics = Dynamics::Stores),
        ));
        let Some(mut c) = self.best_of(effect, opts, Metric::Simulation)? else {
            return Ok(None);
        };
        // The level dependence must beat the same stores with linear outflows and
        // no overflow (the linear cascade refitted the same way, borders included):
        // otherwise the gain is the refit's, not the state dependence's. The
        // candidate keeps the smaller gain and the larger p-value of the two
        // comparisons.
        let mut reference = c.structure.clone();
        reference.dynamics = Dynamics::LinearStores;
        match self.holdout.score(&reference, Metric::Simulation) {
            Ok(Some((_, ev))) if ev.rmse.is_finite() => {
                let (gain, p_value) = compare(&ev, &c.evaluation);
                c.tried.push(Tried::LinearStores(Some(ev.rmse)));
                c.gain = c.gain.min(gain);
                c.p_value = c.p_value.max(p_value);
            }
            Ok(_) | Err(DiagnoseError::Identify(_) | DiagnoseError::Dynamics(_)) => {
                c.tried.push(Tried::LinearStores(None));
            }
            Err(e) => return Err(e),
        }
        Ok(Some(c))
    }
}
