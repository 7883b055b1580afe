//! What a firmware acts on after an identification: the inverse of a border (to compensate the
//! element), the play a reversal of the input leaves (the backlash gap), and the height of the
//! loop between the two borders.
//!
//! All three read only the identified border values on their knots, so they are exact for the
//! piecewise-linear borders the model holds; how close those are to the true element is the
//! identification's accuracy.

use crate::direction::Direction;
use crate::model::Model;
use crate::scalar::Real;

impl Direction {
    /// The other path.
    pub fn opposite(self) -> Self {
        match self {
            Direction::Ascending => Direction::Descending,
            Direction::Descending => Direction::Ascending,
        }
    }
}

impl<T: Real, const M: usize, const H: usize> Model<T, M, H> {
    /// The input `u` in `[u_min, u_max]` at which the border of `dir` takes the value `v`:
    /// `P_dir(u) = v`, or `None` when the border does not reach `v` on the interval.
    ///
    /// Where the border is not one-to-one (a flat or turning stretch), the lowest such input
    /// is returned, so the inverse of a border that rises everywhere is exact and unique. This
    /// is the compensator of a backlash: to make the element's output follow `w(t)`, command
    /// `u(t) = P_a⁻¹(w(t))` while `w` rises and `P_d⁻¹(w(t))` while it falls.
    ///
    /// See [`Model::gap_at`] for an example.
    pub fn border_inverse(&self, dir: Direction, v: T) -> Option<T> {
        let k = self.knots().path(dir);
        let b = self.border_values(dir);
        for (kk, bb) in k.windows(2).zip(b.windows(2)) {
            let ([k0, k1], [b0, b1]) = (kk, bb) else {
                continue;
            };
            let (lo, hi) = if b0 <= b1 { (*b0, *b1) } else { (*b1, *b0) };
            if v < lo || v > hi {
                continue;
            }
            if b1 == b0 {
                return Some(*k0);
            }
            return Some(*k0 + (*k1 - *k0) * (v - *b0) / (*b1 - *b0));
        }
        None
    }

    /// The play at `u` after the input arrived on the path `dir`: how far the input must travel
    /// back after a reversal at `u` before the output of the element moves again.
    ///
    /// Arriving at `u` on `dir`, the element's output is `v = P_dir(u)`; after the reversal it
    /// follows the other border only once that border reaches `v`, at `u' = P_other⁻¹(v)`. The
    /// play is `u' − u` after a descent and `u − u'` after an ascent, so it is positive for a
    /// backlash (the gap, in input units) and zero for a static element. `None` when the other
    /// border does not reach `v` on `[u_min, u_max]` (near the ends of the interval).
    ///
    /// ```
    /// use hsid::{Direction, Excitation, Identifier, Knots, MuZero, Settings};
    /// use rand_core::SeedableRng;
    /// use rand_pcg::Pcg32;
    ///
    /// // A backlash of gap 0.4 (rising border u − 0.2, falling u + 0.2) before the paper's G(q),
    /// // knots where its borders bend (at rest from u_min the rising border is flat to −2.6).
    /// let asc = [-3.0, -2.6, -1.5, -0.5, 0.5, 1.5, 2.4, 3.0];
    /// let desc = [-3.0, -2.4, -1.5, -0.5, 0.5, 1.5, 2.6, 3.0];
    /// let knots = Knots::<f64, 14>::new(&asc, &desc)?;
    /// let settings = Settings::new(knots, 10, 10, MuZero::Hold { len: 300, settle: 150 });
    /// let mut id = Identifier::<f64, 14, 20>::new(settings)?;
    /// let (mut w, mut y1, mut y2, mut w1, mut w2) = (-2.8f64, -2.8, -2.8, -2.8, -2.8);
    /// for u in Excitation::<f64, _>::new(-3.0, 3.0, 300, Pcg32::seed_from_u64(1))?.take(6000) {
    ///     w = w.max(u - 0.2).min(u + 0.2);
    ///     let y = 1.8858 * y1 - 0.9048 * y2 + 0.1994 * w1 - 0.1804 * w2;
    ///     (w2, w1, y2, y1) = (w1, w, y1, y);
    ///     id.push(u, y);
    /// }
    /// let model = id.solve(&mut vec![0.0; id.workspace_len()])?;
    ///
    /// // The play after a descent to 0: the input climbs 0.4 before the output moves.
    /// let gap = model.gap_at(Direction::Descending, 0.0).unwrap();
    /// assert!((gap - 0.4).abs() < 1e-6);
    /// // The compensator: to bring the element's output up to 0.5, command 0.7.
    /// let u = model.border_inverse(Direction::Ascending, 0.5).unwrap();
    /// assert!((u - 0.7).abs() < 1e-6);
    /// // The loop is 0.4 high in output units (unit slope).
    /// assert!((model.loop_height(1.0) - 0.4).abs() < 1e-6);
    /// # Ok::<(), hsid::Error>(())
    /// ```
    pub fn gap_at(&self, dir: Direction, u: T) -> Option<T> {
        let v = self.border(dir, u);
        let other = self.border_inverse(dir.opposite(), v)?;
        Some(match dir {
            Direction::Descending => other - u,
            Direction::Ascending => u - other,
        })
    }

    /// The height of the loop at `u`: `P_d(u) − P_a(u)`, in the element's output units
    /// (positive for a backlash, whose falling border lies above its rising one).
    pub fn loop_height(&self, u: T) -> T {
        self.border(Direction::Descending, u) - self.border(Direction::Ascending, u)
    }
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use heapless::Vec;

    use crate::direction::Direction::{Ascending, Descending};
    use crate::linalg::Small;
    use crate::model::Model;
    use crate::regressor::Knots;

    /// A first-order model with the given knots and border values.
    fn model(asc: (&[f64], &[f64]), desc: (&[f64], &[f64])) -> Model<f64, 8, 2> {
        let knots = Knots::<f64, 8>::new(asc.0, desc.0).unwrap();
        let values = |v: &[f64]| Vec::<f64, 8>::from_slice(v).unwrap();
        Model {
            n: 1,
            a: Small::<f64, 2>::zeros(),
            b: [1.0, 0.0],
            c: [1.0, 0.0],
            d: 0.0,
            dc_state: [1.0, 0.0],
            mu0: asc.1[0],
            knots,
            border_asc: values(asc.1),
            border_desc: values(desc.1),
            f: 2,
            columns: 0,
            sv: [0.0; 2],
            sv_white: [0.0; 2],
        }
    }

    #[test]
    fn inverse_of_a_rising_border_is_exact_and_none_out_of_its_range() {
        let m = model(
            (&[0.0, 1.0, 3.0], &[0.0, 2.0, 4.0, 8.0]),
            (&[0.0, 3.0], &[0.0, 6.0]),
        );
        // P_a: 0 → 2 on [0, 1], 2 → 4 on [1, 3].
        assert_eq!(m.border_inverse(Ascending, 1.0), Some(0.5));
        assert_eq!(m.border_inverse(Ascending, 3.0), Some(2.0));
        assert_eq!(m.border_inverse(Ascending, 4.0), Some(3.0));
        assert_eq!(m.border_inverse(Ascending, 4.5), None);
        assert_eq!(m.border_inverse(Ascending, -0.1), None);
        // Round trip on the falling border.
        for u in [0.0, 0.7, 1.9, 3.0] {
            let v = m.border(Descending, u);
            let back = m.border_inverse(Descending, v).unwrap();
            assert!((back - u).abs() < 1e-12, "{u} -> {v} -> {back}");
        }
    }

    #[test]
    fn a_flat_stretch_inverts_to_its_lowest_input() {
        // A dead band: 0 on [−1, 1], slope 1 outside.
        let k: &[f64] = &[-2.0, -1.0, 1.0, 2.0];
        let v: &[f64] = &[-1.0, 0.0, 0.0, 1.0];
        let m = model((k, v), (k, v));
        assert_eq!(m.border_inverse(Ascending, 0.0), Some(-1.0));
        assert_eq!(m.border_inverse(Ascending, 0.5), Some(1.5));
        // A static element has no play and no loop.
        assert_eq!(m.gap_at(Descending, 1.5), Some(0.0));
        assert_eq!(m.loop_height(0.3), 0.0);
    }

    #[test]
    fn the_play_of_a_backlash_is_its_gap_after_either_reversal() {
        // Rising border 2(u − 0.25), falling 2(u + 0.25), flat at the ends of [−2, 2].
        let ka: &[f64] = &[-2.0, -1.5, 2.0];
        let va: &[f64] = &[-3.5, -3.5, 3.5];
        let kd: &[f64] = &[-2.0, 1.5, 2.0];
        let vd: &[f64] = &[-3.5, 3.5, 3.5];
        let m = model((ka, va), (kd, vd));
        for u in [-1.0, 0.0, 1.2] {
            let after_descent = m.gap_at(Descending, u).unwrap();
            let after_ascent = m.gap_at(Ascending, u).unwrap();
            assert!((after_descent - 0.5).abs() < 1e-12, "{after_descent}");
            assert!((after_ascent - 0.5).abs() < 1e-12, "{after_ascent}");
            assert!((m.loop_height(u) - 1.0).abs() < 1e-12);
        }
        // Near the top the falling border is flat at 3.5, which the rising border reaches only
        // at u_max: the play is cut short by the end of the interval.
        assert!((m.gap_at(Descending, 1.9).unwrap() - 0.1).abs() < 1e-12);
        // A value the other border never takes gives no play.
        let low = model((ka, &[-3.5, -3.5, 3.0]), (kd, vd));
        assert_eq!(low.gap_at(Descending, 1.9), None);
    }
}
