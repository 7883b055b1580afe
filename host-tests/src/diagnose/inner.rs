//! The inner validation inside the estimation data, on which every setting and every effect is
//! chosen: one held-out block if the base model fitted without it simulates it about as well as
//! the model fits the record (at most 3 × the in-sample RMSE); otherwise leave-block-out
//! cross-validation over tenths of the record (10-fold) that are scorable in that sense (at
//! least two), their scores pooled.

use std::ops::Range;

use super::effects::Holdout;
use super::model::{self, ExtendedModel, FitOptions, InitialState, Metric, Structure};
use super::options::DiagnoseOptions;
use crate::model::Record;
use crate::validation::residual;

/// The blocks of the inner validation.
#[derive(Clone, Debug, PartialEq)]
pub struct InnerValidation {
    /// The single held-out block (the last `1 − inner_fraction` of the record, moved to
    /// leave every knot segment excited).
    pub block: Range<usize>,
    /// The blocks scored: the single block, or the cross-validation folds.
    pub folds: Vec<Range<usize>>,
    /// With a single block at the record's end: a block of its length inside the record (see
    /// [`Holdout::interior_block`]), which scores the steps after a term in time is added.
    pub interior: Option<Range<usize>>,
    /// Whether the blocks can score extensions: the base structure fitted without the block
    /// simulates it within 3 × the in-sample error, or at least two cross-validation blocks
    /// do.
    pub scorable: bool,
    /// Whether the inner fits refine their poles because, with the subspace poles, the blocks
    /// were weak or unscorable (see [`InnerValidation::choose_refining`]).
    pub refined_poles: bool,
}

impl InnerValidation {
    /// [`InnerValidation::choose`], then, if the inner fits keep the subspace poles
    /// (`fit.refine_poles` unset) and the estimator refines poles at all, again with the poles
    /// refined in `fit` when the base structure fitted that way without the blocks cannot
    /// score them or is [`weak`] there: an extension must not gain on the inner score by a
    /// better fit of the same dynamics.
    pub fn choose_refining(
        est: &Record,
        opts: &DiagnoseOptions,
        fit: &mut FitOptions,
        base: &ExtendedModel,
    ) -> Self {
        let inner = Self::choose(est, opts, fit, base);
        let refine = !fit.refine_poles
            && model::Estimator::of(est).refines_poles()
            && (!inner.scorable || weak(est, fit, base, &inner.folds, opts.min_gain));
        if !refine {
            return inner;
        }
        fit.refine_poles = true;
        Self {
            refined_poles: true,
            ..Self::choose(est, opts, fit, base)
        }
    }

    /// Chooses the blocks for the estimation record `est`, fitted with `fit` (knots chosen),
    /// its base model `base` fitted on all of it.
    pub fn choose(
        est: &Record,
        opts: &DiagnoseOptions,
        fit: &FitOptions,
        base: &ExtendedModel,
    ) -> Self {
        let id = &fit.identify;
        let (hold, ne) = (id.hold, est.len());
        let shared = id.static_nonlinearity;
        let estimated = fit.initial == InitialState::Estimated;
        let block_len = ((ne - hold) as f64 * (1.0 - opts.inner_fraction)).round() as usize;
        let (_, _, bins, count) =
            residual::regressor(&est.u, &id.knots_asc, &id.knots_desc, shared);
        let block = Holdout::choose_block(est, hold, block_len, &bins, count, estimated);
        let (folds, scorable): (Vec<Range<usize>>, bool) = if scorable(est, fit, base, &block) {
            (vec![block.clone()], true)
        } else {
            let good = cross_folds(est, fit, base);
            if good.len() >= 2 {
                (good, true)
            } else {
                (vec![block.clone()], false)
            }
        };
        let interior = (folds.len() == 1 && block.end == ne)
            .then(|| Holdout::interior_block(est, hold, block.len(), &bins, count))
            .flatten();
        Self {
            block,
            folds,
            interior,
            scorable,
            refined_poles: false,
        }
    }

    /// How the settings and effects are chosen, in words, for `ne` estimation samples.
    pub fn describe(&self, ne: usize) -> String {
        let refined = if self.refined_poles {
            "; these fits refine their poles on the simulation error (with the subspace poles alone, the base model fitted without the blocks simulated them worse than the minimum gain allows)"
        } else {
            ""
        };
        format!("{}{refined}", self.describe_blocks(ne))
    }

    /// How the blocks are chosen and scored, in words.
    fn describe_blocks(&self, ne: usize) -> String {
        let block = &self.block;
        if self.folds.len() == 1 {
            let interior = self.interior.as_ref().map_or(String::new(), |r| {
                format!(
                    " (once a trend or settling in time is added, without samples {}..{} inside the record, across which it interpolates)",
                    r.start, r.end
                )
            });
            format!(
                "every setting and every effect is chosen on the estimation data: fitted without its samples {}..{} (of {ne}), scored on them{interior}",
                block.start, block.end
            )
        } else {
            let list: Vec<String> = self
                .folds
                .iter()
                .map(|r| format!("{}..{}", r.start, r.end))
                .collect();
            format!(
                "every setting and every effect is chosen on the estimation data by leave-block-out cross-validation (10 blocks; blocks that leave a knot segment unexcited, the first with an estimated initial state, and blocks the base model fitted without them simulates with more than 3 × its in-sample error are not used): fitted without each of the blocks {} (of {ne}) in turn, scored on it, the scores pooled (the last 30 % of the record, {}..{}, cannot be scored: the model fitted without it simulates it with more than 3 × its in-sample error)",
                list.join(", "),
                block.start,
                block.end
            )
        }
    }

    /// The hold-outs of these blocks on `est`, fitted with `fit`; `extra_dead_time` is the
    /// dead-time test's delay beyond the base model's.
    pub(crate) fn holdouts<'a>(
        &self,
        est: &'a Record,
        fit: &'a FitOptions,
        base: &ExtendedModel,
        extra_dead_time: usize,
    ) -> Holdouts<'a> {
        let delay_folds = if extra_dead_time > 0 && self.folds.len() == 1 {
            cross_folds(est, fit, base)
        } else {
            Vec::new()
        };
        Holdouts {
            main: Holdout::with_folds(est, self.folds.clone(), fit),
            delay: (delay_folds.len() >= 2).then(|| Holdout::with_folds(est, delay_folds, fit)),
            interior: self.interior.clone().map(|r| Holdout::new(est, r, fit)),
        }
    }
}

/// Whether the base structure fitted without the blocks `folds` simulates them (pooled) worse
/// than the base model `base` fits the whole record by more than the smallest gain an
/// extension must show (`1/√(1 − min_gain)` in RMSE): an extension could then gain on the
/// inner score by a better fit of the same dynamics, not by the effect it adds.
pub fn weak(
    est: &Record,
    fit: &FitOptions,
    base: &ExtendedModel,
    folds: &[Range<usize>],
    min_gain: f64,
) -> bool {
    let (hold, ne) = (fit.identify.hold, est.len());
    let in_sample = model::evaluate(base, est, hold..ne, Metric::Simulation).rmse;
    let holdout = Holdout::with_folds(est, folds.to_vec(), fit);
    match holdout.evaluate_folds(&Structure::base(), Metric::Simulation, false) {
        // A NaN on either side (a fit that cannot simulate) counts as weak.
        Ok(Some((_, ev))) => {
            let limit = in_sample / (1.0 - min_gain).max(1e-9).sqrt();
            !matches!(
                ev.rmse.partial_cmp(&limit),
                Some(std::cmp::Ordering::Less | std::cmp::Ordering::Equal)
            )
        }
        _ => true,
    }
}

/// Whether the base model fitted without the block `r` simulates it about as well as the base
/// model `base` fits the record: at most 3 × its in-sample RMSE.
fn scorable(est: &Record, fit: &FitOptions, base: &ExtendedModel, r: &Range<usize>) -> bool {
    let (hold, ne) = (fit.identify.hold, est.len());
    let in_sample = model::evaluate(base, est, hold..ne, Metric::Simulation).rmse;
    let fit_part = est.joined(&[0..r.start, r.end..ne]);
    model::fit_structure(&Structure::base(), &fit_part, fit).is_ok_and(|m| {
        let e = model::evaluate(&m, est, r.clone(), Metric::Simulation).rmse;
        e.is_finite() && e <= 3.0 * in_sample
    })
}

/// The hold-outs the steps are scored on (see [`steps::Context`](super::steps::Context)).
pub(crate) struct Holdouts<'a> {
    /// The inner validation's blocks.
    pub main: Holdout<'a>,
    /// The dead-time test's delay scored by cross-validation over the whole record: when the
    /// test finds extra dead time and the inner validation is the single block, and at least
    /// two folds are scorable.
    pub delay: Option<Holdout<'a>>,
    /// The block inside the record ([`InnerValidation::interior`]).
    pub interior: Option<Holdout<'a>>,
}

/// The blocks of leave-block-out cross-validation over tenths of the estimation record that
/// can be scored: their removal leaves every knot segment excited, the first is not one of
/// them with an estimated initial state, and the base model fitted without each simulates it
/// within 3 × its in-sample RMSE. Fewer than two means the record cannot be cross-validated.
pub(crate) fn cross_folds(
    est: &Record,
    fit: &FitOptions,
    base: &ExtendedModel,
) -> Vec<Range<usize>> {
    let id = &fit.identify;
    let estimated = fit.initial == InitialState::Estimated;
    let (_, _, bins, count) = residual::regressor(
        &est.u,
        &id.knots_asc,
        &id.knots_desc,
        id.static_nonlinearity,
    );
    Holdout::fold_blocks(est, id.hold, 10, &bins, count, estimated)
        .into_iter()
        .filter(|r| scorable(est, fit, base, r))
        .collect()
}
