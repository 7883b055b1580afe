//! Axes in pixels: the plot rectangle, the tick positions and their labels.

use super::style::TICK_SIZE;
use super::ticks::{
    TickLabel, at_least_two_ticks, is_pow10, log_ticks, minus, nice_step, snap, tick_labels,
};

/// A closed interval `(min, max)`.
pub(super) type Span = (f64, f64);

pub(super) struct Rect {
    pub(super) x: f64,
    pub(super) y: f64,
    pub(super) w: f64,
    pub(super) h: f64,
}

impl Rect {
    pub(super) fn contains(&self, px: f64, py: f64, margin: f64) -> bool {
        px >= self.x - margin
            && px <= self.x + self.w + margin
            && py >= self.y - margin
            && py <= self.y + self.h + margin
    }
}

pub(super) struct Layout {
    pub(super) plot: Rect,
    pub(super) x: Axis,
    pub(super) y: Axis,
}

/// One axis: range in axis coordinates (log10 of the value for a log axis), tick positions in
/// axis coordinates, and labels for the major ticks.
pub(super) struct Axis {
    pub(super) lo: f64,
    pub(super) hi: f64,
    pub(super) major: Vec<f64>,
    pub(super) minor: Vec<f64>,
    pub(super) labels: Vec<TickLabel>,
}

impl Axis {
    pub(super) fn to_unit(&self, v: f64) -> f64 {
        (v - self.lo) / (self.hi - self.lo)
    }

    /// Range widened to multiples of a nice step.
    ///
    /// An end is only moved to a tick if that adds at most 8 % of the span; otherwise it stays
    /// (so [-1.02, 1.02] does not become [-1.5, 1.5]).
    pub(super) fn linear_extended(lo: f64, hi: f64, target: f64) -> Axis {
        let span = hi - lo;
        let step = nice_step(span, target);
        let mut a = snap((lo / step + 1e-9).floor() * step, step);
        let mut b = snap((hi / step - 1e-9).ceil() * step, step);
        if lo - a > 0.08 * span {
            a = lo;
        }
        if b - hi > 0.08 * span {
            b = hi;
        }
        Axis::linear_within(a, b, step)
    }

    /// Range as given, ticks at the multiples of `step` inside it.
    pub(super) fn linear_within(lo: f64, hi: f64, step: f64) -> Axis {
        let (major, step) = at_least_two_ticks(lo, hi, step);
        let labels = tick_labels(&major, step);
        Axis {
            lo,
            hi,
            major,
            minor: Vec::new(),
            labels,
        }
    }

    /// Halves the number of labelled ticks until the labels do not overlap.
    pub(super) fn thin_to_fit(mut self, px_len: f64) -> Axis {
        for _ in 0..6 {
            if self.major.len() < 3 {
                break;
            }
            let widest = self
                .labels
                .iter()
                .map(|l| l.width(TICK_SIZE))
                .fold(0.0, f64::max);
            let spacing = px_len * (self.major[1] - self.major[0]) / (self.hi - self.lo);
            if widest + 10.0 <= spacing {
                break;
            }
            let step = nice_step(2.01 * (self.major[1] - self.major[0]), 1.0);
            let (lo, hi) = (self.lo, self.hi);
            self = Axis::linear_within(lo, hi, step);
            self.lo = lo;
            self.hi = hi;
        }
        self
    }

    /// A log axis over `[lo, hi]` given as log10 values.
    pub(super) fn log(lo: f64, hi: f64, target: f64) -> Axis {
        let (ticks, minor_values) = log_ticks(10f64.powf(lo), 10f64.powf(hi), target);
        let all_pow10 = ticks.iter().all(|t| is_pow10(*t));
        let labels = ticks
            .iter()
            .map(|&t| {
                if all_pow10 {
                    TickLabel::Pow10(t.log10().round() as i32)
                } else {
                    TickLabel::Text(minus(&format!("{}", t)))
                }
            })
            .collect();
        Axis {
            lo,
            hi,
            major: ticks.iter().map(|t| t.log10()).collect(),
            minor: minor_values.iter().map(|t| t.log10()).collect(),
            labels,
        }
    }
}
