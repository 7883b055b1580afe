//! Rounding levels of the solve: below them a pivot or a residual cannot be told from the
//! rounding of the sums and of the factorisations.

use super::layout::Layout;
use crate::accumulation::OutputRounding;
use crate::linalg::{at, packed};
use crate::scalar::Real;

/// The relative rounding levels of one solve.
#[derive(Clone, Copy, Debug)]
pub(super) struct Rounding<T> {
    /// Effective columns `j` (with forgetting `Σλ^i`).
    pub j_eff: f64,
    /// For the input sums (always recursive) and anything that mixes them in.
    pub level: T,
    /// For what only the sums of products with the output carry.
    pub level_y: T,
}

impl<T: Real> Rounding<T> {
    /// The levels for `j_eff` effective columns, factorisations of dimension `dim` and the
    /// output sums' rounding.
    pub(super) fn new(j_eff: f64, dim: usize, output_rounding: OutputRounding) -> Self {
        let level = rounding_level::<T>(j_eff, dim);
        let level_y = match output_rounding {
            OutputRounding::Recursive => level,
            OutputRounding::Compensated => rounding_level::<T>(4.0, dim),
        };
        Self {
            j_eff,
            level,
            level_y,
        }
    }

    /// Rounding floors of the rows that may be singular (`Ȳ_p`, `Ȳ_f`: rows `pm .. q` of the
    /// packed `schur`, `q − pm = py + f <= p + f <= K` of them): their raw Gram diagonals times
    /// the level.
    pub(super) fn input_floors<const K: usize>(&self, schur: &[T], pm: usize, q: usize) -> [T; K] {
        let mut floor = [T::zero(); K];
        for (i, fl) in floor.iter_mut().enumerate().take(q - pm) {
            let r = pm + i;
            *fl = self.level * at(schur, packed(r, r)).abs();
        }
        floor
    }

    /// Rounding level of the residual `L₃₃L₃₃ᵀ = S₃₃ − L₃₂L₃₂ᵀ`, row by row, from the factored
    /// `schur` and the raw diagonals `g` of `[Z_p; Ȳ_p; Ȳ_f]`, `dof` the residual's degrees of
    /// freedom: `(res_floor, white_floor)`.
    ///
    /// The row's own (level · raw diagonal), plus what L₃₂ inherits from the pivots d_i of the
    /// instruments: d_i² carries an error of level · g_i (g_i its raw diagonal), so column i
    /// of L₃₂ a relative error of level · g_i / d_i², and the row's residual
    /// 2 Σ_i L₃₂\[r,i\]² times that. Past outputs that the inputs nearly explain (high SNR)
    /// have small pivots and make this large where the row leans on them. Besides, each entry
    /// L₃₂\[r,i\] carries an absolute rounding error of about level · √(g_r g_i) / d_i, which
    /// looks like noise to the whitening: its floor for L₃₃'s row is also the residual that
    /// noise of that size would leave (dof/w times the mean squared error of the row). Below
    /// `res_floor` a residual is rounding (the CVA weighting is then singular), below
    /// `white_floor` the whitening cannot tell noise from rounding.
    pub(super) fn residual_floors<const H: usize>(
        &self,
        schur: &[T],
        g: &[T],
        lay: Layout,
        dof: f64,
    ) -> ([T; H], [T; H]) {
        let (f, w) = (lay.f, lay.w());
        let mut g_y = [T::zero(); H];
        let mut e = [T::zero(); H];
        let mut noise = [T::zero(); H];
        for (r, ((gy, e), noise)) in g_y
            .iter_mut()
            .zip(e.iter_mut())
            .zip(noise.iter_mut())
            .enumerate()
            .take(f)
        {
            let row = packed(w + r, 0);
            *gy = at(g, w + r);
            for (i, &gi) in g.iter().enumerate().take(w) {
                let d = at(schur, packed(i, i));
                if d > T::zero() {
                    let l = at(schur, row + i) / d;
                    *e += (l + l) * l * gi;
                    *noise += gi / (d * d);
                }
            }
        }
        self.floors(&g_y, &e, &noise, dof, lay)
    }

    /// The floors of [`residual_floors`](Self::residual_floors) from, per output row, its raw
    /// diagonal `g_y`, `e = Σ_i 2 (L₃₂[r,i] / d_i)² g_i` and `noise = Σ_i g_i / d_i²`.
    pub(super) fn floors<const H: usize>(
        &self,
        g_y: &[T; H],
        e: &[T; H],
        noise: &[T; H],
        dof: f64,
        lay: Layout,
    ) -> ([T; H], [T; H]) {
        let (level, level_y) = (self.level, self.level_y);
        let per_col = T::of(dof / lay.w() as f64);
        let mut res_floor = [T::zero(); H];
        let mut white_floor = [T::zero(); H];
        let rows = g_y.iter().zip(e).zip(noise).take(lay.f);
        for ((v, wf), ((&gr, &e), &noise)) in
            res_floor.iter_mut().zip(white_floor.iter_mut()).zip(rows)
        {
            // The row's own diagonal and the cross products are output sums; the pivots d_i
            // come from the input sums.
            *v = level_y * gr + level * e;
            *wf = v.max(level_y * level_y * gr * noise * per_col);
        }
        (res_floor, white_floor)
    }
}

/// Relative rounding level of the Gram entries and of what is computed from them, for sums
/// over `j` (effective) columns and factorisations of dimension `dim`: recursive summation
/// leaves a relative error of about `ε·√j` in each sum, the Schur complement and the
/// Cholesky factorisation about `ε·dim` more. A residual variance below this level times
/// its row's Gram diagonal cannot be told from rounding.
fn rounding_level<T: Real>(j: f64, dim: usize) -> T {
    T::EPS * T::of(libm::sqrt(j.max(1.0)) + libm::sqrt(dim as f64))
}
