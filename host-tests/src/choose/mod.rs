//! The desktop's choices from the data: the horizons when the user gives none, the refinement
//! by the prediction-error method, and the refined model's order by an information criterion.
//! The paper's estimator (PI-MOESP at the given horizons, no refinement) stays one setting away.

mod element;
mod file;
pub mod holdout;
mod horizons;
mod knots;
mod linear;
mod order;
mod start;

pub use element::static_beside;
pub use file::{model_std, noise_file};

pub use horizons::{
    COLUMNS_PER_ROW, HorizonChoice, MAX_HORIZON, MEMORY_LEVEL, MIN_HORIZON, choose_horizons,
};
pub use knots::{KnotSupport, MIN_SEGMENT_SAMPLES, supported_knots};
pub use linear::{LINEAR_MAX_ORDER, is_linear, linear_model, linear_options};
pub use order::{OrderChoice, choose_order, neighbours};
use order::{Refined, on_whole_record};
pub use start::{MAX_START_RADIUS, MIN_REDUCED_HORIZON, ReducedHorizons, StableStart, stabilised};

use crate::identify::{HostModel, IdentifyError, IdentifyOptions};
use crate::numerics::select::{Criterion, relative_scores};
use crate::reference::uniform_knots;
use crate::refine::pem::{NoiseOrder, PemFit};
use start::subspace_start;

/// `order 2: why; order 3: why`.
fn per_order(why: &[(usize, String)]) -> String {
    let parts: Vec<String> = why.iter().map(|(n, e)| format!("order {n}: {e}")).collect();
    parts.join("; ")
}

/// Why [`best_model`] gave no model.
#[derive(Debug, thiserror::Error)]
pub enum ChooseError {
    /// The subspace identification failed (at the paper's horizons or at the chosen ones).
    #[error("{0}")]
    Identify(#[from] IdentifyError),
    /// No candidate order could be refined; the reasons per order.
    #[error(
        "the refinement failed at every candidate order ({}): identify without refinement (--no-refine) to see the subspace model",
        per_order(.0)
    )]
    Refine(Vec<(usize, String)>),
    /// No candidate was given (an empty list of candidate orders).
    #[error("no candidate to identify: give at least one order or segment count")]
    NoCandidate,
    /// The caller stopped the run.
    #[error(transparent)]
    Interrupted(#[from] crate::progress::Interrupted),
}

/// How the horizons are set.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Horizons {
    /// As given in the identification options.
    Given,
    /// From the data ([`choose_horizons`]).
    FromData,
}

/// Whether uniform knots stay where the record has few samples.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum KnotPlacement {
    /// As given: every knot stays (knots the user gave, or the paper's uniform knots).
    Given,
    /// Segments with too few samples of their path merged into a neighbour
    /// ([`supported_knots`]).
    FromData,
}

/// How many segments.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Segments {
    /// As given in the identification options.
    Given,
    /// Uniform, this many segments per path, the count with the smallest criterion of the
    /// refined model ([`ModelStage::Refined`] only; the subspace estimator keeps the given knots).
    FromData(Vec<usize>),
}

/// The segment counts tried by default: the paper's 7, and 10 and 14 for borders that bend
/// more than seven chords follow at a high SNR (the chords' error is part of the prediction
/// error, so BIC adds segments only when the data resolve them).
pub const SEGMENT_CANDIDATES: [usize; 3] = [7, 10, 14];

/// The stage of the estimation the model is taken from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ModelStage {
    /// The paper's: the subspace model as it is.
    Subspace,
    /// The subspace model refined by the prediction-error method; without a fixed order, the
    /// order of the refined model by [`choose_order`].
    Refined,
}

/// The choices of [`best_model`].
#[derive(Clone, Debug)]
pub struct Choices {
    /// Segment count given or from the data.
    pub segments: Segments,
    /// Knots kept, or merged where the record has few samples.
    pub knots: KnotPlacement,
    /// Horizons given or from the data.
    pub horizons: Horizons,
    /// Subspace only, or refined.
    pub estimator: ModelStage,
    /// The criterion of the order choice.
    pub criterion: Criterion,
    /// The noise model of the refinement: ARMA with the order by BIC (the default), or white
    /// (`NoiseOrder::Fixed(0)`: output error, the simulation error minimised).
    pub noise: NoiseOrder,
    /// The candidate orders of the refinement when the order is not given.
    pub orders: OrderCandidates,
    /// A record longer than this many samples makes the choices above (segments, horizons,
    /// order) on its first this-many samples and then refines the chosen model alone on the
    /// whole record, started from its fit on those samples ([`ChoiceWindow`]): the
    /// candidates cost a fixed amount, not one refinement of the whole record each. `None`:
    /// every candidate on the whole record.
    pub window: Option<usize>,
}

/// The orders refined when the order is not given.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OrderCandidates {
    /// The subspace order and its neighbours ([`neighbours`]).
    Neighbours,
    /// Every order from 1 to this one (below the future horizon), as a linear output-error
    /// fit by BIC over orders does.
    UpTo(usize),
}

impl Default for Choices {
    /// The desktop default: segments among [`SEGMENT_CANDIDATES`], knots where the record has
    /// samples, horizons from the data, refined, BIC.
    fn default() -> Self {
        Self {
            segments: Segments::FromData(SEGMENT_CANDIDATES.to_vec()),
            knots: KnotPlacement::FromData,
            horizons: Horizons::FromData,
            estimator: ModelStage::Refined,
            criterion: Criterion::Bic,
            noise: NoiseOrder::default(),
            orders: OrderCandidates::Neighbours,
            window: Some(CHOICE_WINDOW),
        }
    }
}

/// The samples the default choices are made on in a longer record ([`Choices::window`]):
/// above the longest measured record of the project's data (the positioning drive's 24,841),
/// so every documented choice is made on the whole record as before.
pub const CHOICE_WINDOW: usize = 30_000;

impl Choices {
    /// The paper's estimator at the given horizons.
    pub fn paper() -> Self {
        Self {
            segments: Segments::Given,
            knots: KnotPlacement::Given,
            horizons: Horizons::Given,
            estimator: ModelStage::Subspace,
            criterion: Criterion::Bic,
            noise: NoiseOrder::default(),
            orders: OrderCandidates::Neighbours,
            window: None,
        }
    }

    /// Whether these choices choose anything from the data for options `base`: the segment
    /// count, the horizons or the refined model's order.
    fn chooses(&self, base: &IdentifyOptions) -> bool {
        self.estimator == ModelStage::Refined
            && (matches!(self.segments, Segments::FromData(_))
                || self.horizons == Horizons::FromData
                || base.order.is_none())
    }
}

/// The model and what was chosen on the way.
#[derive(Clone, Debug)]
pub struct Best {
    /// The model.
    pub model: HostModel,
    /// The options the final subspace model was identified with (knots and horizons
    /// included).
    pub options: IdentifyOptions,
    /// The knots' merging, when segments were merged where the record has few samples.
    pub knots: Option<KnotSupport>,
    /// The stable start of the refinement, when the subspace model was not stable.
    pub start: Option<StableStart>,
    /// The horizons shortened, when the input Hankel Gram was rank deficient at those asked.
    pub reduced: Option<ReducedHorizons>,
    /// The refinement, when refined.
    pub fit: Option<PemFit>,
    /// The segments' choice, when from the data: `(segments, score)` of every candidate.
    pub segments: Option<SegmentChoice>,
    /// The horizons' choice, when from the data.
    pub horizons: Option<HorizonChoice>,
    /// The order's choice, when refined without a fixed order.
    pub order: Option<OrderChoice>,
    /// The choices made on the start of a long record, when they were.
    pub window: Option<ChoiceWindow>,
}

/// The choices of a long record made on its first samples ([`Choices::window`]).
#[derive(Clone, Debug, PartialEq)]
pub struct ChoiceWindow {
    /// Samples the candidates were identified and refined on.
    pub samples: usize,
    /// Samples of the whole record.
    pub record: usize,
    /// Why the whole-record refinement started from the whole record's subspace model rather
    /// than from the window's fit, when it did.
    pub restarted: Option<String>,
}

impl ChoiceWindow {
    /// One line for a report.
    pub fn report(&self) -> String {
        let start = match &self.restarted {
            None => "started from its fit there".to_string(),
            Some(why) => format!(
                "started from the whole record's subspace model (from the window's fit: {why})"
            ),
        };
        format!(
            "choices made on the first {} of {} samples (segments, horizons and order: every \
             candidate refined there); the chosen model refined on the whole record, {start}",
            self.samples, self.record
        )
    }
}

impl Best {
    /// The lines that say what was chosen and why.
    pub fn report(&self) -> Vec<String> {
        let mut lines = Vec::new();
        if let Some(s) = &self.segments {
            lines.push(s.report());
        }
        if let Some(k) = &self.knots {
            lines.push(k.report());
        }
        if let Some(r) = &self.reduced {
            lines.push(r.report());
        }
        if let Some(s) = &self.start {
            lines.push(s.report());
        }
        if let Some(h) = &self.horizons {
            lines.push(h.report());
        }
        if let Some(o) = &self.order {
            lines.push(o.report());
        }
        if let Some(w) = &self.window {
            lines.push(w.report());
        }
        lines
    }
}

/// The segment count chosen and the score of every candidate.
#[derive(Clone, Debug)]
pub struct SegmentChoice {
    /// Segments per path kept.
    pub segments: usize,
    /// The criterion.
    pub criterion: Criterion,
    /// `(segments, score)` of every candidate that could be identified and refined.
    pub scores: Vec<(usize, f64)>,
    /// `(segments, reason)` of the candidates that failed.
    pub failures: Vec<(usize, String)>,
}

impl SegmentChoice {
    /// One line for a report.
    pub fn report(&self) -> String {
        format!(
            "segments per path: {} chosen by {} of the refined models ({} relative to the best: {})",
            self.segments,
            self.criterion.name(),
            self.criterion.name(),
            relative_scores(&self.scores, self.segments)
        )
    }
}

/// Identifies `(u, y)` with `base` (interval, knots, hold, order, method) and `choices`.
///
/// With the segment count from the data (refined estimator), every candidate count is
/// identified and refined on its uniform knots and the best by the criterion is kept; else
/// the model is the one at `base`'s knots. The candidates' first error is returned when none
/// gives a model.
///
/// A record longer than `choices.window` makes the choices on its first `window` samples
/// and refines the chosen model alone on the whole record ([`ChoiceWindow`]).
pub fn best_model(
    u: &[f64],
    y: &[f64],
    base: &IdentifyOptions,
    choices: &Choices,
) -> Result<Best, ChooseError> {
    let window = match choices.window {
        Some(w) if u.len() > w && y.len() == u.len() && choices.chooses(base) => Some(w),
        _ => None,
    };
    let end = window.unwrap_or(u.len());
    let chosen = candidates(&u[..end], &y[..end.min(y.len())], base, choices)?;
    let (Some(samples), Some(window_fit)) = (window, &chosen.fit) else {
        return Ok(chosen);
    };
    let mut options = chosen.options.clone();
    options.order = Some(window_fit.model.order);
    let Refined { fit, restarted } = on_whole_record(u, y, &options, window_fit, choices)?;
    Ok(Best {
        model: fit.model.clone(),
        options,
        fit: Some(fit),
        window: Some(ChoiceWindow {
            samples,
            record: u.len(),
            restarted: restarted.map(|e| e.to_string()),
        }),
        ..chosen
    })
}

/// [`best_model`] on the whole of `(u, y)`: every candidate.
fn candidates(
    u: &[f64],
    y: &[f64],
    base: &IdentifyOptions,
    choices: &Choices,
) -> Result<Best, ChooseError> {
    let counts: &[usize] = match &choices.segments {
        Segments::FromData(c) if choices.estimator == ModelStage::Refined => c,
        _ => &[],
    };
    // `None`: `base`'s own knots, the only candidate when the count is not chosen.
    let candidates: Vec<Option<usize>> = match counts {
        [] => vec![None],
        c => c.iter().copied().map(Some).collect(),
    };
    let (lo, hi) = (base.u_min(), base.u_max());
    let mut kept: Option<(f64, usize, Best)> = None;
    let mut scores = Vec::new();
    let mut failures = Vec::new();
    let mut first_error = None;
    let n = candidates.len();
    // One segment count after the other: each builds subspace models, whose lagged sums and
    // solve workspace are the largest buffers of a run; the orders each refines run across
    // the cores ([`choose_order`]).
    for (i, s) in candidates.into_iter().enumerate() {
        let mut opts = base.clone();
        if let Some(s) = s {
            crate::progress::stage(|| format!("choosing segments: {s} ({} of {n})", i + 1))?;
            opts.knots_asc = uniform_knots(lo, hi, s);
            opts.knots_desc = opts.knots_asc.clone();
        }
        match at_knots(u, y, &opts, choices) {
            Ok(b) => {
                let score = b.fit.as_ref().map_or(f64::INFINITY, |f| {
                    choices
                        .criterion
                        .score(f.samples as f64, f.mse, f.parameters() as f64)
                });
                scores.extend(s.map(|s| (s, score)));
                if kept.as_ref().is_none_or(|(k, _, _)| score < *k) {
                    kept = Some((score, s.unwrap_or(0), b));
                }
            }
            Err(e @ ChooseError::Interrupted(_)) => return Err(e),
            Err(e) => {
                failures.extend(s.map(|s| (s, e.to_string())));
                first_error.get_or_insert(e);
            }
        }
    }
    let Some((_, segments, mut b)) = kept else {
        return Err(first_error.unwrap_or(ChooseError::NoCandidate));
    };
    if !counts.is_empty() {
        b.segments = Some(SegmentChoice {
            segments,
            criterion: choices.criterion,
            scores,
            failures,
        });
    }
    Ok(b)
}

/// [`best_model`] at the knots of `base`: the subspace model at the given horizons, or at
/// those chosen from a first model at the given ones ([`choose_horizons`]), then refined at
/// the candidate orders ([`choose_order`]) unless the estimator is the subspace one.
fn at_knots(
    u: &[f64],
    y: &[f64],
    base: &IdentifyOptions,
    choices: &Choices,
) -> Result<Best, ChooseError> {
    let mut opts = base.clone();
    let mut knots = None;
    if choices.knots == KnotPlacement::FromData {
        let s = supported_knots(
            u,
            opts.hold,
            &opts.knots_asc,
            &opts.knots_desc,
            !opts.static_nonlinearity,
        );
        if s.merged() {
            opts.knots_asc = s.asc.clone();
            opts.knots_desc = s.desc.clone();
            knots = Some(s);
        }
    }
    let mut horizons = None;
    let free = choices.horizons == Horizons::FromData;
    let mut reduced = None;
    let (model, start) = loop {
        crate::progress::stage(|| format!("subspace model at f = {}, p = {}", opts.f, opts.p))?;
        let s = subspace_start(u, y, &mut opts, choices.estimator, free)?;
        // Horizons the input could not support stay shortened: the plant's memory is not
        // read from a model at horizons the data do not allow.
        let done = !free || horizons.is_some() || s.reduced.is_some();
        reduced = s.reduced.or(reduced);
        if done {
            break (s.model, s.stable);
        }
        let (model, start) = (s.model, s.stable);
        let h = choose_horizons(&model, &opts, u.len().saturating_sub(opts.hold));
        let same = (h.f, h.p) == (opts.f, opts.p);
        (opts.f, opts.p) = (h.f, h.p);
        horizons = Some(h);
        if same {
            break (model, start);
        }
    };
    if choices.estimator == ModelStage::Subspace {
        return Ok(Best {
            model,
            options: opts,
            knots,
            start,
            reduced,
            fit: None,
            segments: None,
            horizons,
            order: None,
            window: None,
        });
    }
    let candidates = match (base.order, choices.orders) {
        (Some(n), _) => vec![n],
        (None, OrderCandidates::Neighbours) => neighbours(model.order, opts.f),
        (None, OrderCandidates::UpTo(max)) => (1..=max.min(opts.f.saturating_sub(1))).collect(),
    };
    let (fit, order) = choose_order(u, y, &opts, model.order, &candidates, choices)?;
    Ok(Best {
        model: fit.model.clone(),
        options: opts,
        knots,
        start,
        reduced,
        fit: Some(fit),
        segments: None,
        horizons,
        order: (base.order.is_none()).then_some(order),
        window: None,
    })
}
