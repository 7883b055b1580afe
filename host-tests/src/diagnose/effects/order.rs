//! Unmodelled dynamics: orders up to 3 above the current one.

use super::candidate::Candidate;
use super::catalog::Effect;
use super::proposal::Proposal;
use crate::diagnose::error::DiagnoseError;
use crate::diagnose::model::Metric;

impl Proposal<'_> {
    /// Orders up to 3 above the current one, at the current horizons and at the longest the core
    /// supports (for slower or higher-order dynamics).
    pub fn unmodeled_dynamics(&self) -> Result<Option<Candidate>, DiagnoseError> {
        let effect = Effect::UnmodeledDynamics;
        // Orders up to 3 above the current one, at the current horizons and at the
        // longest the core supports (for slower or higher-order dynamics).
        let mut horizons = vec![self.f];
        if self.f < hsid::MAX_HORIZON {
            horizons.push(hsid::MAX_HORIZON);
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
