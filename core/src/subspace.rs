//! PI-MOESP (eq. 11) from the accumulated Gram: the projection, its SVD and the order.
//!
//! With `M = [Z_f; Z_p; Ȳ_f] = L Q` (LQ factorisation) the projection of eq. (11) is
//! `O_f = Ȳ_f Φᵀ(ΦΦᵀ)⁻¹Φ Π⊥_{Z_f} = L₃₂ Q₂`, so `O_f` and `L₃₂` have the same singular values
//! and left singular vectors. `L` is the Cholesky factor of `M Mᵀ`, which the accumulator
//! provides block by block; `Q` is never formed. The SVD of the `f × p·m` block `L₃₂` is taken
//! through the QR of `L₃₂ᵀ`, leaving an `f × f` SVD.
//!
//! **Order selection** ([`Order::Auto`]): the residual block `L₃₃` estimates the part of `Ȳ_f`
//! that no input explains. Whitening `L₃₂` with it, `W = √((j − d)/(p·m)) · L₃₃⁻¹ L₃₂`
//! (`d = (f+p)·m`), gives singular values near 1 for directions that carry only noise
//! (between `1 ± √(f/(p·m))`, the Marchenko–Pastur edges for an `f × p·m` noise matrix) and
//! far above 1 for directions that carry state. The order is the number of whitened singular
//! values above [`AUTO_ORDER_MARGIN`] times the upper edge, capped at `f − 1`.

use crate::MAX_HORIZON;
use crate::accumulation::{Accumulator, RowSums};
use crate::error::{Error, Stage};
use crate::linalg::{Small, cholesky_packed, dot, householder_qr, packed, packed_len, svd_small};
use crate::regressor::{Basis, Knots};
use crate::scalar::Real;

/// How the model order is chosen.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Order {
    /// From the whitened singular values (see the [module docs](self)).
    #[default]
    Auto,
    /// Given by the user (`1 <= n < f`).
    Fixed(usize),
}

/// Margin over the noise-only edge `1 + √(f/(p·m))` that a whitened singular value must clear
/// to count as a state direction in [`Order::Auto`].
pub const AUTO_ORDER_MARGIN: f64 = 1.5;

/// Columns of `[Z_p; Ȳ_f]` processed per block when the Schur complement is formed: the
/// workspace holds two blocks of `L₁₁⁻¹ G_{f,·}` instead of the whole cross Gram.
pub const SCHUR_BLOCK: usize = 32;

/// Layout of the solve workspace for `m` channels and horizons `f`, `p`:
/// `[L₁₁ (packed f·m) | S (packed p·m + f) | B_f (f × f·m) | two column blocks | scratch]`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Layout {
    pub m: usize,
    pub f: usize,
    pub p: usize,
    /// Columns per block of the Schur complement (at least 1, at most `q`).
    pub block: usize,
}

impl Layout {
    /// Rows of `Φ = [Z_f; Z_p]`.
    pub const fn d(&self) -> usize {
        (self.f + self.p) * self.m
    }
    /// Rows of `Z_f`.
    pub const fn fm(&self) -> usize {
        self.f * self.m
    }
    /// Rows of `[Z_p; Ȳ_f]`, the block that stays after `Z_f` is eliminated.
    pub const fn q(&self) -> usize {
        self.p * self.m + self.f
    }
    /// A layout with the default block width ([`SCHUR_BLOCK`], or `q` if smaller).
    pub const fn new(m: usize, f: usize, p: usize) -> Self {
        Self::with_block(m, f, p, SCHUR_BLOCK)
    }
    /// A layout with the given block width, clamped to `1 ..= q`.
    pub const fn with_block(m: usize, f: usize, p: usize, block: usize) -> Self {
        let q = p * m + f;
        let b = if block > q { q } else { block };
        Self {
            m,
            f,
            p,
            block: if b == 0 { 1 } else { b },
        }
    }
    /// The widest block that fits in `len` scalars, if any.
    pub fn fitting(self, len: usize) -> Option<Self> {
        let fixed = self.total() - self.cache();
        let per = 2 * self.fm();
        let b = len.checked_sub(fixed)? / per.max(1);
        (b >= 1).then(|| Self::with_block(self.m, self.f, self.p, b))
    }
    /// Columns per block of the Schur complement.
    pub const fn block(&self) -> usize {
        self.block
    }
    /// Packed `L₁₁`.
    pub const fn lff(&self) -> usize {
        packed_len(self.fm())
    }
    /// Packed Schur complement, then its Cholesky factor.
    pub const fn schur(&self) -> usize {
        packed_len(self.q())
    }
    /// Length of `B_f = L₃₁ L₁₁⁻¹` (`f × f·m`).
    pub const fn bf(&self) -> usize {
        self.f * self.fm()
    }
    /// Two column blocks of `L₁₁⁻¹ G_{f,·}`.
    pub const fn cache(&self) -> usize {
        2 * self.block() * self.fm()
    }
    /// Scratch for the QR/least-squares steps.
    pub const fn scratch(&self) -> usize {
        let (f, m, p) = (self.f, self.m, self.p);
        let a = p * m * f + f;
        let b = f * f * (f + m + 1) + f;
        let c = m * f + m + f;
        let ab = if a > b { a } else { b };
        if ab > c { ab } else { c }
    }
    /// Whole workspace.
    pub const fn total(&self) -> usize {
        self.lff() + self.schur() + self.bf() + self.cache() + self.scratch()
    }
    /// Row of channel `c` of block row `a` of `z` in `[Z_f; Z_p; Ȳ_f]`.
    #[inline]
    pub fn z_row(&self, a: usize, c: usize) -> usize {
        if a >= self.p {
            (a - self.p) * self.m + c
        } else {
            self.f * self.m + a * self.m + c
        }
    }
    /// Row of `ȳ` in block row `a`, if it belongs to `Ȳ_f`.
    #[inline]
    pub fn y_row(&self, a: usize) -> Option<usize> {
        (a >= self.p).then(|| self.d() + (a - self.p))
    }
}

/// Scalars the solve workspace needs for `m` channels and horizons `f`, `p` with the default
/// block width [`SCHUR_BLOCK`]: size a static array with it, e.g.
/// `[0.0f32; hsid::workspace_len(14, 10, 10)]`.
///
/// The solve adapts to the workspace it is given: less (down to
/// [`workspace_len_with_block`]`(m, f, p, 1)`) saves memory and costs passes over the lagged
/// sums, more (up to block `p·m + f`) saves time.
pub const fn workspace_len(m: usize, f: usize, p: usize) -> usize {
    Layout::new(m, f, p).total()
}

/// Scalars the solve workspace needs with a Schur-complement block of `block` columns.
pub const fn workspace_len_with_block(m: usize, f: usize, p: usize, block: usize) -> usize {
    Layout::with_block(m, f, p, block).total()
}

/// The outcome of the PI-MOESP step.
#[derive(Clone, Debug)]
pub(crate) struct Projection<T> {
    /// Hankel columns.
    pub j: u64,
    /// Singular values of `O_f / √j`, descending (first `f` valid).
    pub sv: [T; MAX_HORIZON],
    /// Whitened singular values (order selection), descending.
    pub sv_white: [T; MAX_HORIZON],
    /// Left singular vectors of `O_f` (`f × f`).
    pub u: Small<T>,
}

/// Visits every entry `(r, c, v)`, `r >= c`, of the Gram of `[Z_f; Z_p; Ȳ_f]` (rows centred
/// if `sums` is given), block by block from the accumulator.
fn for_each_entry<T: Real, const M: usize, const K: usize>(
    acc: &Accumulator<T, M, K>,
    knots: &Knots<T, M>,
    basis: Basis,
    lay: Layout,
    sums: Option<&RowSums<T, M, K>>,
    want: impl Fn(usize, usize) -> bool,
    mut sink: impl FnMut(usize, usize, T),
) {
    let m = lay.m;
    let inv_j = T::one() / T::of(acc.columns().max(1) as f64);
    let mut put = |ra: usize, rb: usize, v: T| sink(ra.max(rb), ra.min(rb), v);
    acc.for_each_block_where(knots, basis, want, |a, b, blk| {
        let mut blk = *blk;
        if let Some(s) = sums {
            let (za, zb, ya, yb) = (s.z[a], s.z[b], s.y[a] * inv_j, s.y[b] * inv_j);
            for (row, &zi) in blk.zz.iter_mut().zip(&za) {
                let zi = zi * inv_j;
                for (v, &zj) in row.iter_mut().zip(&zb) {
                    *v -= zi * zj;
                }
            }
            for (v, &zi) in blk.zy.iter_mut().zip(&za) {
                *v -= zi * yb;
            }
            for (v, &zj) in blk.yz.iter_mut().zip(&zb) {
                *v -= ya * zj;
            }
            blk.yy -= ya * s.y[b];
        }
        for (i, row) in blk.zz.iter().enumerate().take(m) {
            let ra = lay.z_row(a, i);
            for (jj, &v) in row.iter().enumerate().take(m) {
                put(ra, lay.z_row(b, jj), v);
            }
            if let Some(rb) = lay.y_row(b) {
                put(ra, rb, blk.zy[i]);
            }
        }
        if let Some(ra) = lay.y_row(a) {
            for (jj, &v) in blk.yz.iter().enumerate().take(m) {
                put(ra, lay.z_row(b, jj), v);
            }
            if let Some(rb) = lay.y_row(b) {
                put(ra, rb, blk.yy);
            }
        }
    });
}

/// Columns `c0 .. c0 + width` of `X = L₁₁⁻¹ G_{Z_f, [Z_p; Ȳ_f]}` into `out` (column-major,
/// leading dimension `f·m`): one pass over the Gram, then forward substitution.
#[allow(clippy::too_many_arguments)]
fn cross_block<T: Real, const M: usize, const K: usize>(
    acc: &Accumulator<T, M, K>,
    knots: &Knots<T, M>,
    basis: Basis,
    lay: Layout,
    sums: Option<&RowSums<T, M, K>>,
    lff: &[T],
    c0: usize,
    width: usize,
    out: &mut [T],
) {
    let (fm, p, m) = (lay.fm(), lay.p, lay.m);
    let pm = p * m;
    let in_range = |col: usize| col >= c0 && col < c0 + width;
    // Block rows whose Z_p channels, or whose ȳ (in Ȳ_f), fall in the wanted columns.
    let zp = |b: usize| b < p && c0 < (b + 1) * m && b * m < c0 + width;
    let yf = |a: usize| a >= p && in_range(pm + a - p);
    let want = |x: usize, y: usize| (x < p && y >= p && zp(x)) || (x >= p && (yf(x) || yf(y)));
    for_each_entry(acc, knots, basis, lay, sums, want, |r, c, v| {
        // r >= c: the Z_f row is c, the [Z_p; Ȳ_f] column is r − fm.
        if c < fm && r >= fm {
            let col = r - fm;
            if in_range(col) {
                out[(col - c0) * fm + c] = v;
            }
        }
    });
    for x in out.chunks_exact_mut(fm).take(width) {
        for i in 0..fm {
            let row = packed(i, 0);
            let s = x[i] - dot(&lff[row..row + i], &x[..i]);
            x[i] = s / lff[row + i];
        }
    }
}

/// PI-MOESP from the accumulated Gram: `L₁₁`, the Schur complement of `[Z_p; Ȳ_f]` given
/// `Z_f` (whose Cholesky factor holds `L₂₂`, `L₃₂`, `L₃₃`), `B_f = L₃₁L₁₁⁻¹`, and the SVD of
/// `L₃₂`. The cross block `G_{Z_f,[Z_p; Ȳ_f]}` is never stored whole: it is regenerated from
/// the lagged sums block of columns by block of columns, which keeps the workspace near
/// `(f·m)²/2 + (p·m + f)²/2` instead of `((f + p)·m + f)²/2`.
pub(crate) fn pi_moesp<T: Real, const M: usize, const K: usize>(
    acc: &Accumulator<T, M, K>,
    knots: &Knots<T, M>,
    basis: Basis,
    lay: Layout,
    centred: bool,
    ws: &mut [T],
) -> Result<Projection<T>, Error> {
    let (f, m) = (lay.f, lay.m);
    let (fm, q, pm, d) = (lay.fm(), lay.q(), lay.p * m, lay.d());
    let (lff, rest) = ws.split_at_mut(lay.lff());
    let (schur, rest) = rest.split_at_mut(lay.schur());
    let (bf, rest) = rest.split_at_mut(lay.bf());
    let (cache, scratch) = rest.split_at_mut(lay.cache());
    let sums = centred.then(|| acc.row_sums(knots, basis));
    let sums = sums.as_ref();

    // 1. G_{Z_f Z_f} and G_{QQ} (Q = [Z_p; Ȳ_f]) in one pass.
    for_each_entry(
        acc,
        knots,
        basis,
        lay,
        sums,
        |_, _| true,
        |r, c, v| {
            if r < fm {
                lff[packed(r, c)] = v;
            } else if c >= fm {
                schur[packed(r - fm, c - fm)] = v;
            }
        },
    );
    let tol = T::EPS * T::of_usize(8 * (d + f));
    cholesky_packed(lff, fm, fm, tol).map_err(|_| Error::RankDeficient {
        stage: Stage::InputHankel,
    })?;

    // 2. S = G_QQ − XᵀX with X = L₁₁⁻¹ G_{Z_f Q}, by blocks of columns.
    let bw = lay.block();
    let nb = q.div_ceil(bw);
    let (xa, xb) = cache.split_at_mut(bw * fm);
    for jb in 0..nb {
        let (j0, jw) = (jb * bw, bw.min(q - jb * bw));
        cross_block(acc, knots, basis, lay, sums, lff, j0, jw, xa);
        for ib in 0..=jb {
            let (i0, iw) = (ib * bw, bw.min(q - ib * bw));
            let xi: &[T] = if ib == jb {
                xa
            } else {
                cross_block(acc, knots, basis, lay, sums, lff, i0, iw, xb);
                xb
            };
            for cj in 0..jw {
                let colj = &xa[cj * fm..(cj + 1) * fm];
                let r = j0 + cj;
                let iend = if ib == jb { cj + 1 } else { iw };
                for ci in 0..iend {
                    let coli = &xi[ci * fm..(ci + 1) * fm];
                    schur[packed(r, i0 + ci)] -= dot(colj, coli);
                }
            }
        }
    }

    // 3. B_f = G_{Ȳ_f Z_f} G_{Z_f Z_f}⁻¹ = (L₁₁⁻ᵀ X_Y)ᵀ, X_Y the last f columns of X.
    cross_block(acc, knots, basis, lay, sums, lff, pm, f, bf);
    for x in bf.chunks_exact_mut(fm).take(f) {
        for i in (0..fm).rev() {
            let mut s = x[i];
            for (r, &xr) in x.iter().enumerate().skip(i + 1) {
                s -= lff[packed(r, i)] * xr;
            }
            x[i] = s / lff[packed(i, i)];
        }
    }

    // 4. Cholesky of S: Z_p rows must be positive definite, Ȳ_f rows may be singular.
    cholesky_packed(schur, q, pm, tol).map_err(|_| Error::RankDeficient {
        stage: Stage::InputHankel,
    })?;

    // 5. L₃₂ᵀ (p·m × f) into scratch, QR, and the f × f SVD of Rᵀ.
    let (x, tau) = scratch.split_at_mut(pm * f);
    for i in 0..f {
        let row = packed(pm + i, 0);
        x[i * pm..(i + 1) * pm].copy_from_slice(&schur[row..row + pm]);
    }
    householder_qr(x, pm, f, &mut tau[..f]);
    let mut rt = Small::<T>::zeros();
    for i in 0..f {
        for k in 0..=i {
            rt[(i, k)] = x[k + i * pm];
        }
    }
    let (u, s, _) = svd_small(rt).ok_or(Error::NoConvergence {
        stage: Stage::Projection,
    })?;

    // 6. Whitened singular values: √((j − d)/(p·m)) · L₃₃⁻¹ Rᵀ, with L₃₃'s diagonal floored
    // at √ε·σ₁ so that noise-free data do not divide by zero.
    let j = acc.columns();
    let floor = T::EPS.sqrt() * s[0];
    let mut w = rt;
    for c in 0..f {
        for r in 0..f {
            let row = packed(pm + r, pm);
            let mut acc_v = w[(r, c)];
            for k in 0..r {
                acc_v -= schur[row + k] * w[(k, c)];
            }
            let diag = schur[row + r].max(floor);
            w[(r, c)] = if diag > T::zero() {
                acc_v / diag
            } else {
                T::zero()
            };
        }
    }
    let dof = (j as f64 - d as f64).max(1.0);
    let scale = T::of(libm::sqrt(dof / pm as f64));
    let (_, sw, _) = svd_small(w).ok_or(Error::NoConvergence {
        stage: Stage::Projection,
    })?;

    let sqrt_j = T::of(libm::sqrt(j as f64));
    let mut sv = [T::zero(); MAX_HORIZON];
    let mut sv_white = [T::zero(); MAX_HORIZON];
    for i in 0..f {
        sv[i] = s[i] / sqrt_j;
        sv_white[i] = sw[i] * scale;
    }
    Ok(Projection { j, sv, sv_white, u })
}

/// The order: fixed, or counted from the whitened singular values.
pub(crate) fn select_order<T: Real>(
    order: Order,
    proj: &Projection<T>,
    lay: Layout,
) -> Result<usize, Error> {
    match order {
        Order::Fixed(n) => Ok(n),
        Order::Auto => {
            let edge = 1.0 + libm::sqrt(lay.f as f64 / (lay.p * lay.m) as f64);
            let thr = T::of(AUTO_ORDER_MARGIN * edge);
            let n = proj.sv_white[..lay.f]
                .iter()
                .take_while(|&&s| s > thr)
                .count();
            match n {
                0 => Err(Error::NoDynamics),
                n => Ok(n.min(lay.f - 1)),
            }
        }
    }
}
