//! Output nonlinearity: a monotone piecewise-linear output map with 3, 5 or 8 segments.

use super::candidate::Candidate;
use super::catalog::Effect;
use super::proposal::Proposal;
use crate::diagnose::error::DiagnoseError;
use crate::diagnose::model::Metric;

impl Proposal<'_> {
    /// Output maps of 3, 5 and 8 segments.
    pub fn output_nonlinearity(&self) -> Result<Option<Candidate>, DiagnoseError> {
        let effect = Effect::OutputNonlinearity;
        let opts = [3usize, 5, 8]
            .into_iter()
            .map(|k| {
                (
                    format!("{k} segments"),
                    self.with(|s| s.output_map_segments = Some(k)),
                )
            })
            .collect();
        self.best_of(effect, opts, Metric::Simulation)
    }
}
