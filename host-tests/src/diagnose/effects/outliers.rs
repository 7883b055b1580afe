//! Outliers: robust re-estimation by the MAD rule, if it flags at most 3 % of the samples.

use super::candidate::Candidate;
use super::catalog::Effect;
use super::proposal::Proposal;
use crate::diagnose::error::DiagnoseError;
use crate::diagnose::model::Metric;

impl Proposal<'_> {
    /// The MAD rule, kept only while the outliers are rare.
    pub fn outliers(&self) -> Result<Option<Candidate>, DiagnoseError> {
        let effect = Effect::Outliers;
        let opts = vec![("MAD rule".to_string(), self.with(|s| s.robust = true))];
        let c = self.best_of(effect, opts, Metric::Simulation)?;
        // Outliers are rare: beyond 3 % of the samples flagged, the "outliers" are the
        // tails of a model error, and leaving them out of the error would hide it.
        Ok(c.filter(|c| {
            let n = c.evaluation.excluded.len().max(1);
            let k = c.evaluation.excluded.iter().filter(|&&e| e).count();
            k * 100 <= 3 * n && c.inner_model.flagged * 100 <= 3 * self.holdout.fit_part.len()
        }))
    }
}
