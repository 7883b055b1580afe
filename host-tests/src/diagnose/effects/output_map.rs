//! Output nonlinearity: a monotone piecewise-linear output map with 3, 5 or 8 segments; on an
//! output the data checks find pinned at an extreme, first the output saturation alone (a
//! linear map with flat ends at the pinned levels). On a model with an element with memory,
//! only the output saturation: the element's simulation clamped at the pinned levels, `G` and
//! the borders refitted through the clamp (see [`element`](crate::diagnose::model::element)).

use super::candidate::Candidate;
use super::catalog::Effect;
use super::proposal::Proposal;
use crate::diagnose::error::DiagnoseError;
use crate::diagnose::model::Metric;

impl Proposal<'_> {
    /// Output maps of 3, 5 and 8 segments, after the one-segment saturation when the output
    /// sits at a saturation level (the map is clipped there in every setting). On a model with
    /// an element with memory, the saturation alone, and only when the output sits at a level.
    pub fn output_nonlinearity(&self) -> Result<Option<Candidate>, DiagnoseError> {
        let effect = Effect::OutputNonlinearity;
        let saturated = self.holdout.opts.saturation.any();
        let segments: &[usize] = match (self.current.element.is_some(), saturated) {
            (true, false) => return Ok(None),
            (true, true) => &[1],
            (false, true) => &[1, 3, 5, 8],
            (false, false) => &[3, 5, 8],
        };
        let opts = segments
            .iter()
            .map(|&k| {
                let label = if k == 1 {
                    "output saturation (linear, flat ends at the pinned levels)".to_string()
                } else {
                    format!("{k} segments")
                };
                (label, self.with(|s| s.output_map_segments = Some(k)))
            })
            .collect();
        self.best_of(effect, opts, Metric::Simulation)
    }
}
