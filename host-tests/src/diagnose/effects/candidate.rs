//! A proposed extension with its inner hold-out score; the comparison of two scores and the
//! choice among candidates.

use crate::diagnose::evidence::Tried;
use crate::diagnose::model::{Evaluation, ExtendedModel, Structure};
use crate::validation::residual::LEVEL;
use crate::validation::stats::{newey_west_var_of_mean, normal_sf};

use super::catalog::Effect;

/// Relative MSE reduction and one-sided Diebold–Mariano p-value of `cand` against `base`.
/// Excluded samples (outliers) count with the model's mean loss.
pub fn compare(base: &Evaluation, cand: &Evaluation) -> (f64, f64) {
    diebold_mariano(&base.losses(), &cand.losses())
}

/// [`compare`] on the samples that neither model excludes: for two settings of the same
/// extension, whose outliers differ, so that neither wins by leaving out what the other keeps.
pub(crate) fn compare_common(base: &Evaluation, cand: &Evaluation) -> (f64, f64) {
    let (mut lb, mut lc) = (base.losses(), cand.losses());
    for (b, c) in lb.iter_mut().zip(lc.iter_mut()) {
        if b.is_none() || c.is_none() {
            (*b, *c) = (None, None);
        }
    }
    diebold_mariano(&lb, &lc)
}

/// Relative reduction of the mean loss `lb` → `lc` and its one-sided Diebold–Mariano p-value
/// (`None` losses count with their model's mean loss).
fn diebold_mariano(lb: &[Option<f64>], lc: &[Option<f64>]) -> (f64, f64) {
    let mean_of = |l: &[Option<f64>]| {
        let v: Vec<f64> = l.iter().flatten().copied().collect();
        v.iter().sum::<f64>() / v.len().max(1) as f64
    };
    let (mb, mc) = (mean_of(lb), mean_of(lc));
    let d: Vec<f64> = lb
        .iter()
        .zip(lc)
        .map(|(b, c)| b.unwrap_or(mb) - c.unwrap_or(mc))
        .collect();
    if d.is_empty() || mb <= 0.0 {
        return (0.0, 1.0);
    }
    let dbar = d.iter().sum::<f64>() / d.len() as f64;
    let lags = ((d.len() as f64).powf(1.0 / 3.0) * 1.5).ceil() as usize;
    let var = newey_west_var_of_mean(&d, lags);
    let stat = dbar / var.sqrt().max(1e-300);
    (1.0 - mc / mb, normal_sf(stat))
}

/// The test behind a candidate's p-value.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Significance {
    /// The one-sided Diebold–Mariano test of the inner hold-out losses against the current
    /// model's ([`compare`]).
    DieboldMariano,
    /// The heavy-tails test on the current model's estimation residual (samples beyond 5
    /// robust σ against the Gaussian count): for the `outliers` step that keeps the model,
    /// whose hold-out losses differ from the current model's only at the samples it flags.
    HeavyTails,
}

impl Significance {
    /// How the report names it.
    pub fn label(self) -> &'static str {
        match self {
            Significance::DieboldMariano => "Diebold–Mariano",
            Significance::HeavyTails => "heavy-tails",
        }
    }
}

/// A proposed extension with its inner hold-out score.
#[derive(Clone, Debug)]
pub struct Candidate {
    /// The effect.
    pub effect: Effect,
    /// The structure with the extension.
    pub structure: Structure,
    /// It fitted on the inner hold-out's fitting part.
    pub inner_model: ExtendedModel,
    /// Its inner hold-out evaluation.
    pub evaluation: Evaluation,
    /// Relative reduction of the inner hold-out MSE against the current model.
    pub gain: f64,
    /// The p-value of that reduction, by the test `significance` names.
    pub p_value: f64,
    /// The test behind `p_value`.
    pub significance: Significance,
    /// Complexity (parameters added), for ties.
    pub complexity: f64,
    /// Settings tried, with their inner hold-out RMSE.
    pub tried: Vec<Tried>,
}

/// The rule every step meets: a reduction `gain` significant at the diagnosis's level (`p`)
/// and at least `min_gain`.
pub fn passes(gain: f64, p: f64, min_gain: f64) -> bool {
    p < LEVEL && gain >= min_gain
}

/// Picks the effect to add among candidates that [`passes`]; the largest gain wins, and
/// within `tie` of it the simplest extension.
pub fn choose(cands: &[Candidate], min_gain: f64, tie: f64) -> Option<usize> {
    let ok: Vec<usize> = (0..cands.len())
        .filter(|&i| passes(cands[i].gain, cands[i].p_value, min_gain))
        .collect();
    let top = ok
        .iter()
        .map(|&i| cands[i].gain)
        .fold(f64::NEG_INFINITY, f64::max);
    ok.into_iter()
        .filter(|&i| cands[i].gain >= top - tie)
        .min_by(|&a, &b| {
            cands[a]
                .complexity
                .total_cmp(&cands[b].complexity)
                .then(cands[b].gain.total_cmp(&cands[a].gain))
        })
}
