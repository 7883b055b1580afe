//! The knot count from the data (item 7 of the issue).
//!
//! For every candidate number of uniform segments per path, the model is identified (PI-MOESP)
//! and refined by the prediction-error method; the count with the smallest information
//! criterion on the refined model's prediction errors is kept:
//! `BIC = N ln(Σε²/N) + d ln N` (default) or `AIC = N ln(Σε²/N) + 2d`, `d` the number of
//! estimated parameters. More knots follow the borders more closely (the approximation error
//! is part of the prediction error) but cost two parameters each; BIC's `ln N` penalty
//! prefers the smaller models and is consistent, AIC prefers prediction accuracy.

use std::ops::RangeInclusive;

use super::RefineError;
use super::pem::{PemOptions, refine};
use crate::identify::{IdentifyOptions, identify};
use crate::numerics::select::best;
use crate::reference::uniform_knots;

pub use crate::numerics::select::Criterion;

/// The choice and the score of every candidate.
#[derive(Clone, Debug, PartialEq)]
pub struct KnotChoice {
    /// Segments per path chosen.
    pub segments: usize,
    /// The criterion used.
    pub criterion: Criterion,
    /// `(segments, score)` of every candidate that could be identified.
    pub scores: Vec<(usize, f64)>,
    /// `(segments, reason)` of the candidates that failed.
    pub failures: Vec<(usize, String)>,
}

impl KnotChoice {
    /// One line for the command line: the choice and the scores.
    pub fn report(&self) -> String {
        let best = self
            .scores
            .iter()
            .find(|(s, _)| *s == self.segments)
            .map_or(f64::NAN, |(_, v)| *v);
        let others: Vec<String> = self
            .scores
            .iter()
            .map(|(s, v)| format!("{s}: {:+.1}", v - best))
            .collect();
        format!(
            "segments per path: {} (chosen from the data by {} of the refined model; {} relative to the best: {})",
            self.segments,
            self.criterion.name(),
            self.criterion.name(),
            others.join(", ")
        )
    }
}

/// Chooses the number of uniform segments per path among `candidates` for the record
/// `(u, y)`; `base` gives everything else (interval from its knots, horizons, hold, order).
pub fn select_segments(
    u: &[f64],
    y: &[f64],
    base: &IdentifyOptions,
    candidates: RangeInclusive<usize>,
    criterion: Criterion,
) -> Result<KnotChoice, RefineError> {
    let (lo, hi) = (base.u_min(), base.u_max());
    if !(lo.is_finite() && hi.is_finite() && lo < hi) {
        return Err(RefineError::InvalidKnots(
            "the interval [u_min, u_max] is empty",
        ));
    }
    let mut scores = Vec::new();
    let mut failures = Vec::new();
    for s in candidates {
        if s == 0 {
            continue;
        }
        let mut opts = base.clone();
        opts.knots_asc = uniform_knots(lo, hi, s);
        opts.knots_desc = opts.knots_asc.clone();
        let fit = identify(u, y, &opts)
            .map_err(RefineError::from)
            .and_then(|init| refine(u, y, &init, &PemOptions::for_identify(&opts)));
        match fit {
            Ok(f) => {
                let (n, d) = (f.samples as f64, f.parameters() as f64);
                scores.push((s, criterion.score(n, f.mse, d)));
            }
            Err(e) => failures.push((s, e.to_string())),
        }
    }
    let segments = best(&scores).ok_or_else(|| {
        RefineError::Identify(format!(
            "no candidate knot count could be identified: {}",
            failures
                .iter()
                .map(|(s, e)| format!("{s} segments: {e}"))
                .collect::<Vec<_>>()
                .join("; ")
        ))
    })?;
    Ok(KnotChoice {
        segments,
        criterion,
        scores,
        failures,
    })
}

/// `--segments`: a count, or `auto` to choose it from the data.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SegmentCount {
    /// This many uniform segments per path.
    Fixed(usize),
    /// Chosen by [`select_segments`] with BIC among [`AUTO_CANDIDATES`].
    Auto,
}

/// The candidates of [`SegmentCount::Auto`].
pub const AUTO_CANDIDATES: RangeInclusive<usize> = 2..=14;

impl std::str::FromStr for SegmentCount {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        if s.eq_ignore_ascii_case("auto") {
            return Ok(SegmentCount::Auto);
        }
        s.parse::<usize>()
            .map(SegmentCount::Fixed)
            .map_err(|_| format!("expected a number of segments or `auto`, got `{s}`"))
    }
}
