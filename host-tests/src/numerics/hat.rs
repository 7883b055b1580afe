//! The hat (linear B-spline) basis on a knot sequence: where an input falls and the weights of
//! the two hats around it.

/// The hat weights of `u` on strictly increasing `knots`: the segment `s` with
/// `knots[s] ≤ u < knots[s + 1]` (the first segment below the knots, the last above them) and
/// `θ = (u − knots[s]) / (knots[s + 1] − knots[s])` clamped to `[0, 1]`; the hat `φ_s` has
/// weight `1 − θ`, `φ_{s+1}` weight `θ`. `(0, 0.0)` for fewer than two knots.
pub(crate) fn hat_weights(knots: &[f64], u: f64) -> (usize, f64) {
    if knots.len() < 2 {
        return (0, 0.0);
    }
    let segs = knots.len() - 1;
    let (mut lo, mut hi) = (0usize, segs);
    while hi - lo > 1 {
        let mid = lo + (hi - lo) / 2;
        if knots[mid] <= u {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let theta = ((u - knots[lo]) / (knots[lo + 1] - knots[lo])).clamp(0.0, 1.0);
    (lo, theta)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn segment_and_weight_inside_and_outside_the_knots() {
        let k = [-2.0, -1.0, 0.5, 3.0];
        assert_eq!(hat_weights(&k, -1.5), (0, 0.5));
        // On a knot: the segment it starts, weight 0.
        assert_eq!(hat_weights(&k, -1.0), (1, 0.0));
        assert_eq!(hat_weights(&k, 1.75), (2, 0.5));
        // The last knot ends the last segment; beyond the ends θ is clamped.
        assert_eq!(hat_weights(&k, 3.0), (2, 1.0));
        assert_eq!(hat_weights(&k, 9.0), (2, 1.0));
        assert_eq!(hat_weights(&k, -9.0), (0, 0.0));
        assert_eq!(hat_weights(&[1.0], 2.0), (0, 0.0));
    }

    #[test]
    fn agrees_with_a_linear_scan() {
        // The segment is the last knot at or below u, at most the last segment.
        let k = [0.0, 0.3, 0.35, 1.0, 2.5, 2.6];
        for i in 0..=300 {
            let u = -0.2 + 0.01 * f64::from(i);
            let scan = k
                .iter()
                .rposition(|&x| x <= u)
                .unwrap_or(0)
                .min(k.len() - 2);
            assert_eq!(hat_weights(&k, u).0, scan, "{u}");
        }
    }
}
