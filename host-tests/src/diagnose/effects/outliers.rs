//! Outliers: samples flagged by the MAD rule and left out of the error, the model re-estimated
//! without them only when that pays on the estimation hold-out; kept if the rule flags at most
//! 3 % of the samples.

use super::candidate::{Candidate, Significance, compare_common, passes};
use super::catalog::Effect;
use super::proposal::Proposal;
use crate::diagnose::error::DiagnoseError;
use crate::diagnose::model::Metric;
use crate::validation::residual::Test;

impl Proposal<'_> {
    /// The MAD rule, kept only while the outliers are rare.
    ///
    /// Two settings are scored on the inner hold-out: the current model with the flagged
    /// samples left out of the error, and the model re-estimated with them replaced by its own
    /// output. The re-estimation is chosen only when it beats the kept model by the rule every
    /// step meets (Diebold–Mariano at the diagnosis's level, on the samples neither flags, and
    /// at least the minimum gain): replacing samples by the model's output
    /// also pulls the estimate towards the model, and on spikes that did not bias it the
    /// re-estimate is no better and can be marginally worse on new data.
    pub fn outliers(&self) -> Result<Option<Candidate>, DiagnoseError> {
        let effect = Effect::Outliers;
        let kept = self.best_of(
            effect,
            vec![(
                "MAD rule, model kept".into(),
                self.with(|s| s.robust = true),
            )],
            Metric::Simulation,
        )?;
        let refit = self.best_of(
            effect,
            vec![(
                "MAD rule, re-estimated".into(),
                self.with(|s| {
                    s.robust = true;
                    s.robust_refit = true;
                }),
            )],
            Metric::Simulation,
        )?;
        // The kept model differs from the current one only by the samples it leaves out, so
        // the hold-out's paired test has only the flagged samples of its block to go on (a
        // dozen spikes give p ≈ 0.01 for a 30 % gain). Whether those samples are outliers is
        // what the heavy-tails test asks of the whole estimation residual: its p-value is the
        // kept setting's significance; its gain is still the hold-out's.
        let tails = self.tests.get(Test::HeavyTails).map_or(1.0, |t| t.p_value);
        let with_tails = |mut c: Candidate| {
            c.p_value = tails;
            c.significance = Significance::HeavyTails;
            c
        };
        let chosen = match (kept, refit) {
            (Some(k), Some(r)) => {
                let (gain, p) = compare_common(&k.evaluation, &r.evaluation);
                let (mut win, lose) = if passes(gain, p, self.min_gain) {
                    (r, k)
                } else {
                    (with_tails(k), r)
                };
                win.tried.extend(lose.tried);
                Some(win)
            }
            (Some(k), None) => Some(with_tails(k)),
            (k, r) => k.or(r),
        };
        // Outliers are rare: beyond 3 % of the samples flagged, the "outliers" are the
        // tails of a model error, and leaving them out of the error would hide it.
        Ok(chosen.filter(|c| {
            let n = c.evaluation.excluded.len().max(1);
            let k = c.evaluation.excluded.iter().filter(|&&e| e).count();
            k * 100 <= 3 * n && c.inner_model.flagged * 100 <= 3 * self.holdout.fit_part.len()
        }))
    }
}
