//! An element with memory on a static model: the play operator and the relay with borders on
//! the static model's knots, each fitted with `G` by simulation error from the static
//! estimate.

use super::candidate::Candidate;
use super::catalog::Effect;
use super::proposal::Proposal;
use crate::diagnose::error::DiagnoseError;
use crate::diagnose::model::{Dynamics, Metric};
use crate::hysteresis::ElementKind;

impl Proposal<'_> {
    /// The play operator (backlash), then the relay with borders (switch), on a static model
    /// without an output map or stores (the element's fit holds `G` and the borders alone).
    pub fn hysteresis(&self) -> Result<Option<Candidate>, DiagnoseError> {
        let c = self.current;
        let plain = c.output_map_segments.is_none() && c.dynamics == Dynamics::Linear;
        if !self.holdout.opts.identify.static_nonlinearity || !plain {
            return Ok(None);
        }
        let opts = [
            ("play operator (backlash)", ElementKind::Backlash),
            ("relay with borders (switch)", ElementKind::Switch),
        ]
        .into_iter()
        .map(|(label, kind)| (label.to_string(), self.with(|s| s.element = Some(kind))))
        .collect();
        self.best_of(Effect::Hysteresis, opts, Metric::Simulation)
    }
}
