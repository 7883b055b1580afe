//! The backlash gap (play) and the loop height of a two-path element, by the definitions of
//! the firmware's `Model::gap_at` and `Model::loop_height` (in `hsid::Model`), on a
//! [`HostModel`]'s borders.

use hsid::Direction;

use crate::identify::HostModel;

impl HostModel {
    /// The border of path `dir`: its knots and values.
    fn path(&self, dir: Direction) -> (&[f64], &[f64]) {
        match dir {
            Direction::Ascending => (&self.knots_asc, &self.border_asc),
            Direction::Descending => (&self.knots_desc, &self.border_desc),
        }
    }

    fn border(&self, dir: Direction, u: f64) -> f64 {
        match dir {
            Direction::Ascending => self.border_asc_at(u),
            Direction::Descending => self.border_desc_at(u),
        }
    }

    /// The input `u` at which the border of `dir` takes the value `v`: the first segment whose
    /// value range holds `v` (the knot of a flat segment), `None` when no segment does.
    pub fn border_inverse(&self, dir: Direction, v: f64) -> Option<f64> {
        let (k, b) = self.path(dir);
        k.windows(2).zip(b.windows(2)).find_map(|(kk, bb)| {
            let (lo, hi) = (bb[0].min(bb[1]), bb[0].max(bb[1]));
            if v < lo || v > hi {
                None
            } else if bb[1] == bb[0] {
                Some(kk[0])
            } else {
                Some(kk[0] + (kk[1] - kk[0]) * (v - bb[0]) / (bb[1] - bb[0]))
            }
        })
    }

    /// The play at `u` after the input arrived on path `dir`: how far the input must travel back
    /// after a reversal at `u` before the element's output moves again (input units), `None` when
    /// the other border never reaches the value `P_dir(u)`.
    pub fn gap_at(&self, dir: Direction, u: f64) -> Option<f64> {
        let v = self.border(dir, u);
        let other = self.border_inverse(dir.opposite(), v)?;
        Some(match dir {
            Direction::Descending => other - u,
            Direction::Ascending => u - other,
        })
    }

    /// `P_d(u) − P_a(u)`, in the element's output units.
    pub(crate) fn loop_height(&self, u: f64) -> f64 {
        self.border_desc_at(u) - self.border_asc_at(u)
    }
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;
    use crate::units::gain::tests::first_order;

    #[test]
    fn a_symmetric_backlash_has_its_gap_after_either_reversal() {
        // On [−1, 1] (knots −1, 0, 1): P_a = 2(u − 0.25) clipped, P_d = 2(u + 0.25) clipped,
        // sampled at the knots: P_a = (−2.5, −0.5, 1.5), P_d = (−1.5, 0.5, 2.5).
        let m = first_order(0.5, 0.5, vec![-2.5, -0.5, 1.5], vec![-1.5, 0.5, 2.5]);
        for u in [-0.4, 0.0, 0.3] {
            assert!((m.gap_at(Direction::Descending, u).unwrap() - 0.5).abs() < 1e-12);
            assert!((m.gap_at(Direction::Ascending, u).unwrap() - 0.5).abs() < 1e-12);
            assert!((m.loop_height(u) - 1.0).abs() < 1e-12);
        }
        // At u_max the rising border's value 1.5 is reached by the falling one at u = 0.5.
        assert!((m.gap_at(Direction::Ascending, 1.0).unwrap() - 0.5).abs() < 1e-12);
        // After a descent to u_min, P_d = −1.5 is reached by P_a at u = −0.5.
        assert!((m.gap_at(Direction::Descending, -1.0).unwrap() - 0.5).abs() < 1e-12);
        // Beyond the borders' ranges there is no gap.
        assert_eq!(m.border_inverse(Direction::Ascending, 2.0), None);
    }
}
