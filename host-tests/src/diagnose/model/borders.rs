//! The border values refitted by least squares for a given linear part, with the initial
//! state at rest.

use crate::identify::HostModel;
use crate::numerics::direction::directions;
use crate::numerics::hat::hat_weights;
use crate::numerics::lstsq::lstsq_min_norm;
use hsid::Direction;
use nalgebra::{DMatrix, DVector};

use super::fit_options::InitialState;

/// Least-squares initial state at rest at a level `c`: `target(t) − zero-state response =
/// c · C A^t (I − A)⁻¹ B`.
pub(super) fn estimate_x0(m: &HostModel, h: &[f64], target: &[f64], skip: &[bool]) -> Vec<f64> {
    let n = m.order;
    let zs = m.linear_response(h, &vec![0.0; n]);
    let xs = m.steady_state();
    let free = m.linear_response(&vec![0.0; h.len()], &xs);
    let (mut num, mut den) = (0.0, 0.0);
    for t in 0..target.len() {
        if !skip[t] {
            num += free[t] * (target[t] - zs[t]);
            den += free[t] * free[t];
        }
    }
    let c = if den > 0.0 { num / den } else { m.mu0 };
    xs.iter().map(|v| v * c).collect()
}

/// The output of the Hammerstein part is linear in the border values at the knots (μ0 shared
/// by both paths, A.1) and, for an estimated initial state, in `x0`, once `A, B, C, D` are
/// fixed. This is that linear map: one column per unknown, one row per sample.
pub struct BorderBasis {
    /// Columns: `ψ_c = G0[φ_c]` (zero-state responses of the hat channels; column 0 is μ0's,
    /// already combined with the rest state), then `C A^t` for an estimated initial state.
    cols: Vec<Vec<f64>>,
    /// Border unknowns (μ0, ascending knots 1…, descending knots 1…).
    borders: usize,
    /// Segments of the ascending path.
    na: usize,
    /// Segments of the descending path.
    nd: usize,
    shared: bool,
    initial: InitialState,
}

impl BorderBasis {
    /// The basis of a model for an input record.
    pub fn new(m: &HostModel, u: &[f64], initial: InitialState, shared: bool) -> Option<Self> {
        let n = u.len();
        let na = m.knots_asc.len().checked_sub(1)?;
        let nd = m.knots_desc.len().checked_sub(1)?;
        if na == 0 || nd == 0 {
            return None;
        }
        let borders = 1 + na + if shared { 0 } else { nd };
        let phi = border_channels(m, u, shared)?;
        let order = m.order;
        let zero = vec![0.0; order];
        let mut cols: Vec<Vec<f64>> = phi.iter().map(|p| m.linear_response(p, &zero)).collect();
        match initial {
            InitialState::Rest => {
                // Rest at μ0 before the record: y = μ0 (1 − Σ_{c≥1} ψ_c) + Σ_{c≥1} v_c ψ_c.
                #[allow(clippy::needless_range_loop)]
                for t in 0..n {
                    let s: f64 = (1..borders).map(|c| cols[c][t]).sum();
                    cols[0][t] = 1.0 - s;
                }
            }
            InitialState::Estimated => {
                // Free response from rest at the unit level, C A^t (I − A)⁻¹ B.
                let xs = m.steady_state();
                cols.push(m.linear_response(&vec![0.0; n], &xs));
            }
        }
        Some(Self {
            cols,
            borders,
            na,
            nd,
            shared,
            initial,
        })
    }

    /// The output for the unknowns `beta`.
    pub fn output(&self, beta: &[f64]) -> Vec<f64> {
        let n = self.cols.first().map_or(0, Vec::len);
        (0..n)
            .map(|t| self.cols.iter().zip(beta).map(|(c, b)| c[t] * b).sum())
            .collect()
    }

    /// The unknowns of a model (`x0` for an estimated initial state).
    pub(crate) fn unknowns(&self, m: &HostModel, x0: &[f64]) -> Vec<f64> {
        let mut b = vec![m.mu0];
        b.extend(m.border_asc.iter().skip(1));
        if !self.shared {
            b.extend(m.border_desc.iter().skip(1));
        }
        if self.initial == InitialState::Estimated {
            b.push(m.level_of(x0));
        }
        b
    }

    /// Weighted least squares `min Σ_t (w_t (row_t · β) − rhs_t)²` over samples not skipped.
    pub fn solve(&self, rhs: &[f64], weight: Option<&[f64]>, skip: &[bool]) -> Option<Vec<f64>> {
        let rows: Vec<usize> = (0..rhs.len()).filter(|&t| !skip[t]).collect();
        let k = self.cols.len();
        let mut x = DMatrix::<f64>::zeros(rows.len(), k);
        for (r, &t) in rows.iter().enumerate() {
            let w = weight.map_or(1.0, |w| w[t]);
            for c in 0..k {
                x[(r, c)] = w * self.cols[c][t];
            }
        }
        let y = DVector::from_iterator(rows.len(), rows.iter().map(|&t| rhs[t]));
        let beta = lstsq_min_norm(&x, &y)?;
        beta.iter()
            .all(|v| v.is_finite())
            .then(|| beta.iter().copied().collect())
    }

    /// The model with the border values of `beta`, and its initial state.
    pub fn apply(&self, m: &HostModel, beta: &[f64]) -> (HostModel, Vec<f64>) {
        let mut out = m.clone();
        out.mu0 = beta[0];
        out.border_asc = (0..=self.na)
            .map(|j| if j == 0 { beta[0] } else { beta[j] })
            .collect();
        out.border_desc = if self.shared {
            out.border_asc.clone()
        } else {
            (0..=self.nd)
                .map(|j| if j == 0 { beta[0] } else { beta[self.na + j] })
                .collect()
        };
        let x0 = match self.initial {
            InitialState::Estimated => {
                let c = beta.get(self.borders).copied().unwrap_or(0.0);
                out.steady_state().iter().map(|v| v * c).collect()
            }
            InitialState::Rest => out.rest_state(),
        };
        (out, x0)
    }
}

/// The border values refit by least squares with `A, B, C, D` fixed (Remark 5 of the paper:
/// `B` and `μ` separately once `A` and `C` are known). Returns the model with the new borders
/// and μ0, and the initial state (fitted too when estimated).
pub fn refit_borders(
    m: &HostModel,
    u: &[f64],
    target: &[f64],
    skip: &[bool],
    initial: InitialState,
    shared: bool,
) -> Option<(HostModel, Vec<f64>)> {
    let basis = BorderBasis::new(m, u, initial, shared)?;
    let beta = basis.solve(target, None, skip)?;
    Some(basis.apply(m, &beta))
}

/// `B` and `D` of the linear part given the borders and `A`, `C`: the output is linear in
/// `[B; D]` (and in `x0` when estimated; at rest the rest state `(I − A)⁻¹ B μ0` is linear in
/// `B` too). After the solve `G(1) = 1` is restored by scaling `B`, `D` down and the borders up.
pub(super) struct BdBasis {
    cols: Vec<Vec<f64>>,
    order: usize,
    initial: InitialState,
    level: f64,
}

impl BdBasis {
    pub(super) fn new(m: &HostModel, u: &[f64], x0: &[f64], initial: InitialState) -> Option<Self> {
        let n = m.order;
        // The rest level the record starts from: μ0, or the fitted level.
        let level = match initial {
            InitialState::Rest => m.mu0,
            InitialState::Estimated => m.level_of(x0),
        };
        let h = m.nonlinearity_output(u);
        let len = u.len();
        // Free response rows C A^t.
        let mut ca = vec![vec![0.0; n]; len];
        let mut v = m.c.clone();
        for row in ca.iter_mut() {
            row.copy_from_slice(&v);
            v = (0..n)
                .map(|j| (0..n).map(|i| v[i] * m.a[(i, j)]).sum())
                .collect();
        }
        let ia = DMatrix::<f64>::identity(n, n) - &m.a;
        let ia_inv = ia.try_inverse()?;
        let mut cols = Vec::with_capacity(2 * n + 1);
        for i in 0..n {
            // y_i(t) = C x(t), x(t+1) = A x(t) + e_i h(t).
            let mut x = vec![0.0; n];
            let mut col = Vec::with_capacity(len);
            for (t, &ht) in h.iter().enumerate() {
                // Plus the free response from rest: C A^t (I − A)⁻¹ e_i · level.
                let y: f64 = m.c.iter().zip(&x).map(|(c, x)| c * x).sum::<f64>()
                    + level * (0..n).map(|j| ca[t][j] * ia_inv[(j, i)]).sum::<f64>();
                col.push(y);
                let mut next: Vec<f64> = (0..n)
                    .map(|r| (0..n).map(|c| m.a[(r, c)] * x[c]).sum())
                    .collect();
                next[i] += ht;
                x = next;
            }
            cols.push(col);
        }
        cols.push(h);
        Some(Self {
            cols,
            order: n,
            initial,
            level,
        })
    }

    pub(super) fn solve(
        &self,
        rhs: &[f64],
        weight: Option<&[f64]>,
        skip: &[bool],
    ) -> Option<Vec<f64>> {
        let rows: Vec<usize> = (0..rhs.len()).filter(|&t| !skip[t]).collect();
        let k = self.cols.len();
        let x = DMatrix::from_fn(rows.len(), k, |r, c| {
            weight.map_or(1.0, |w| w[rows[r]]) * self.cols[c][rows[r]]
        });
        let y = DVector::from_iterator(rows.len(), rows.iter().map(|&t| rhs[t]));
        let beta = lstsq_min_norm(&x, &y)?;
        beta.iter()
            .all(|v| v.is_finite())
            .then(|| beta.iter().copied().collect())
    }

    pub(super) fn unknowns(&self, m: &HostModel) -> Vec<f64> {
        let mut b = m.b.clone();
        b.push(m.d);
        b
    }

    /// The model with `[B; D]` (normalised to `G(1) = 1`, the borders scaled inversely).
    pub(super) fn apply(&self, m: &HostModel, beta: &[f64]) -> Option<(HostModel, Vec<f64>)> {
        let n = self.order;
        let mut out = m.clone();
        out.b = beta[..n].to_vec();
        out.d = beta[n];
        let ia = DMatrix::<f64>::identity(n, n) - &out.a;
        let xs = ia.lu().solve(&DVector::from_column_slice(&out.b))?;
        // The initial state before normalisation: (I − A)⁻¹ B_raw · level (unchanged by it).
        let x_start: Vec<f64> = xs.iter().map(|v| v * self.level).collect();
        let gain = out.d + out.c.iter().zip(xs.iter()).map(|(c, x)| c * x).sum::<f64>();
        if !(gain.is_finite() && gain.abs() > 1e-9) {
            return None;
        }
        for v in out.b.iter_mut() {
            *v /= gain;
        }
        out.d /= gain;
        out.mu0 *= gain;
        for v in out.border_asc.iter_mut().chain(out.border_desc.iter_mut()) {
            *v *= gain;
        }
        let x0 = match self.initial {
            InitialState::Estimated => x_start,
            InitialState::Rest => out.rest_state(),
        };
        Some((out, x0))
    }
}

/// The hat channels of the borders (column 0: the knot `u_min`).
pub(super) fn border_channels(m: &HostModel, u: &[f64], shared: bool) -> Option<Vec<Vec<f64>>> {
    let na = m.knots_asc.len().checked_sub(1)?;
    let nd = m.knots_desc.len().checked_sub(1)?;
    if na == 0 || nd == 0 {
        return None;
    }
    let borders = 1 + na + if shared { 0 } else { nd };
    let mut phi = vec![vec![0.0; u.len()]; borders];
    for (t, (&ui, dir)) in u.iter().zip(directions(u, m.u_min())).enumerate() {
        let (k, off) = if dir == Direction::Ascending || shared {
            (&m.knots_asc, 0)
        } else {
            (&m.knots_desc, na)
        };
        let (s, th) = hat_weights(k, ui);
        let col = |j: usize| if j == 0 { 0 } else { off + j };
        phi[col(s)][t] += 1.0 - th;
        phi[col(s + 1)][t] += th;
    }
    Some(phi)
}
