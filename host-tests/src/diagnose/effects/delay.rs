//! Input delay: the input shifted by `d` samples, screened by a border refit, the best
//! delays and those near the strongest input correlations identified and scored.

use super::candidate::Candidate;
use super::catalog::Effect;
use super::proposal::Proposal;
use crate::diagnose::error::DiagnoseError;
use crate::diagnose::model::{Metric, evaluate, refit_borders};
use crate::diagnose::simulate::delay_input;

impl Proposal<'_> {
    /// The delays screened and around the lags of the strongest correlations.
    pub fn input_delay(&self) -> Result<Option<Candidate>, DiagnoseError> {
        let effect = Effect::InputDelay;
        // Screening: every delay by the border refit with the current linear part (no
        // subspace step); the two best are identified and scored on the hold-out.
        let mut screen: Vec<(f64, usize)> = (1..=self.max_delay)
            .filter_map(|d| self.screen_delay(d).map(|e| (e, d)))
            .collect();
        screen.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut delays: Vec<usize> = screen.iter().take(1).map(|&(_, d)| d).collect();
        // And around the lags of the strongest input and regressor correlations.
        for lag in [
            self.tests.strongest_input_lag,
            self.tests.strongest_input_lag_raw,
            self.tests.strongest_regressor_lag,
        ] {
            for d in [lag - 1, lag, lag + 1] {
                if d >= 1 && d as usize <= self.max_delay && !delays.contains(&(d as usize)) {
                    delays.push(d as usize);
                }
            }
        }
        delays.sort_unstable();
        let opts = delays
            .iter()
            .map(|&d| (format!("d = {d}"), self.with(|s| s.delay = d)))
            .collect();
        self.best_of(effect, opts, Metric::Simulation)
    }
}

impl Proposal<'_> {
    /// Inner hold-out RMSE of the current model's linear part with the input delayed by `d`
    /// and the borders refit (a cheap screen of the delay).
    fn screen_delay(&self, d: usize) -> Option<f64> {
        let h = self.holdout;
        let m = self.inner_model;
        let total = self.current.delay + d;
        let shared = h.opts.identify.static_nonlinearity;
        let ud_fit = delay_input(&h.fit_part.u, total);
        let skip = vec![false; ud_fit.len()];
        let target = m.less_additive(&h.fit_part);
        let (hm, x0) = refit_borders(
            &m.hammerstein,
            &ud_fit,
            &target,
            &skip,
            h.opts.initial,
            shared,
        )?;
        let mut cand = m.clone();
        cand.hammerstein = hm;
        cand.x0 = x0;
        cand.structure.delay = total;
        let ev = evaluate(&cand, h.est, h.range.clone(), Metric::Simulation);
        ev.rmse.is_finite().then_some(ev.rmse)
    }
}
