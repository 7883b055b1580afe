//! The dead band of a static (one-border) element: the widest interval of inputs over which the
//! identified border is flat, so that the output does not follow the input there.
//!
//! The border is piecewise linear on its knots, so the band is a run of whole segments and its
//! ends are knots: its width is resolved to the segment width around it. A segment is flat when
//! its slope is at most [`FLAT_FRACTION`] of the border's mean slope
//! `|H(u_max) − H(u_min)| / (u_max − u_min)`.

use serde::Serialize;

/// A segment counts as flat when its slope is at most this fraction of the mean slope.
pub const FLAT_FRACTION: f64 = 0.1;

/// The widest flat interval of a border.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct DeadBand {
    /// Lower end (a knot), input units.
    pub from: f64,
    /// Upper end (a knot), input units.
    pub to: f64,
    /// Mean of the border over the band (the element's output there, before the linear part).
    pub level: f64,
}

impl DeadBand {
    /// `to − from`, input units.
    pub fn width(&self) -> f64 {
        self.to - self.from
    }
}

/// The widest run of flat segments of the border through `(knots[i], values[i])`, or `None`
/// when no segment is flat (or the border is flat everywhere: then the input has no effect,
/// which is not a dead band). Knots increase strictly (as the model file guarantees).
pub(crate) fn dead_band(knots: &[f64], values: &[f64]) -> Option<DeadBand> {
    let n = knots.len().min(values.len());
    if n < 2 {
        return None;
    }
    let mean_slope = (values[n - 1] - values[0]).abs() / (knots[n - 1] - knots[0]);
    if mean_slope.is_nan() || mean_slope <= 0.0 {
        return None;
    }
    let flat = |i: usize| {
        ((values[i + 1] - values[i]) / (knots[i + 1] - knots[i])).abs()
            <= FLAT_FRACTION * mean_slope
    };
    let mut best: Option<(usize, usize)> = None;
    let mut i = 0;
    while i + 1 < n {
        if !flat(i) {
            i += 1;
            continue;
        }
        let start = i;
        while i + 1 < n && flat(i) {
            i += 1;
        }
        let wider = best.is_none_or(|(a, b)| knots[i] - knots[start] > knots[b] - knots[a]);
        if wider {
            best = Some((start, i));
        }
    }
    let (a, b) = best?;
    if a == 0 && b == n - 1 {
        return None;
    }
    let level = values[a..=b].iter().sum::<f64>() / (b - a + 1) as f64;
    Some(DeadBand {
        from: knots[a],
        to: knots[b],
        level,
    })
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;

    #[test]
    fn a_dead_zone_on_its_knots_is_found_with_its_ends() {
        // A dead zone of ±1 on [−3, 3] with unit slope outside it.
        let knots = [-3.0, -2.0, -1.0, 0.0, 1.0, 2.0, 3.0];
        let values = [-2.0, -1.0, 0.0, 0.0, 0.0, 1.0, 2.0];
        let d = dead_band(&knots, &values).unwrap();
        assert_eq!((d.from, d.to, d.level), (-1.0, 1.0, 0.0));
        assert_eq!(d.width(), 2.0);
    }

    #[test]
    fn small_slopes_count_as_flat_and_the_widest_run_wins() {
        let knots = [0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0];
        // Mean slope 1; a flat run [1, 2] and a wider, slightly sloped run [3, 6] (slope 0.05).
        let values = [0.0, 2.0, 2.0, 3.0, 3.05, 3.1, 3.15, 7.0];
        let d = dead_band(&knots, &values).unwrap();
        assert_eq!((d.from, d.to), (3.0, 6.0));
        assert!((d.level - 3.075).abs() < 1e-12);
    }

    #[test]
    fn a_linear_or_constant_border_has_no_dead_band() {
        let knots = [0.0, 1.0, 2.0];
        assert_eq!(dead_band(&knots, &[0.0, 1.0, 2.0]), None);
        assert_eq!(dead_band(&knots, &[1.0, 1.0, 1.0]), None);
        assert_eq!(dead_band(&knots[..1], &[1.0]), None);
    }
}
