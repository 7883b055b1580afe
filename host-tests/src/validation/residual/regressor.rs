//! The hat-basis regressor, δ and the (path, segment) bins of an input record.

use hsid::Direction;

use crate::numerics::direction::directions;
use crate::numerics::hat::hat_weights;

/// Hat-basis regressor channels, δ and the (path, segment) bin of every sample.
pub fn regressor(
    u: &[f64],
    knots_asc: &[f64],
    knots_desc: &[f64],
    shared: bool,
) -> (Vec<f64>, Vec<Vec<f64>>, Vec<usize>, usize) {
    let channels = channel_count(knots_asc, knots_desc, shared);
    let mut z = vec![vec![0.0; u.len()]; channels];
    let mut delta = Vec::with_capacity(u.len());
    let mut bins = Vec::with_capacity(u.len());
    for (t, s) in samples(u, knots_asc, knots_desc, shared).enumerate() {
        for &(c, w) in &s.on {
            if w != 0.0 {
                z[c][t] = w;
            }
        }
        delta.push(s.delta);
        bins.push(s.bin);
    }
    (delta, z, bins, channels)
}

/// The regressor's channels: the segments of both paths, or of the shared one.
pub fn channel_count(knots_asc: &[f64], knots_desc: &[f64], shared: bool) -> usize {
    let na = knots_asc.len().saturating_sub(1).max(1);
    let nd = knots_desc.len().saturating_sub(1).max(1);
    if shared { na } else { na + nd }
}

/// One sample of the regressor: the (at most two) channels on with their weights (a weight
/// of 0 is off), δ and the (path, segment) bin.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RegressorSample {
    /// `(channel, weight)` of the lower and the upper hat.
    pub on: [(usize, f64); 2],
    /// δ: 1 ascending, 0 descending.
    pub delta: f64,
    /// The (path, segment) bin.
    pub bin: usize,
}

/// The regressor sample by sample, in constant memory: what [`regressor`] stores for a whole
/// record.
pub fn samples<'a>(
    u: &'a [f64],
    knots_asc: &'a [f64],
    knots_desc: &'a [f64],
    shared: bool,
) -> impl Iterator<Item = RegressorSample> + 'a {
    let na = knots_asc.len().saturating_sub(1).max(1);
    let u_start = knots_asc.first().copied().unwrap_or(0.0);
    u.iter().zip(directions(u, u_start)).map(move |(&ui, dir)| {
        let up = dir == Direction::Ascending;
        let (k, off) = if up || shared {
            (knots_asc, 0)
        } else {
            (knots_desc, na)
        };
        let (s, th) = hat_weights(k, ui);
        let lower = match s {
            0 => (off, 0.0),
            _ => (off + s - 1, 1.0 - th),
        };
        RegressorSample {
            on: [lower, (off + s, th)],
            delta: f64::from(dir.delta()),
            bin: off + s,
        }
    })
}
