//! The catalog of missing effects, the evidence each one needs, and the proposal of each
//! effect's model extension with its setting chosen on the estimation data.
//!
//! Every setting is chosen by an inner hold-out inside the estimation record: the extended
//! model is fitted on its first 70 % (after the hold) and scored by simulation on the last
//! 30 % (simulated from the start, so the initial state is consistent). The same score decides
//! whether the effect is added: the extension must lower the inner hold-out mean squared error
//! by at least the minimum gain and significantly (one-sided Diebold–Mariano test on the
//! squared errors at 1 %, Newey–West variance).

use serde::Serialize;

use super::error::DiagnoseError;
use super::model::{
    Dynamics, Evaluation, ExtendedModel, FitOptions, Metric, Record, Structure, evaluate,
    fit_structure, fit_structure_fold, refit_borders, spectral_radius,
};
use super::noise::ar_order_bic;
use super::residual::{LEVEL, Test, TestSet};
use super::simulate::delay_input;
use super::stats::{newey_west_var_of_mean, normal_sf, periodogram};

/// The effects the diagnosis can name and add.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, PartialOrd, Ord)]
#[serde(rename_all = "snake_case")]
pub enum Effect {
    /// Output offset or slow drift: a polynomial trend in time.
    OffsetDrift,
    /// Extra transport delay: the input shifted by `d` samples.
    InputDelay,
    /// Order too low: a higher model order.
    UnmodeledDynamics,
    /// A static output map (saturation, overflow, sensor curve): Hammerstein–Wiener.
    OutputNonlinearity,
    /// A sinusoidal disturbance at a frequency detected in the residual.
    PeriodicDisturbance,
    /// Coloured noise: an AR noise model for one-step-ahead prediction.
    ColoredNoise,
    /// Isolated outliers: robust re-estimation.
    Outliers,
    /// State-dependent dynamics: level-dependent stores instead of the linear `G`. Beyond the
    /// seven-effect catalog the simulated scenarios cover ([`Effect::ALL`]); proposed with
    /// them ([`Effect::PROPOSED`]).
    StateDependentDynamics,
}

impl Effect {
    /// Every effect of the catalog.
    pub const ALL: [Effect; 7] = [
        Effect::OffsetDrift,
        Effect::InputDelay,
        Effect::UnmodeledDynamics,
        Effect::OutputNonlinearity,
        Effect::PeriodicDisturbance,
        Effect::ColoredNoise,
        Effect::Outliers,
    ];

    /// Every effect the diagnosis proposes: the catalog, then the level-dependent stores
    /// for state-dependent dynamics.
    pub const PROPOSED: [Effect; 8] = {
        let mut all = [Effect::StateDependentDynamics; 8];
        let mut i = 0;
        while i < Effect::ALL.len() {
            all[i] = Effect::ALL[i];
            i += 1;
        }
        all
    };

    /// The catalog name (`offset_drift`, …).
    pub fn name(self) -> &'static str {
        match self {
            Effect::OffsetDrift => "offset_drift",
            Effect::InputDelay => "input_delay",
            Effect::UnmodeledDynamics => "unmodeled_dynamics",
            Effect::OutputNonlinearity => "output_nonlinearity",
            Effect::PeriodicDisturbance => "periodic_disturbance",
            Effect::ColoredNoise => "colored_noise",
            Effect::Outliers => "outliers",
            Effect::StateDependentDynamics => "state_dependent_dynamics",
        }
    }

    /// The effect with this catalog name.
    pub fn from_name(name: &str) -> Option<Effect> {
        Effect::PROPOSED.into_iter().find(|e| e.name() == name)
    }

    /// The residual tests that point at this effect (at least one must fire).
    pub fn evidence_tests(self) -> &'static [Test] {
        match self {
            Effect::OffsetDrift => &[Test::Trend],
            Effect::InputDelay => &[
                Test::InputCorrelation,
                Test::DirectionCorrelation,
                Test::RegressorCorrelation,
            ],
            Effect::UnmodeledDynamics => &[
                Test::InputCorrelation,
                Test::DirectionCorrelation,
                Test::RegressorCorrelation,
                Test::Whiteness,
            ],
            Effect::OutputNonlinearity => &[Test::StructureOutput, Test::StructureInput],
            Effect::PeriodicDisturbance => &[Test::SpectralLine],
            Effect::ColoredNoise => &[Test::Whiteness],
            Effect::Outliers => &[Test::HeavyTails],
            // Dynamics of another class: the evidence of wrong dynamics (as for a higher
            // order), and a residual that follows the level (its increment, or its mean).
            Effect::StateDependentDynamics => &[
                Test::StateDependence,
                Test::StructureOutput,
                Test::InputCorrelation,
                Test::RegressorCorrelation,
                Test::Whiteness,
            ],
        }
    }

    /// The model extension, in words.
    pub fn extension(self) -> &'static str {
        match self {
            Effect::OffsetDrift => {
                "polynomial output trend in time, degree chosen on the estimation hold-out"
            }
            Effect::InputDelay => "input shifted by d samples, d chosen on the estimation hold-out",
            Effect::UnmodeledDynamics => "higher model order, chosen on the estimation hold-out",
            Effect::OutputNonlinearity => {
                "monotone piecewise-linear output map (Hammerstein–Wiener), segments chosen on the estimation hold-out"
            }
            Effect::PeriodicDisturbance => {
                "sinusoid at the residual's spectral line, frequency refined by least squares"
            }
            Effect::ColoredNoise => "AR noise model (order by BIC) for one-step-ahead prediction",
            Effect::Outliers => {
                "robust re-estimation: outliers by the MAD rule replaced by the model output, left out of the error"
            }
            Effect::StateDependentDynamics => {
                "level-dependent stores: the order-2 linear part as a cascade of two stores with power-law outflows, the first overflowing into the second, borders refitted with them on the simulation error"
            }
        }
    }

    /// Whether the effect changes the deterministic (simulated) model; the noise model only
    /// changes predictions.
    pub fn deterministic(self) -> bool {
        self != Effect::ColoredNoise
    }

    /// Rough count of parameters the extension adds (ties go to the simpler one).
    fn complexity(self, s: &Structure, base_order: usize) -> f64 {
        match self {
            Effect::InputDelay => 1.0,
            Effect::OffsetDrift => s.trend_degree.map_or(1, |d| d + 1) as f64,
            Effect::PeriodicDisturbance => 3.0,
            Effect::Outliers => 2.0,
            Effect::OutputNonlinearity => s.output_map_segments.unwrap_or(3) as f64 + 1.0,
            Effect::UnmodeledDynamics => {
                let n = s.order.unwrap_or(base_order + 1);
                ((n.saturating_sub(base_order)) * (2 * n + 2)) as f64
            }
            Effect::ColoredNoise => s.noise_ar_order.unwrap_or(1) as f64,
            // Exponents, offsets, overflow level and spill beyond the linear cascade.
            Effect::StateDependentDynamics => 6.0,
        }
    }

    fn is_in(self, s: &Structure) -> bool {
        match self {
            Effect::OffsetDrift => s.trend_degree.is_some(),
            Effect::InputDelay => s.delay > 0,
            Effect::UnmodeledDynamics => s.order.is_some(),
            Effect::OutputNonlinearity => s.output_map_segments.is_some(),
            Effect::PeriodicDisturbance => s.frequencies.len() >= 3,
            Effect::ColoredNoise => s.noise_ar_order.is_some(),
            Effect::Outliers => s.robust,
            Effect::StateDependentDynamics => s.dynamics != Dynamics::Linear,
        }
    }
}

/// The effect's setting, in words, for a structure that has it.
pub fn setting(effect: Effect, s: &Structure, model: Option<&ExtendedModel>) -> String {
    match effect {
        Effect::OffsetDrift => format!("trend degree {}", s.trend_degree.unwrap_or(0)),
        Effect::InputDelay => format!("delay {} samples", s.delay),
        Effect::UnmodeledDynamics => match s.horizon {
            Some(h) => format!("order {}, horizons f = p = {h}", s.order.unwrap_or(0)),
            None => format!("order {}", s.order.unwrap_or(0)),
        },
        Effect::OutputNonlinearity => format!(
            "output map with {} segments",
            s.output_map_segments.unwrap_or(0)
        ),
        Effect::PeriodicDisturbance => match s.frequencies.last() {
            Some(w) => format!(
                "sinusoid at ω = {w:.5} rad/sample (period {:.2} samples)",
                2.0 * std::f64::consts::PI / w
            ),
            None => String::new(),
        },
        Effect::ColoredNoise => format!("AR({}) noise model", s.noise_ar_order.unwrap_or(0)),
        Effect::Outliers => match model {
            Some(m) => format!(
                "MAD rule at {} robust σ, {} estimation samples flagged",
                m.outlier_k, m.flagged
            ),
            None => "MAD rule".into(),
        },
        Effect::StateDependentDynamics => {
            let map = match s.output_map_segments {
                Some(k) => format!(", output map with {k} segments"),
                None => String::new(),
            };
            match model.and_then(|m| m.stores.as_ref()) {
                Some(st) => format!(
                    "level-dependent stores: outflow exponents {:.2}, {:.2}; overflow at {:.3} with {:.0} % spilled{map}",
                    st.alpha[0],
                    st.alpha[1],
                    st.level,
                    100.0 * st.spill
                ),
                None => format!("level-dependent stores{map}"),
            }
        }
    }
}

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
    let sd = super::stats::variance(&meas).sqrt();
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
    pub fn with_folds(
        est: &'a Record,
        ranges: Vec<std::ops::Range<usize>>,
        opts: &'a FitOptions,
    ) -> Self {
        let folds: Vec<Fold> = ranges
            .into_iter()
            .map(|r| Fold {
                fit_part: est.parts(&[0..r.start, r.end..est.len()]),
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
    pub fn evaluate_folds(
        &self,
        s: &Structure,
        metric: Metric,
        check_slow: bool,
    ) -> Result<Option<(ExtendedModel, Evaluation)>, DiagnoseError> {
        let mut first: Option<ExtendedModel> = None;
        let mut evs = Vec::new();
        for f in &self.folds {
            let m = if s.dynamics.stores().is_some() {
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
                    super::stats::variance(&est.y[end - len..end]),
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
    m.stores.is_none() && spectral_radius(&m.hammerstein) >= 1.0 - 0.5 / n.max(4) as f64
}

/// Relative MSE reduction and one-sided Diebold–Mariano p-value of `cand` against `base`.
/// Excluded samples (outliers) count with the model's mean loss.
pub fn compare(base: &Evaluation, cand: &Evaluation) -> (f64, f64) {
    let lb = base.losses();
    let lc = cand.losses();
    let mean_of = |l: &[Option<f64>]| {
        let v: Vec<f64> = l.iter().flatten().copied().collect();
        v.iter().sum::<f64>() / v.len().max(1) as f64
    };
    let (mb, mc) = (mean_of(&lb), mean_of(&lc));
    let d: Vec<f64> = lb
        .iter()
        .zip(&lc)
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
    /// One-sided Diebold–Mariano p-value of that reduction.
    pub p_value: f64,
    /// Complexity (parameters added), for ties.
    pub complexity: f64,
    /// Settings tried, with their inner hold-out RMSE.
    pub tried: Vec<(String, f64)>,
}

/// What a proposal needs.
pub struct Proposal<'a> {
    /// The inner hold-out.
    pub holdout: &'a Holdout<'a>,
    /// The current structure.
    pub current: &'a Structure,
    /// Its inner hold-out evaluation (simulation).
    pub baseline: &'a Evaluation,
    /// The current structure fitted on the inner hold-out's fitting part.
    pub inner_model: &'a ExtendedModel,
    /// Order of the current model.
    pub order: usize,
    /// Future horizon (orders stay below it).
    pub f: usize,
    /// Largest delay tried.
    pub max_delay: usize,
    /// In-sample residual of the current model on the estimation record (after the hold).
    pub residual: &'a [f64],
    /// Input over the same samples.
    pub input: &'a [f64],
    /// The current model's tests on that residual.
    pub tests: &'a TestSet,
}

impl Proposal<'_> {
    /// Scores every setting (given in increasing complexity) on the inner hold-out and keeps
    /// the simplest whose RMSE is within 0.5 % of the best.
    fn best_of(
        &self,
        effect: Effect,
        options: Vec<(String, Structure)>,
        metric: Metric,
    ) -> Result<Option<Candidate>, DiagnoseError> {
        let mut scored: Vec<(Structure, ExtendedModel, Evaluation)> = Vec::new();
        let mut tried = Vec::new();
        for (label, s) in options {
            let (m, ev) = match self.holdout.score(&s, metric) {
                Ok(Some(v)) => v,
                Ok(None) => {
                    tried.push((format!("{label} (mode too slow)"), f64::NAN));
                    continue;
                }
                Err(DiagnoseError::Identify(e)) => {
                    tried.push((format!("{label} (identification failed: {e})"), f64::NAN));
                    continue;
                }
                Err(DiagnoseError::Dynamics(e)) => {
                    tried.push((format!("{label} (not fitted: {e})"), f64::NAN));
                    continue;
                }
                Err(e) => return Err(e),
            };
            tried.push((label, ev.rmse));
            if ev.rmse.is_finite() {
                scored.push((s, m, ev));
            }
        }
        let best = scored
            .iter()
            .map(|(_, _, e)| e.rmse)
            .fold(f64::INFINITY, f64::min);
        let Some((s, m, ev)) = scored.into_iter().find(|(_, _, e)| e.rmse <= best * 1.005) else {
            return Ok(None);
        };
        let (gain, p_value) = compare(self.baseline, &ev);
        Ok(Some(Candidate {
            effect,
            complexity: effect.complexity(&s, self.order),
            structure: s,
            inner_model: m,
            evaluation: ev,
            gain,
            p_value,
            tried,
        }))
    }

    /// Inner hold-out RMSE of the current model's linear part with the input delayed by `d`
    /// and the borders refit (a cheap screen of the delay).
    fn screen_delay(&self, d: usize) -> Option<f64> {
        let h = self.holdout;
        let m = self.inner_model;
        let total = self.current.delay + d;
        let shared = h.opts.identify.static_nonlinearity;
        let ud_fit = delay_input(&h.fit_part.u, total);
        let skip = vec![false; ud_fit.len()];
        let target: Vec<f64> = h
            .fit_part
            .y
            .iter()
            .zip(&h.fit_part.time)
            .map(|(y, &t)| y - m.additive.eval(t))
            .collect();
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

    /// Proposes the effect's extension with its best setting, or `None` when it has nothing
    /// to add (already in the model, no setting left, no fit).
    pub fn propose(&self, effect: Effect) -> Result<Option<Candidate>, DiagnoseError> {
        if effect.is_in(self.current) {
            return Ok(None);
        }
        let with = |f: &dyn Fn(&mut Structure)| {
            let mut s = self.current.clone();
            f(&mut s);
            s
        };
        match effect {
            Effect::InputDelay => {
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
                        if d >= 1 && d as usize <= self.max_delay && !delays.contains(&(d as usize))
                        {
                            delays.push(d as usize);
                        }
                    }
                }
                delays.sort_unstable();
                let opts = delays
                    .iter()
                    .map(|&d| (format!("d = {d}"), with(&|s| s.delay = d)))
                    .collect();
                self.best_of(effect, opts, Metric::Simulation)
            }
            Effect::UnmodeledDynamics => {
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
                            with(&|s| {
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
            Effect::OffsetDrift => {
                let opts = (0..=2)
                    .map(|d| (format!("degree {d}"), with(&|s| s.trend_degree = Some(d))))
                    .collect();
                self.best_of(effect, opts, Metric::Simulation)
            }
            Effect::OutputNonlinearity => {
                let opts = [3usize, 5, 8]
                    .into_iter()
                    .map(|k| {
                        (
                            format!("{k} segments"),
                            with(&|s| s.output_map_segments = Some(k)),
                        )
                    })
                    .collect();
                self.best_of(effect, opts, Metric::Simulation)
            }
            Effect::PeriodicDisturbance => {
                let Some(w) = refine_frequency(self.residual, self.tests.line_frequency) else {
                    return Ok(None);
                };
                let opts = vec![(format!("ω = {w:.5}"), with(&|s| s.frequencies.push(w)))];
                self.best_of(effect, opts, Metric::Simulation)
            }
            Effect::Outliers => {
                let opts = vec![("MAD rule".to_string(), with(&|s| s.robust = true))];
                let c = self.best_of(effect, opts, Metric::Simulation)?;
                // Outliers are rare: beyond 3 % of the samples flagged, the "outliers" are the
                // tails of a model error, and leaving them out of the error would hide it.
                Ok(c.filter(|c| {
                    let n = c.evaluation.excluded.len().max(1);
                    let k = c.evaluation.excluded.iter().filter(|&&e| e).count();
                    k * 100 <= 3 * n
                        && c.inner_model.flagged * 100 <= 3 * self.holdout.fit_part.len()
                }))
            }
            Effect::StateDependentDynamics => {
                // With stores the steady-state curve bends by itself: the output map, if
                // any, is also tried reduced to its affine part and clip.
                let mut opts = Vec::new();
                if self.current.output_map_segments.is_some_and(|k| k > 1) {
                    opts.push((
                        "stores, output map reduced to 1 segment".to_string(),
                        with(&|s| {
                            s.dynamics = Dynamics::Stores;
                            s.output_map_segments = Some(1);
                        }),
                    ));
                }
                opts.push((
                    "stores".to_string(),
                    with(&|s| s.dynamics = Dynamics::Stores),
                ));
                let Some(mut c) = self.best_of(effect, opts, Metric::Simulation)? else {
                    return Ok(None);
                };
                // The level dependence must beat the same stores with linear outflows and
                // no overflow (the linear cascade refitted the same way, borders included):
                // otherwise the gain is the refit's, not the state dependence's. The
                // candidate keeps the smaller gain and the larger p-value of the two
                // comparisons.
                let mut reference = c.structure.clone();
                reference.dynamics = Dynamics::LinearStores;
                match self.holdout.score(&reference, Metric::Simulation) {
                    Ok(Some((_, ev))) if ev.rmse.is_finite() => {
                        let (gain, p_value) = compare(&ev, &c.evaluation);
                        c.tried
                            .push(("linear stores (the reference)".to_string(), ev.rmse));
                        c.gain = c.gain.min(gain);
                        c.p_value = c.p_value.max(p_value);
                    }
                    Ok(_) | Err(DiagnoseError::Identify(_) | DiagnoseError::Dynamics(_)) => {
                        c.tried.push((
                            "linear stores (the reference): not fitted".to_string(),
                            f64::NAN,
                        ));
                    }
                    Err(e) => return Err(e),
                }
                Ok(Some(c))
            }
            Effect::ColoredNoise => {
                let Some(p) = ar_order_bic(self.residual, 20) else {
                    return Ok(None);
                };
                let opts = vec![(format!("AR({p})"), with(&|s| s.noise_ar_order = Some(p)))];
                self.best_of(effect, opts, Metric::Prediction)
            }
        }
    }
}

/// Power of the least-squares sinusoid at `w` in `r`.
fn sinusoid_power(r: &[f64], w: f64) -> f64 {
    let (mut cc, mut ss, mut cs, mut rc, mut rs) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for (t, v) in r.iter().enumerate() {
        let (s, c) = (w * t as f64).sin_cos();
        cc += c * c;
        ss += s * s;
        cs += c * s;
        rc += v * c;
        rs += v * s;
    }
    let det = cc * ss - cs * cs;
    if det.abs() < 1e-300 {
        return 0.0;
    }
    let a = (rc * ss - rs * cs) / det;
    let b = (rs * cc - rc * cs) / det;
    a * rc + b * rs
}

/// Refines a spectral line's frequency by maximising the least-squares sinusoid's power
/// (golden section within two periodogram bins).
pub fn refine_frequency(r: &[f64], w0: f64) -> Option<f64> {
    if !(w0 > 0.0 && w0 < std::f64::consts::PI) || r.len() < 16 {
        return None;
    }
    let (omega, _) = periodogram(r);
    let bin = omega.first().copied().unwrap_or(0.01);
    let (mut a, mut b) = (
        (w0 - 2.0 * bin).max(1e-6),
        (w0 + 2.0 * bin).min(std::f64::consts::PI),
    );
    let g = 0.618_033_988_749_895;
    let mut x1 = b - g * (b - a);
    let mut x2 = a + g * (b - a);
    let mut f1 = sinusoid_power(r, x1);
    let mut f2 = sinusoid_power(r, x2);
    for _ in 0..40 {
        if f1 > f2 {
            b = x2;
            x2 = x1;
            f2 = f1;
            x1 = b - g * (b - a);
            f1 = sinusoid_power(r, x1);
        } else {
            a = x1;
            x1 = x2;
            f1 = f2;
            x2 = a + g * (b - a);
            f2 = sinusoid_power(r, x2);
        }
    }
    Some(0.5 * (a + b))
}

/// Whether any of the effect's evidence tests fired.
pub fn has_evidence(effect: Effect, tests: &TestSet) -> bool {
    effect.evidence_tests().iter().any(|&t| tests.fired(t))
}

/// Picks the effect to add among candidates: significant at 1 % and at least `min_gain`; the
/// largest gain wins, and within `tie` of it the simplest extension.
pub fn choose(cands: &[Candidate], min_gain: f64, tie: f64) -> Option<usize> {
    let ok: Vec<usize> = (0..cands.len())
        .filter(|&i| cands[i].p_value < LEVEL && cands[i].gain >= min_gain)
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
