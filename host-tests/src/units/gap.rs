//! The backlash gap (play) and the loop height of a two-path element, by the definitions of
//! the firmware's `Model::gap_at` and `Model::loop_height` (in `hsid::Model`), on a
//! [`HostModel`]'s borders.

use hsid::Direction;
use nalgebra::DMatrix;

use super::report::GAP_POINTS;
use crate::identify::HostModel;
use crate::model_file::ModelStd;

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

    /// The mean gap of the report ([`UnitReport::mean_gap`](super::UnitReport::mean_gap)):
    /// the mean of the defined gaps [`gap_at`](Self::gap_at) after an ascent and after a
    /// descent at the [`GAP_POINTS`] interior points of `GAP_POINTS + 1` equal parts of
    /// `[u_min, u_max]` (input units); `None` when none is defined.
    pub fn mean_gap(&self) -> Option<f64> {
        let (lo, hi) = (self.u_min(), self.u_max());
        let defined: Vec<f64> = (1..=GAP_POINTS)
            .flat_map(|k| {
                let u = lo + (hi - lo) * k as f64 / (GAP_POINTS + 1) as f64;
                [
                    self.gap_at(Direction::Descending, u),
                    self.gap_at(Direction::Ascending, u),
                ]
            })
            .flatten()
            .collect();
        (!defined.is_empty()).then(|| defined.iter().sum::<f64>() / defined.len() as f64)
    }

    /// The standard deviation of [`mean_gap`](Self::mean_gap) for the covariance `cov` of the
    /// border values, ordered as `border_asc` then `border_desc` (a square matrix of their
    /// total length), propagated to first order
    /// ([`border_functional_std`](Self::border_functional_std)). `None` when the mean gap is not defined, when `cov` has
    /// another size, or when a step leaves the gap undefined.
    pub fn mean_gap_std(&self, cov: &DMatrix<f64>) -> Option<f64> {
        self.border_functional_std(cov, HostModel::mean_gap)
    }

    /// The standard deviation of [`gap_at`](Self::gap_at)`(dir, u)` for the covariance `cov`
    /// of the border values, as for [`mean_gap_std`](Self::mean_gap_std).
    pub fn gap_std_at(&self, dir: Direction, u: f64, cov: &DMatrix<f64>) -> Option<f64> {
        self.border_functional_std(cov, |m| m.gap_at(dir, u))
    }

    /// The standard deviation of `f(self)` for the covariance `cov` of the border values
    /// (`border_asc` then `border_desc`), to first order: `√(gᵀ cov g)` with `g` the gradient
    /// of `f` in the border values by central differences. `None` when `f(self)` is not
    /// defined, when `cov` has another size, or when a step leaves `f` undefined.
    pub fn border_functional_std(
        &self,
        cov: &DMatrix<f64>,
        f: impl Fn(&HostModel) -> Option<f64>,
    ) -> Option<f64> {
        let (na, nd) = (self.border_asc.len(), self.border_desc.len());
        if cov.nrows() != na + nd || cov.ncols() != na + nd {
            return None;
        }
        f(self)?;
        let scale = self
            .border_asc
            .iter()
            .chain(&self.border_desc)
            .fold(0.0_f64, |m, v| m.max(v.abs()))
            .max(f64::MIN_POSITIVE);
        let h = 1e-6 * scale;
        let mut grad = Vec::with_capacity(na + nd);
        for i in 0..na + nd {
            let moved = |d: f64| {
                let mut m = self.clone();
                match i.checked_sub(na) {
                    None => m.border_asc[i] += d,
                    Some(j) => m.border_desc[j] += d,
                }
                f(&m)
            };
            grad.push((moved(h)? - moved(-h)?) / (2.0 * h));
        }
        let g = nalgebra::DVector::from_vec(grad);
        Some((g.transpose() * cov * &g)[(0, 0)].max(0.0).sqrt())
    }

    /// The covariance of the border values (`border_asc` then `border_desc`) that a model
    /// file's standard deviations `std` give: their squares on the diagonal and, the two
    /// borders starting at the same parameter μ0, full correlation of their first values; the
    /// file holds no covariance between other values, so it is taken as zero. `None` when
    /// `std`'s lengths are not the borders'.
    pub fn border_covariance_of_std(&self, std: &ModelStd) -> Option<DMatrix<f64>> {
        let (na, nd) = (self.border_asc.len(), self.border_desc.len());
        if std.border_asc.len() != na || std.border_desc.len() != nd || na == 0 || nd == 0 {
            return None;
        }
        let sd: Vec<f64> = std
            .border_asc
            .iter()
            .chain(&std.border_desc)
            .copied()
            .collect();
        let mut cov = DMatrix::from_diagonal(&nalgebra::DVector::from_iterator(
            na + nd,
            sd.iter().map(|s| s * s),
        ));
        cov[(0, na)] = sd[0] * sd[na];
        cov[(na, 0)] = sd[0] * sd[na];
        Some(cov)
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

    #[test]
    fn the_mean_gap_std_is_the_change_along_the_covariance_direction() {
        // Uneven borders, so that every value moves the mean gap differently.
        let m = first_order(0.5, 0.5, vec![-2.5, -0.7, 1.5], vec![-2.5, 0.4, 2.2]);
        let g0 = m.mean_gap().unwrap();
        // For cov = δ δᵀ the standard deviation is |g·δ|, the mean gap's rate of change along
        // δ: measured here by a finite difference of the whole mean gap.
        let delta = [0.0, 0.03, -0.02, 0.0, 0.05, 0.01];
        let cov = DMatrix::from_fn(6, 6, |i, j| delta[i] * delta[j]);
        let moved = |e: f64| {
            let mut p = m.clone();
            for i in 0..3 {
                p.border_asc[i] += e * delta[i];
                p.border_desc[i] += e * delta[3 + i];
            }
            p.mean_gap().unwrap()
        };
        let rate = (moved(1e-3) - moved(-1e-3)) / 2e-3;
        let std = m.mean_gap_std(&cov).unwrap();
        assert!(
            rate.abs() > 1e-3 && (std - rate.abs()).abs() < 1e-4 * rate.abs(),
            "{std} {rate} {g0}"
        );
        // A covariance of the wrong size gives none.
        assert_eq!(m.mean_gap_std(&DMatrix::zeros(5, 5)), None);
        // The file's standard deviations: squares on the diagonal, μ0 shared by both borders.
        let std = ModelStd {
            poles: vec![],
            mu0: 0.1,
            border_asc: vec![0.1, 0.2, 0.3],
            border_desc: vec![0.1, 0.4, 0.5],
            mean_gap: None,
        };
        let c = m.border_covariance_of_std(&std).unwrap();
        assert!((c[(4, 4)] - 0.16).abs() < 1e-15 && (c[(0, 3)] - 0.01).abs() < 1e-15);
        assert_eq!(c[(1, 4)], 0.0);
    }
}
