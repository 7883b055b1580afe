//! Unmodelled dynamics: orders up to 3 above the current one.

use super::candidate::Candidate;
use super::catalog::Effect;
use super::proposal::Proposal;
use crate::diagnose::error::DiagnoseError;
use crate::diagnose::model::Metric;

/// The longer horizons `f = p` tried for unmodelled dynamics (12, the longest the core took when
/// the diagnosis was tuned; the confusion table and the measured reports are scored with it).
pub const LONGER_HORIZON: usize = 12;

impl Proposal<'_> {
    /// Orders up to 3 above the current one, at the current horizons and at
    /// [`LONGER_HORIZON`] (for slower or higher-order dynamics).
    pub fn unmodeled_dynamics(&self) -> Result<Option<Candidate>, DiagnoseError> {
        let effect = Effect::UnmodeledDynamics;
        let mut horizons = vec![self.f];
        if self.f < LONGER_HORIZON {
            horizons.push(LONGER_HORIZON);
        }
        let mut opts = Vec::new();
        for n in self.order + 1..=self.order + 3 {
            for &h in horizons.iter().filter(|&&h| n < h) {
                let label = if h == self.f {
                    format!("n = {n}")
                } else {
                    format!("n = {n}, f = p = {h}")
                };
                opts.push((
                    label,
                    self.with(|s| {
                        s.order = Some(n);
                        if h != self.f {
                            s.horizon = Some(h);
                        }
                    }),
                ));
            }
        }
        self.best_of(effect, opts, Metric::Simulation)
    }
}
