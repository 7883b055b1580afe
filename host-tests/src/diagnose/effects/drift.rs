//! Offset or drift: a polynomial trend in time of degree 0 to 2.

use super::candidate::Candidate;
use super::catalog::Effect;
use super::proposal::Proposal;
use crate::diagnose::error::DiagnoseError;
use crate::diagnose::model::Metric;

impl Proposal<'_> {
    /// Trends of degree 0, 1 and 2.
    pub fn offset_drift(&self) -> Result<Option<Candidate>, DiagnoseError> {
        let effect = Effect::OffsetDrift;
        let opts = (0..=2)
            .map(|d| {
                (
                    format!("degree {d}"),
                    self.with(|s| s.trend_degree = Some(d)),
                )
            })
            .collect();
        self.best_of(effect, opts, Metric::Simulation)
    }
}
