//! The identified Hammerstein model, simulated piece by piece: the delayed input, the input
//! nonlinearity's output, the linear response and the states at rest.

use nalgebra::{DMatrix, DVector};

use hsid::Direction;

use crate::identify::HostModel;
use crate::numerics::direction::directions;

/// The input delayed by `d` samples, the first value repeated in front.
pub fn delay_input(u: &[f64], d: usize) -> Vec<f64> {
    let n = u.len();
    if d == 0 || n == 0 {
        return u.to_vec();
    }
    let mut v = vec![u[0]; d.min(n)];
    v.extend_from_slice(&u[..n - d.min(n)]);
    v
}

impl HostModel {
    /// The output of the identified input nonlinearity for an input record: `P_a(u)` while the
    /// input rises, `P_d(u)` while it falls (δ starts descending, the previous input at `u_min`).
    pub fn nonlinearity_output(&self, u: &[f64]) -> Vec<f64> {
        u.iter()
            .zip(directions(u, self.u_min()))
            .map(|(&ui, dir)| match dir {
                Direction::Ascending => self.border_asc_at(ui),
                Direction::Descending => self.border_desc_at(ui),
            })
            .collect()
    }
    /// The response of `G` to `h` from the state `x0`.
    pub fn linear_response(&self, h: &[f64], x0: &[f64]) -> Vec<f64> {
        self.respond(h, x0, None)
    }

    /// [`linear_response`](Self::linear_response) against end stops: where the next state's
    /// output (with the present input's direct term) would pass `upper` (`lower`), the state
    /// is set at rest at that level, `(I − A)⁻¹ B ℓ` (`G(1) = 1`): a drive held at a mechanical
    /// stop, which leaves it as soon as the push turns.
    pub fn linear_response_held(
        &self,
        h: &[f64],
        x0: &[f64],
        upper: Option<f64>,
        lower: Option<f64>,
    ) -> Vec<f64> {
        let steady = self.steady_state();
        self.respond(h, x0, Some((&steady, upper, lower)))
    }

    /// The state recursion, the state set at rest at a stop's level (`steady` times the level)
    /// where `stops` has one the next output passes.
    fn respond(
        &self,
        h: &[f64],
        x0: &[f64],
        stops: Option<(&[f64], Option<f64>, Option<f64>)>,
    ) -> Vec<f64> {
        let n = self.order;
        let mut x: Vec<f64> = x0
            .iter()
            .copied()
            .chain(std::iter::repeat(0.0))
            .take(n)
            .collect();
        let mut next = vec![0.0; n];
        let out = |x: &[f64], hi: f64| {
            self.d * hi + self.c.iter().zip(x).map(|(c, x)| c * x).sum::<f64>()
        };
        h.iter()
            .map(|&hi| {
                let y = out(&x, hi);
                for (i, nx) in next.iter_mut().enumerate() {
                    *nx = self.b[i] * hi + (0..n).map(|j| self.a[(i, j)] * x[j]).sum::<f64>();
                }
                if let Some((steady, upper, lower)) = stops {
                    let ahead = out(&next, hi);
                    let at = match (upper, lower) {
                        (Some(l), _) if ahead > l => Some(l),
                        (_, Some(l)) if ahead < l => Some(l),
                        _ => None,
                    };
                    if let Some(l) = at {
                        for (nx, s) in next.iter_mut().zip(steady) {
                            *nx = s * l;
                        }
                    }
                }
                std::mem::swap(&mut x, &mut next);
                y
            })
            .collect()
    }

    /// The state at rest at `u_min`: `(I − A)⁻¹ B μ0`.
    pub(crate) fn rest_state(&self) -> Vec<f64> {
        let n = self.order;
        let ia = DMatrix::<f64>::identity(n, n) - &self.a;
        let b = DVector::from_column_slice(&self.b) * self.mu0;
        ia.lu()
            .solve(&b)
            .map_or_else(|| vec![0.0; n], |x| x.iter().copied().collect())
    }
    /// The state at rest at the unit level: `(I − A)⁻¹ B`.
    pub(crate) fn steady_state(&self) -> Vec<f64> {
        let n = self.order;
        let ia = DMatrix::<f64>::identity(n, n) - &self.a;
        ia.lu()
            .solve(&DVector::from_column_slice(&self.b))
            .map_or_else(|| vec![0.0; n], |x| x.iter().copied().collect())
    }
    /// The level `c` of a state at rest, `x0 = (I − A)⁻¹ B c` (least squares).
    pub(crate) fn level_of(&self, x0: &[f64]) -> f64 {
        let xs = self.steady_state();
        let nn: f64 = xs.iter().map(|v| v * v).sum();
        if nn <= 0.0 {
            return 0.0;
        }
        xs.iter().zip(x0).map(|(a, b)| a * b).sum::<f64>() / nn
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn first_order() -> HostModel {
        HostModel::first_order_for_tests()
    }

    #[test]
    fn a_response_held_at_a_stop_rests_there_and_leaves_when_the_push_turns() {
        let m = first_order();
        // A step to 1 for 10 samples, then to -1: free, the output rises as 1 − 0.5^t; held at
        // 0.6, it rests at 0.6 from the first sample that would pass it (0.75 at t = 2) and
        // falls from there when the input turns, as a first-order response from rest at 0.6.
        let h: Vec<f64> = (0..20).map(|t| if t < 10 { 1.0 } else { -1.0 }).collect();
        let free = m.linear_response(&h, &[0.0]);
        let held = m.linear_response_held(&h, &[0.0], Some(0.6), None);
        assert!((free[2] - 0.75).abs() < 1e-12, "{free:?}");
        assert!((held[1] - 0.5).abs() < 1e-12, "{held:?}");
        for (t, y) in held.iter().enumerate().take(11).skip(2) {
            assert!((y - 0.6).abs() < 1e-12, "t = {t}: {held:?}");
        }
        // After the turn: y(t) = −1 + 1.6 · 0.5^(t − 10) from t = 10.
        for (t, y) in held.iter().enumerate().skip(11) {
            let want = -1.0 + 1.6 * 0.5f64.powi(t as i32 - 10);
            assert!((y - want).abs() < 1e-12, "t = {t}: {y} against {want}");
        }
        // Without stops the held response is the free one.
        assert_eq!(m.linear_response_held(&h, &[0.0], None, None), free);
    }
}
