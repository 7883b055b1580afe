//! The inner validation of the estimation record: its blocks and folds, the fits without them
//! and the pooled scores.

use crate::diagnose::error::DiagnoseError;
use crate::diagnose::model::{
    Evaluation, ExtendedModel, FitOptions, Metric, Structure, evaluate, fit_structure,
    fit_structure_fold,
};
use crate::model::Record;

/// One fold of the inner validation: the estimation record without a block (joined at the
/// gap) fits, the block is scored.
#[derive(Clone, Debug)]
pub struct Fold {
    /// The record without the block.
    pub fit_part: Record,
    /// The scored block.
    pub range: std::ops::Range<usize>,
}

/// The inner validation of the estimation record: one held-out block, or several folds
/// (leave-block-out cross-validation) whose scored blocks are pooled.
#[derive(Clone, Debug)]
pub struct Holdout<'a> {
    /// The whole estimation record (simulated from its start).
    pub est: &'a Record,
    /// The first fold's fitting part (the record without its block, joined at the gap).
    pub fit_part: Record,
    /// The first fold's scored block.
    pub range: std::ops::Range<usize>,
    /// Every fold (the first is `fit_part`, `range`).
    pub folds: Vec<Fold>,
    /// Fit options.
    pub opts: &'a FitOptions,
}

/// Whether removing samples `a..b` leaves every knot segment the record excites with at least
/// 5 samples (or all its samples, if fewer).
fn leaves_every_segment(bins: &[usize], count: usize, a: usize, b: usize) -> bool {
    let mut total = vec![0usize; count];
    for &bin in bins {
        if let Some(c) = total.get_mut(bin) {
            *c += 1;
        }
    }
    let mut left = total.clone();
    for &bin in &bins[a.min(bins.len())..b.min(bins.len())] {
        if let Some(c) = left.get_mut(bin) {
            *c -= 1;
        }
    }
    left.iter()
        .zip(&total)
        .all(|(&l, &t)| t == 0 || l >= 5.min(t))
}

/// Pools evaluations of several blocks: residuals and exclusions concatenated, the errors over
/// all of them (the output is the first one's).
fn pool(est: &Record, evs: Vec<(std::ops::Range<usize>, Evaluation)>) -> Option<Evaluation> {
    let mut it = evs.into_iter();
    let (r0, first) = it.next()?;
    let mut ranges = vec![r0];
    let mut out = first;
    for (r, ev) in it {
        out.residual.extend(ev.residual);
        out.excluded.extend(ev.excluded);
        ranges.push(r);
    }
    let meas: Vec<f64> = ranges
        .iter()
        .flat_map(|r| r.clone())
        .zip(&out.excluded)
        .filter(|(_, e)| !**e)
        .map(|(t, _)| est.y[t])
        .collect();
    let used = meas.len();
    let sse: f64 = out
        .residual
        .iter()
        .zip(&out.excluded)
        .filter(|(_, e)| !**e)
        .map(|(r, _)| r * r)
        .sum();
    out.rmse = (sse / used.max(1) as f64).sqrt();
    let sd = crate::validation::stats::variance(&meas).sqrt();
    out.nrmse = out.rmse / sd.max(1e-300);
    out.fit_percent = 100.0 * (1.0 - out.nrmse);
    out.used = used;
    Some(out)
}

impl<'a> Holdout<'a> {
    /// Inner hold-out scoring the block `range`.
    pub fn new(est: &'a Record, range: std::ops::Range<usize>, opts: &'a FitOptions) -> Self {
        Self::with_folds(est, vec![range], opts)
    }

    /// Leave-block-out cross-validation over the blocks `ranges` (at least one).
    pub(crate) fn with_folds(
        est: &'a Record,
        ranges: Vec<std::ops::Range<usize>>,
        opts: &'a FitOptions,
    ) -> Self {
        let folds: Vec<Fold> = ranges
            .into_iter()
            .map(|r| Fold {
                fit_part: est.joined(&[0..r.start, r.end..est.len()]),
                range: r,
            })
            .collect();
        let (fit_part, range) = folds.first().map_or_else(
            || (est.clone(), est.len()..est.len()),
            |f| (f.fit_part.clone(), f.range.clone()),
        );
        Self {
            est,
            fit_part,
            range,
            folds,
            opts,
        }
    }

    /// The `k` equal blocks after `hold` that can be left out (see [`Holdout::choose_block`]):
    /// their removal leaves every excited knot segment excited, and with an estimated initial
    /// state the first block is not one of them.
    pub fn fold_blocks(
        est: &Record,
        hold: usize,
        k: usize,
        bins: &[usize],
        count: usize,
        estimated_start: bool,
    ) -> Vec<std::ops::Range<usize>> {
        let n = est.len();
        let k = k.max(1);
        let len = n.saturating_sub(hold) / k;
        if len == 0 {
            return Vec::new();
        }
        (0..k)
            .map(|i| {
                let a = hold + i * len;
                a..if i + 1 == k { n } else { a + len }
            })
            .filter(|r| !(estimated_start && r.start <= hold))
            .filter(|r| leaves_every_segment(bins, count, r.start, r.end))
            .collect()
    }

    /// The structure fitted on every fold's fitting part and scored on its block (pooled); the
    /// model is the first fold's. `None` when a fold's model has a mode too slow to be
    /// validated (see [`too_slow`]) and `check_slow` is set.
    pub(crate) fn evaluate_folds(
        &self,
        s: &Structure,
        metric: Metric,
        check_slow: bool,
    ) -> Result<Option<(ExtendedModel, Evaluation)>, DiagnoseError> {
        let mut first: Option<ExtendedModel> = None;
        let mut evs = Vec::new();
        for f in &self.folds {
            let m = if s.dynamics.stores().is_some() || s.element.is_some() {
                fit_structure_fold(s, &f.fit_part, self.opts, self.est, f.range.clone())?
            } else {
                fit_structure(s, &f.fit_part, self.opts)?
            };
            if check_slow && too_slow(&m, f.fit_part.len()) {
                return Ok(None);
            }
            evs.push((
                f.range.clone(),
                evaluate(&m, self.est, f.range.clone(), metric),
            ));
            first.get_or_insert(m);
        }
        Ok(first.zip(pool(self.est, evs)))
    }

    /// Chooses the block of `len` samples after `hold`, among those whose removal leaves every
    /// knot segment the record excites with at least 5 samples (blocks stepped by a quarter of
    /// their length): the last one, unless its output varies less than half as much as in the
    /// most varied valid block, which is then taken (a staircase input visits each level once,
    /// and a block of constant output scores nothing).
    pub fn choose_block(
        est: &Record,
        hold: usize,
        len: usize,
        bins: &[usize],
        count: usize,
        estimated_start: bool,
    ) -> std::ops::Range<usize> {
        let n = est.len();
        let len = len.min(n.saturating_sub(hold + 1)).max(1);
        let ok = |a: usize, b: usize| leaves_every_segment(bins, count, a, b);
        let step = (len / 4).max(1);
        let mut valid: Vec<(std::ops::Range<usize>, f64)> = Vec::new();
        let mut end = n;
        while end >= hold + len {
            // A block at the very start would leave a fitting part whose estimated initial
            // state belongs to a later sample than the simulation's start.
            if ok(end - len, end) && (end - len > hold || !estimated_start) {
                valid.push((
                    end - len..end,
                    crate::validation::stats::variance(&est.y[end - len..end]),
                ));
            }
            end = end.saturating_sub(step);
        }
        let top = valid.iter().map(|(_, v)| *v).fold(0.0f64, f64::max);
        match valid.first() {
            Some((r, v)) if *v >= 0.5 * top => r.clone(),
            Some(_) => valid
                .iter()
                .max_by(|a, b| a.1.total_cmp(&b.1))
                .map_or(n - len..n, |(r, _)| r.clone()),
            None => n - len..n,
        }
    }

    /// A block of `len` samples inside the record, away from its ends: the one nearest its
    /// middle (stepped by a quarter of the length) whose removal leaves every excited knot
    /// segment excited; `None` if there is none, or if no such block has samples on both of
    /// its sides. Terms in time fitted without it interpolate across it instead of
    /// extrapolating past the record's end.
    pub fn interior_block(
        est: &Record,
        hold: usize,
        len: usize,
        bins: &[usize],
        count: usize,
    ) -> Option<std::ops::Range<usize>> {
        let n = est.len();
        let len = len.min(n.saturating_sub(hold + 2) / 2);
        if len == 0 {
            return None;
        }
        let middle = hold + (n - hold - len) / 2;
        let step = (len / 4).max(1);
        (0..=(n - hold) / step)
            .flat_map(|i| [middle.checked_sub(i * step), Some(middle + i * step)])
            .flatten()
            .filter(|&a| a > hold && a + len < n)
            .find(|&a| leaves_every_segment(bins, count, a, a + len))
            .map(|a| a..a + len)
    }

    /// Fits `s` on every fold's fitting part and scores it on the blocks; `None` when a fitted
    /// model has a mode too slow to be validated (see [`too_slow`]).
    pub fn score(
        &self,
        s: &Structure,
        metric: Metric,
    ) -> Result<Option<(ExtendedModel, Evaluation)>, DiagnoseError> {
        self.evaluate_folds(s, metric, true)
    }
}

/// A linear model with an unstable pole, or a pole whose time constant exceeds twice the `n` samples
/// it was fitted on (`|p| ≥ 1 − 1/(2n)`): such a mode acts as a drift the data cannot
/// validate, and extrapolates wildly.
pub fn too_slow(m: &ExtendedModel, n: usize) -> bool {
    // Stores replace the linear part's simulation and drain by construction.
    m.stores.is_none() && m.spectral_radius() >= ExtendedModel::validatable_radius(n)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// On a record of 1000 samples whose bins are all one segment, the interior block of 300
    /// after a hold of 100 is the middle one, 400..700. With a second segment visited only at
    /// 450..550, the middle block and the one a quarter before it would leave it unvisited, so
    /// the block moves a quarter after it, 475..775. A block asked longer than half the record
    /// after the hold is shortened to leave samples on both of its sides.
    #[test]
    fn the_interior_block_is_the_middle_one_that_leaves_every_segment() -> Result<(), String> {
        let n = 1000;
        let rec = Record::new(vec![0.0; n], vec![0.0; n]).map_err(|e| e.to_string())?;
        let flat = vec![0usize; n];
        let middle = Holdout::interior_block(&rec, 100, 300, &flat, 1);
        if middle != Some(400..700) {
            return Err(format!("flat bins: {middle:?}"));
        }
        let mut bins = flat.clone();
        for b in &mut bins[450..550] {
            *b = 1;
        }
        let moved = Holdout::interior_block(&rec, 100, 300, &bins, 2);
        if moved != Some(475..775) {
            return Err(format!("segment 1 at 450..550: {moved:?}"));
        }
        let long = Holdout::interior_block(&rec, 100, 900, &flat, 1);
        if long != Some(325..774) {
            return Err(format!("a block of 900 asked: {long:?}"));
        }
        Ok(())
    }
}
