//! Inputs outside a model's interval `[u_min, u_max]`: counted ([`OutsideInterval`]), and the
//! model extended beyond it ([`Interval::extended`], [`for_input`]) — the borders continue
//! linearly on the lines through their two end knots, so a two-path model or a play keeps its
//! gap out there. The extended model starts as the model does ([`Extended`]): at rest, with
//! the input before the record at the model's own `u_min`, not at an added knot.

use crate::friction::{FrictionModel, Initial};
use crate::hysteresis::HysteresisModel;
use crate::identify::HostModel;

use super::{FileModel, Simulate};

/// How a note names the flag that refuses instead.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Syntax {
    /// The command line: `--strict-interval`.
    Cli,
    /// Python: `strict_interval=True`.
    Python,
}

/// The samples of an input record outside a model's interval.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OutsideInterval {
    /// Samples outside `[lo, hi]`.
    pub count: usize,
    /// Samples in the record.
    pub total: usize,
    /// The record's lowest input.
    pub lowest: f64,
    /// The record's highest input.
    pub highest: f64,
    /// The model's `u_min`.
    pub lo: f64,
    /// The model's `u_max`.
    pub hi: f64,
}

impl OutsideInterval {
    /// The samples of `u` outside `[lo, hi]`; `None` when every sample lies inside.
    pub fn of(u: &[f64], lo: f64, hi: f64) -> Option<Self> {
        let count = u.iter().filter(|v| **v < lo || **v > hi).count();
        (count > 0).then(|| Self {
            count,
            total: u.len(),
            lowest: u.iter().copied().fold(f64::INFINITY, f64::min),
            highest: u.iter().copied().fold(f64::NEG_INFINITY, f64::max),
            lo,
            hi,
        })
    }

    /// One line saying how many samples lie outside, how far the record goes, and that the
    /// borders are extended (the `note: ` of the command line is not part of it), e.g.
    /// `37 of 24841 samples (0.15 %) lie outside the model's interval [-4.3, 4.02] (lowest
    /// -4.48, highest 4.13): the borders are extended linearly beyond it (--strict-interval
    /// refuses instead)`.
    pub fn note(&self, syntax: Syntax) -> String {
        let percent = 100.0 * self.count as f64 / self.total.max(1) as f64;
        let verb = if self.count == 1 { "lies" } else { "lie" };
        let strict = match syntax {
            Syntax::Cli => "--strict-interval",
            Syntax::Python => "strict_interval=True",
        };
        format!(
            "{} of {} samples ({percent:.2} %) {verb} outside the model's interval [{}, {}] \
             (lowest {}, highest {}): the borders are extended linearly beyond it ({strict} \
             refuses instead)",
            self.count, self.total, self.lo, self.hi, self.lowest, self.highest
        )
    }
}

/// The index of the first sample of `u` outside `[lo, hi]` (what a strict run refuses).
pub fn first_outside(u: &[f64], lo: f64, hi: f64) -> Option<usize> {
    u.iter().position(|v| !(lo..=hi).contains(v))
}

/// A model with an input interval that it can be extended beyond.
pub trait Interval: Sized {
    /// `(u_min, u_max)`.
    fn interval(&self) -> (f64, f64);
    /// The model with a knot added at `lo` below its interval and at `hi` above it (only where
    /// they lie outside), each border's value there on the line through its two end knots.
    fn extended(&self, lo: f64, hi: f64) -> Self;
}

/// A model as it simulates a record: extended beyond its interval where the record leaves it,
/// started as the model it extends.
#[derive(Clone, Debug)]
pub struct Extended<M> {
    /// The model, with the added knots.
    pub model: M,
    /// The input before the record (the path of a first sample that does not move away from
    /// it): the `u_min` of the model before it was extended.
    pub u_start: f64,
}

/// The model that simulates `u`: a copy of `model` when `u` stays inside its interval, else
/// the model extended to the record's lowest and highest input, with the count of the samples
/// outside.
pub fn for_input<M: Interval + Clone>(
    model: &M,
    u: &[f64],
) -> (Extended<M>, Option<OutsideInterval>) {
    let (lo, hi) = model.interval();
    let (model, outside) = match OutsideInterval::of(u, lo, hi) {
        None => (model.clone(), None),
        Some(o) => (model.extended(o.lowest, o.highest), Some(o)),
    };
    (Extended { model, u_start: lo }, outside)
}

impl Simulate for Extended<HostModel> {
    fn simulate(&self, u: &[f64]) -> Vec<f64> {
        self.model.simulate_from(u, self.u_start)
    }
}

/// The play starts at its stored output, the relay on its descending border: neither looks at
/// the input before the record.
impl Simulate for Extended<HysteresisModel> {
    fn simulate(&self, u: &[f64]) -> Vec<f64> {
        crate::hysteresis::simulate::simulate(&self.model, u)
    }
}

impl Simulate for Extended<FileModel> {
    fn simulate(&self, u: &[f64]) -> Vec<f64> {
        match &self.model {
            FileModel::TwoPath(m) => m.simulate_from(u, self.u_start),
            FileModel::Element(h) => crate::hysteresis::simulate::simulate(h, u),
            FileModel::Integrating(m) => {
                crate::integrating::integrate(&m.simulate_from(u, self.u_start), 0.0)
            }
            FileModel::Friction(f) => f.simulate_from(
                u,
                Initial::Rest {
                    u_start: self.u_start,
                },
            ),
        }
    }
}

/// Border value at `u` on the line through knots `i` and `j`.
fn line_at(k: &[f64], v: &[f64], i: usize, j: usize, u: f64) -> f64 {
    v[i] + (v[j] - v[i]) * (u - k[i]) / (k[j] - k[i])
}

/// Adds a knot at `lo` (when below the first) and at `hi` (when above the last) to `knots`,
/// and to each border of `borders` (its values at `knots`) the value on its end segment's line.
fn extend(knots: &mut Vec<f64>, borders: &mut [&mut Vec<f64>], lo: f64, hi: f64) {
    let n = knots.len();
    if n < 2 || borders.iter().any(|v| v.len() != n) {
        return;
    }
    if hi > knots[n - 1] {
        for v in borders.iter_mut() {
            let y = line_at(knots, v, n - 2, n - 1, hi);
            v.push(y);
        }
        knots.push(hi);
    }
    if lo < knots[0] {
        for v in borders.iter_mut() {
            let y = line_at(knots, v, 0, 1, lo);
            v.insert(0, y);
        }
        knots.insert(0, lo);
    }
}

impl Interval for HostModel {
    fn interval(&self) -> (f64, f64) {
        (self.u_min(), self.u_max())
    }

    fn extended(&self, lo: f64, hi: f64) -> Self {
        let mut m = self.clone();
        extend(&mut m.knots_asc, &mut [&mut m.border_asc], lo, hi);
        extend(&mut m.knots_desc, &mut [&mut m.border_desc], lo, hi);
        m
    }
}

impl Interval for HysteresisModel {
    fn interval(&self) -> (f64, f64) {
        let k = &self.knots;
        (
            k.first().copied().unwrap_or(f64::NAN),
            k.last().copied().unwrap_or(f64::NAN),
        )
    }

    /// The knots are shared by both borders: the added knots too.
    fn extended(&self, lo: f64, hi: f64) -> Self {
        let mut m = self.clone();
        extend(
            &mut m.knots,
            &mut [&mut m.border_asc, &mut m.border_desc],
            lo,
            hi,
        );
        m
    }
}

impl Interval for FileModel {
    fn interval(&self) -> (f64, f64) {
        match self {
            FileModel::TwoPath(m) | FileModel::Integrating(m) => m.interval(),
            FileModel::Element(h) => h.interval(),
            FileModel::Friction(f) => f.plant.interval(),
        }
    }

    fn extended(&self, lo: f64, hi: f64) -> Self {
        match self {
            FileModel::TwoPath(m) => FileModel::TwoPath(Interval::extended(m, lo, hi)),
            FileModel::Integrating(m) => FileModel::Integrating(Interval::extended(m, lo, hi)),
            FileModel::Element(h) => FileModel::Element(h.extended(lo, hi)),
            FileModel::Friction(f) => FileModel::Friction(FrictionModel {
                plant: Interval::extended(&f.plant, lo, hi),
                ..f.clone()
            }),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_note_counts_the_samples_outside() {
        let u = [0.0, -1.5, 0.5, 1.0, 2.0, -1.0];
        let o = OutsideInterval::of(&u, -1.0, 1.0);
        assert_eq!(
            o,
            Some(OutsideInterval {
                count: 2,
                total: 6,
                lowest: -1.5,
                highest: 2.0,
                lo: -1.0,
                hi: 1.0
            })
        );
        assert_eq!(
            o.map(|o| o.note(Syntax::Cli)).unwrap_or_default(),
            "2 of 6 samples (33.33 %) lie outside the model's interval [-1, 1] (lowest -1.5, \
             highest 2): the borders are extended linearly beyond it (--strict-interval refuses \
             instead)"
        );
        assert_eq!(OutsideInterval::of(&u, -2.0, 2.0), None);
        assert_eq!(first_outside(&u, -1.0, 1.0), Some(1));
    }
}
