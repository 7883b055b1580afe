//! Coloured noise: an AR noise model of the order chosen by BIC, scored in one-step
//! prediction.

use super::candidate::Candidate;
use super::catalog::Effect;
use super::proposal::Proposal;
use crate::diagnose::error::DiagnoseError;
use crate::diagnose::model::Metric;
use crate::validation::noise::ar_order_bic;

impl Proposal<'_> {
    /// An AR noise model of the residual's BIC order.
    pub fn colored_noise(&self) -> Result<Option<Candidate>, DiagnoseError> {
        let effect = Effect::ColoredNoise;
        let Some(p) = ar_order_bic(self.residual, 20) else {
            return Ok(None);
        };
        let opts = vec![(
            format!("AR({p})"),
            self.with(|s| s.noise_ar_order = Some(p)),
        )];
        self.best_of(effect, opts, Metric::Prediction)
    }
}
