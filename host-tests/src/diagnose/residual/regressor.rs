//! The hat-basis regressor, δ and the (path, segment) bins of an input record.

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
    let mut up = false;
    let mut prev = knots_asc.first().copied().unwrap_or(0.0);
    for (t, &ui) in u.iter().enumerate() {
        if ui > prev {
            up = true;
        } else if ui < prev {
            up = false;
        }
        prev = ui;
        let (k, off) = if up || shared {
            (knots_asc, 0)
        } else {
            (knots_desc, na)
        };
        let segs = k.len().saturating_sub(1).max(1);
        let s = k
            .iter()
            .rposition(|&x| x <= ui)
            .unwrap_or(0)
            .min(segs.saturating_sub(1));
        let th = if k.len() >= 2 {
            ((ui - k[s]) / (k[s + 1] - k[s])).clamp(0.0, 1.0)
        } else {
            0.0
        };
        if s >= 1 {
            z[off + s - 1][t] = 1.0 - th;
        }
        z[off + s][t] = th;
        delta.push(if up { 1.0 } else { 0.0 });
        bins.push(off + s);
    }
    (delta, z, bins, channels)
}
