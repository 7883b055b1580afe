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
    let na = knots_asc.len().saturating_sub(1).max(1);
    let nd = knots_desc.len().saturating_sub(1).max(1);
    let channels = if shared { na } else { na + nd };
    let mut z = vec![vec![0.0; u.len()]; channels];
    let mut delta = Vec::with_capacity(u.len());
    let mut bins = Vec::with_capacity(u.len());
    let u_start = knots_asc.first().copied().unwrap_or(0.0);
    for (t, (&ui, dir)) in u.iter().zip(directions(u, u_start)).enumerate() {
        let up = dir == Direction::Ascending;
        let (k, off) = if up || shared {
            (knots_asc, 0)
        } else {
            (knots_desc, na)
        };
        let (s, th) = hat_weights(k, ui);
        if s >= 1 {
            z[off + s - 1][t] = 1.0 - th;
        }
        z[off + s][t] = th;
        delta.push(f64::from(dir.delta()));
        bins.push(off + s);
    }
    (delta, z, bins, channels)
}
