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

mod layout;
mod workspace;

pub(crate) use layout::Layout;
pub(crate) use workspace::too_small;
pub use workspace::{workspace_len, workspace_len_with_block};

use crate::accumulation::{Accumulator, OutputRounding, RowSums};
use crate::error::{Error, Stage};
use crate::linalg::{
    Small, all_finite, at, cholesky_packed, dot, dot4, householder_qr, packed, set, set_el, sub,
    sub_mut, svd_small,
};
use crate::regressor::{Basis, Knots};
use crate::scalar::Real;

/// The subspace weighting (Remark 4): which instruments and which weights enter the SVD that
/// gives `Γ_f`. All four share the accumulation, the Schur complement and the `B`, `D` step.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Method {
    /// PI-MOESP, the paper's eq. (11): past inputs as instruments, SVD of `L₃₂`.
    #[default]
    PiMoesp,
    /// PO-MOESP: past inputs and past outputs `[Z_p; Ȳ_p]` as instruments, SVD of `L₃₂`.
    PoMoesp,
    /// N4SID (unit weights): SVD of the oblique projection of `Ȳ_f` along `Z_f` on
    /// `W_p = [Z_p; Ȳ_p]`, i.e. of `L₃₂ L₂₂⁻¹ chol(W_p W_pᵀ)`.
    N4sid,
    /// CVA: PO-MOESP with the left weight `(Ȳ_f Π⊥ Ȳ_fᵀ)^{-1/2}` (canonical correlations);
    /// `Γ_f = L_yy U₁ S₁^½`.
    Cva,
}

impl Method {
    /// Whether past outputs enter the instruments.
    pub const fn past_outputs(self) -> bool {
        !matches!(self, Method::PiMoesp)
    }
}

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

/// Columns of each of the two column blocks of the workspace. While the Schur complement is
/// formed, the blocks, `B_f`'s place and the scratch together hold panels of
/// `L₁₁⁻¹ G_{Z_f,[Z_p; Ȳ_f]}` (see the solve's `Schedule`) instead of the whole cross Gram.
pub const SCHUR_BLOCK: usize = 32;

/// The outcome of the PI-MOESP step.
#[derive(Clone, Debug)]
pub(crate) struct Projection<T, const H: usize> {
    /// Hankel columns.
    pub j: u64,
    /// Singular values of `O_f / √j`, descending (first `f` valid).
    pub sv: [T; H],
    /// Whitened singular values (order selection), descending.
    pub sv_white: [T; H],
    /// `Γ_f` for every order: its first `n` columns are the estimate of order `n`.
    pub gamma: Small<T, H>,
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
    let inv_j = T::one() / acc.effective_columns().max(T::one());
    let mut put = |ra: usize, rb: usize, v: T| sink(ra.max(rb), ra.min(rb), v);
    acc.for_each_block_where(knots, basis, want, |a, b, blk| {
        let mut blk = *blk;
        if let Some(s) = sums {
            // Block rows below `K` (the accumulator's lags); the sums of no block otherwise.
            let z = |i: usize| s.z.get(i).copied().unwrap_or([T::zero(); M]);
            let (za, zb) = (z(a), z(b));
            let (ya, yb_raw) = (at(&s.y, a) * inv_j, at(&s.y, b));
            let yb = yb_raw * inv_j;
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
            blk.yy -= ya * yb_raw;
        }
        for (i, (row, &zy)) in blk.zz.iter().zip(&blk.zy).enumerate().take(m) {
            let ra = lay.z_row(a, i);
            for (jj, &v) in row.iter().enumerate().take(m) {
                put(ra, lay.z_row(b, jj), v);
            }
            if let Some(rb) = lay.y_row(b) {
                put(ra, rb, zy);
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
///
/// The pass takes from each block only the entries of the cross Gram in the wanted columns
/// (centred as [`for_each_entry`] centres them, with the same roundings): the blocks of a past
/// block row `a` and a future one `b` give `Z_p(a) × Z_f(b)` (and `Ȳ_p(a) × Z_f(b)`), the
/// blocks of two future block rows give `Z_f × ȳ_f` in both orders.
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
    let py = lay.py();
    let zp = |b: usize| b < p && c0 < (b + 1) * m && b * m < c0 + width;
    let yp = |b: usize| b < p && py > 0 && in_range(pm + b);
    let yf = |a: usize| a >= p && in_range(pm + py + a - p);
    let want =
        |x: usize, y: usize| (x < p && y >= p && (zp(x) || yp(x))) || (x >= p && (yf(x) || yf(y)));
    let inv_j = T::one() / acc.effective_columns().max(T::one());
    // Row sums of block row `a` (zero without centring or past `K`), and `Σȳ / j`.
    let zero = [T::zero(); M];
    let zs = |a: usize| sums.and_then(|s| s.z.get(a)).unwrap_or(&zero);
    let ys = |a: usize| sums.map_or(T::zero(), |s| at(&s.y, a));
    let centre = sums.is_some();
    let cent = |v: T, x: T, y: T| if centre { v - x * y } else { v };
    // Where column `col` of Q, rows of block row `blk_row` of Z_f, start in `out`.
    let from = |col: usize, blk_row: usize| {
        let fut = blk_row.checked_sub(p)?;
        in_range(col).then(|| (col - c0) * fm + fut * m)
    };
    acc.for_each_block_where(knots, basis, want, |a, b, blk| {
        let (za, zb) = (zs(a), zs(b));
        if a < p {
            for (i, (row, &zi)) in blk.zz.iter().zip(za).enumerate().take(m) {
                let zi = zi * inv_j;
                let dst = dest(out, from(a * m + i, b), m);
                for (d, (&v, &zj)) in dst.iter_mut().zip(row.iter().zip(zb)) {
                    *d = cent(v, zi, zj);
                }
            }
            if py > 0 {
                let ya = ys(a) * inv_j;
                let dst = dest(out, from(pm + a, b), m);
                for (d, (&v, &zj)) in dst.iter_mut().zip(blk.yz.iter().zip(zb)) {
                    *d = cent(v, ya, zj);
                }
            }
        } else {
            // Z_f(a) × ȳ(b) (for a = b the same entries as ȳ(a) × Z_f(a), which wins).
            let base = pm + py - p;
            if a < b {
                let yb = ys(b) * inv_j;
                let dst = dest(out, from(base + b, a), m);
                for (d, (&v, &zi)) in dst.iter_mut().zip(blk.zy.iter().zip(za)) {
                    *d = cent(v, zi, yb);
                }
            }
            let ya = ys(a) * inv_j;
            let dst = dest(out, from(base + a, b), m);
            for (d, (&v, &zj)) in dst.iter_mut().zip(blk.yz.iter().zip(zb)) {
                *d = cent(v, ya, zj);
            }
        }
    });
    forward_substitution_columns(lff, out, fm, width);
}

/// The `m` entries of `out` from `from` on (none if `from` is `None` or out of range).
fn dest<T>(out: &mut [T], from: Option<usize>, m: usize) -> &mut [T] {
    from.and_then(|f| out.get_mut(f..f.saturating_add(m)))
        .unwrap_or(&mut [])
}

/// `S[r0 + a, c0 + b] −= x_aᵀ y_b` for the columns `x_a` of `xa` and `y_b` of `xb` (each `fm`
/// long) into the packed `schur`, only `b <= a` if `diagonal` (`xa` and `xb` the same panel).
fn subtract_products<T: Real>(
    schur: &mut [T],
    xa: &[T],
    xb: &[T],
    fm: usize,
    r0: usize,
    c0: usize,
    diagonal: bool,
) {
    let fm = fm.max(1);
    for (a, colj) in xa.chunks_exact(fm).enumerate() {
        let width = if diagonal { a + 1 } else { usize::MAX };
        let row = packed(r0 + a, c0);
        let Some(dst) = schur.get_mut(row..) else {
            return;
        };
        let mut dst = dst.iter_mut();
        let mut cols = xb.chunks_exact(fm).take(width);
        loop {
            match (cols.next(), cols.next(), cols.next(), cols.next()) {
                (Some(p), Some(q), Some(r), Some(s)) => {
                    // The four products first: `zip` asks its first iterator first.
                    for (d, v) in dot4(colj, [p, q, r, s]).into_iter().zip(dst.by_ref()) {
                        *v -= d;
                    }
                }
                (p, q, r, _) => {
                    for (c, v) in [p, q, r].into_iter().flatten().zip(dst.by_ref()) {
                        *v -= dot(colj, c);
                    }
                    break;
                }
            }
        }
    }
}

/// How step 2 of [`pi_moesp`] walks the `q` columns of `X = L₁₁⁻¹ G_{Z_f Q}` with a cache of
/// a few of them: panels of `width` columns, each computed once and kept while the Schur
/// complement's rows of the panel are formed, and the columns left of a panel regenerated
/// `stream` at a time next to it. The pairs of columns, and so the result, are the same for
/// every schedule; the work is not.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Schedule {
    /// Columns per panel.
    width: usize,
    /// Columns regenerated at a time (`width + stream` fit in the cache).
    stream: usize,
}

impl Schedule {
    /// The schedule of least estimated work for a cache of `cols` columns: a regenerated
    /// column costs a forward substitution (`(f·m)²/2` multiply-adds), a pass over the lagged
    /// sums about `k²·m²` (`k = f + p` block rows: `k²/2` blocks of about `m²` entries, each
    /// corrected and scattered).
    fn choose(lay: Layout, cols: usize) -> Self {
        let q = lay.q();
        let column = (lay.fm() * lay.fm() / 2) as u64;
        let k = (lay.f + lay.p) as u64;
        let pass = k * k * (lay.m * lay.m) as u64;
        let mut best = Self {
            width: 1,
            stream: 1,
        };
        let mut best_cost = u64::MAX;
        let mut last = 0;
        for panels in 1..=q {
            let width = q.div_ceil(panels);
            let Some(stream) = cols.checked_sub(width) else {
                continue;
            };
            if (stream == 0 && width < q) || width == last {
                continue;
            }
            last = width;
            let plan = Self { width, stream };
            let (regenerated, passes) = plan.work(q);
            let cost = (regenerated as u64)
                .saturating_mul(column)
                .saturating_add((passes as u64).saturating_mul(pass));
            if cost < best_cost {
                (best, best_cost) = (plan, cost);
            }
        }
        best
    }

    /// Columns regenerated and passes over the lagged sums for `q` columns.
    fn work(self, q: usize) -> (usize, usize) {
        let (mut regenerated, mut passes) = (0, 0);
        for p0 in (0..q).step_by(self.width.max(1)) {
            regenerated += p0;
            passes += 1 + p0.div_ceil(self.stream.max(1));
        }
        (regenerated, passes)
    }
}

/// `X ← L⁻¹ X` for the first `width` columns (`n` long) of the column-major `x`, four at a
/// time (the same bits as one at a time: [`dot4`]).
fn forward_substitution_columns<T: Real>(l: &[T], x: &mut [T], n: usize, width: usize) {
    let mut cols = x.chunks_exact_mut(n.max(1)).take(width);
    loop {
        match (cols.next(), cols.next(), cols.next(), cols.next()) {
            (Some(a), Some(b), Some(c), Some(d)) => forward_substitution4(l, [a, b, c, d]),
            (a, b, c, _) => {
                for x in [a, b, c].into_iter().flatten() {
                    forward_substitution(l, x);
                }
                return;
            }
        }
    }
}

/// [`forward_substitution`] of four columns at once.
fn forward_substitution4<T: Real>(l: &[T], mut x: [&mut [T]; 4]) {
    let n = x.iter().fold(usize::MAX, |n, c| n.min(c.len()));
    let mut rows = l;
    for i in 0..n {
        let Some((row, rest)) = rows.split_at_checked(i + 1) else {
            return;
        };
        rows = rest;
        let Some((&d, li)) = row.split_last() else {
            return;
        };
        let [x0, x1, x2, x3] = &x;
        let done = [x0, x1, x2, x3].map(|c| c.get(..i).unwrap_or(&[]));
        let s = dot4(li, done);
        for (col, s) in x.iter_mut().zip(s) {
            if let Some(xi) = col.get_mut(i) {
                *xi = (*xi - s) / d;
            }
        }
    }
}

/// `x ← L⁻ᵀ x` for the packed lower-triangular `L` of dimension `x.len()` in `l`: from the
/// last row up, `x_i = (x_i − Σ_{r > i} L[r, i] x_r) / L[i, i]`, the sum in increasing `r`
/// (column `i` of `L` walked by its packed offset, which grows by `r + 1` from row `r` on).
fn back_substitution_transposed<T: Real>(l: &[T], x: &mut [T]) {
    for i in (0..x.len()).rev() {
        let Some((done, later)) = x.split_at_mut_checked(i + 1) else {
            return;
        };
        let mut s = at(done, i);
        let mut idx = packed(i + 1, i);
        for (r, &xr) in later.iter().enumerate() {
            s -= at(l, idx) * xr;
            idx += i + r + 2;
        }
        set(done, i, s / at(l, packed(i, i)));
    }
}

/// `x ← L⁻¹ x` for the packed lower-triangular `L` of dimension `x.len()` in `l`.
fn forward_substitution<T: Real>(l: &[T], x: &mut [T]) {
    let mut rows = l;
    for i in 0..x.len() {
        // Row i of L: i entries left of the diagonal, then the diagonal.
        let Some((row, rest)) = rows.split_at_checked(i + 1) else {
            return;
        };
        rows = rest;
        let (Some((&d, li)), (done, todo)) = (row.split_last(), x.split_at_mut(i)) else {
            return;
        };
        if let Some(xi) = todo.first_mut() {
            *xi = (*xi - dot(li, done)) / d;
        }
    }
}

/// PI-MOESP from the accumulated Gram: `L₁₁`, the Schur complement of `[Z_p; Ȳ_f]` given
/// `Z_f` (whose Cholesky factor holds `L₂₂`, `L₃₂`, `L₃₃`), `B_f = L₃₁L₁₁⁻¹`, and the SVD of
/// `L₃₂`. The cross block `G_{Z_f,[Z_p; Ȳ_f]}` is never stored whole: it is formed from the
/// lagged sums panel by panel (columns left of a panel regenerated), which keeps the workspace near
/// `(f·m)²/2 + (p·m + f)²/2` instead of `((f + p)·m + f)²/2`.
pub(crate) fn pi_moesp<T: Real, const M: usize, const K: usize, const H: usize>(
    acc: &Accumulator<T, M, K>,
    knots: &Knots<T, M>,
    basis: Basis,
    lay: Layout,
    centred: bool,
    output_rounding: OutputRounding,
    ws: &mut [T],
) -> Result<Projection<T, H>, Error> {
    let (f, m) = (lay.f, lay.m);
    let (fm, q, pm, d, w) = (lay.fm(), lay.q(), lay.p * m, lay.d(), lay.w());
    // Both refused by `Identifier::new`; kept here so that no layout can index past the QR
    // or the small matrices.
    if !(2..=H).contains(&f) {
        return Err(Error::InvalidHorizon {
            f,
            k: f + lay.p,
            max_f: H,
            max_k: K,
        });
    }
    if w < f {
        return Err(Error::TooFewInstruments {
            f,
            p: lay.p,
            channels: m,
            past_outputs: lay.method.past_outputs(),
        });
    }
    let ws_len = ws.len();
    let [lff, schur, wgram, tail] = lay.carve_front(ws)?;
    // Until step 4 the raw diagonals (below) sit at the end of the tail, and the rest of it
    // (B_f, the column blocks and the scratch) is the cache of step 2.
    let (xs, g) = tail
        .split_at_mut_checked(tail.len().saturating_sub(q))
        .ok_or(too_small(lay, ws_len))?;
    let sums = centred.then(|| acc.row_sums(knots, basis));
    let sums = sums.as_ref();

    // 1. G_{Z_f Z_f} and G_{QQ} (Q = [Z_p; Ȳ_f]) in one pass. Both must be finite: an
    // overflow of the sums (y² above the scalar's range) is reported as such, before any
    // factorisation (a non-finite cross block G_{Z_f Q} shows in the Schur complement).
    for_each_entry(
        acc,
        knots,
        basis,
        lay,
        sums,
        |_, _| true,
        |r, c, v| {
            if r < fm {
                set(lff, packed(r, c), v);
            } else if c >= fm {
                set(schur, packed(r - fm, c - fm), v);
                if r < fm + w {
                    set(wgram, packed(r - fm, c - fm), v);
                }
            }
        },
    );
    if !all_finite(lff) || !all_finite(schur) {
        return Err(Error::Overflow { stage: Stage::Sums });
    }
    // Rounding floors of the rows that may be singular (Ȳ_p, Ȳ_f): their raw Gram diagonals
    // times the relative rounding level of the sums and of the factorisations.
    let j_eff = acc.effective_columns().to_f64();
    // `level` for the input sums (always recursive) and anything that mixes them in,
    // `level_y` for what only the sums of products with the output carry.
    let level = rounding_level::<T>(j_eff, d + q);
    let level_y = match output_rounding {
        OutputRounding::Recursive => level,
        OutputRounding::Compensated => rounding_level::<T>(4.0, d + q),
    };
    // `q − pm = py + f <= p + f <= K` rows.
    let mut floor = [T::zero(); K];
    for (i, fl) in floor.iter_mut().enumerate().take(q - pm) {
        let r = pm + i;
        *fl = level * at(schur, packed(r, r)).abs();
    }
    let floor = &floor[..(q - pm).min(K)];
    // The raw diagonal of every row of [Z_p; Ȳ_p; Ȳ_f].
    for (r, g) in g.iter_mut().enumerate().take(q) {
        *g = at(schur, packed(r, r)).abs();
    }
    let tol = T::EPS * T::of_usize(8 * (d + q));
    cholesky_packed(lff, fm, fm, tol, &[]).map_err(|_| Error::RankDeficient {
        stage: Stage::InputHankel,
    })?;

    // 2. S = G_QQ − XᵀX with X = L₁₁⁻¹ G_{Z_f Q}: a panel of X's columns stays in the cache
    // while the columns left of it are regenerated a few at a time (see `Schedule`).
    let plan = Schedule::choose(lay, xs.len() / fm.max(1));
    let mut y_at = None;
    for p0 in (0..q).step_by(plan.width.max(1)) {
        let pw = plan.width.min(q - p0);
        let (xa, rest) = xs
            .split_at_mut_checked(pw * fm)
            .ok_or(too_small(lay, ws_len))?;
        cross_block(acc, knots, basis, lay, sums, lff, p0, pw, xa);
        subtract_products(schur, xa, xa, fm, p0, p0, true);
        let mut i0 = 0;
        while i0 < p0 {
            let iw = plan.stream.max(1).min(p0 - i0);
            let xb = rest.get_mut(..iw * fm).ok_or(too_small(lay, ws_len))?;
            cross_block(acc, knots, basis, lay, sums, lff, i0, iw, xb);
            subtract_products(schur, xa, xb, fm, p0, i0, false);
            i0 += iw;
        }
        // X_Y (the last f columns) for step 3, if this panel (the last) holds all of them.
        y_at = (p0 <= w && w + f <= p0 + pw).then_some((w - p0) * fm);
    }

    // 3. B_f = G_{Ȳ_f Z_f} G_{Z_f Z_f}⁻¹ = (L₁₁⁻ᵀ X_Y)ᵀ, X_Y the last f columns of X, moved
    // from the last panel to B_f's place at the start of the cache (or computed anew).
    let bf_len = lay.bf();
    match y_at {
        Some(from) if from.saturating_add(bf_len) <= xs.len() => {
            // Forwards, entry by entry: the source lies at or after the destination.
            for k in 0..bf_len {
                let v = at(xs, from + k);
                set(xs, k, v);
            }
        }
        _ => {
            let bf = xs.get_mut(..bf_len).ok_or(too_small(lay, ws_len))?;
            cross_block(acc, knots, basis, lay, sums, lff, w, f, bf);
        }
    }
    let bf = xs.get_mut(..bf_len).ok_or(too_small(lay, ws_len))?;
    for x in bf.chunks_exact_mut(fm.max(1)).take(f) {
        back_substitution_transposed(lff, x);
    }

    if !all_finite(schur) || !all_finite(bf) {
        return Err(Error::Overflow { stage: Stage::Sums });
    }
    // 4. Cholesky of S: Z_p rows must be positive definite; Ȳ_p and Ȳ_f rows may be singular
    // (noise-free data).
    cholesky_packed(schur, q, pm, tol, floor).map_err(|_| Error::RankDeficient {
        stage: Stage::InputHankel,
    })?;
    let j = acc.columns();
    // Rounding level of the residual L₃₃L₃₃ᵀ = S₃₃ − L₃₂L₃₂ᵀ, row by row: the row's own
    // (level · raw diagonal), plus what L₃₂ inherits from the pivots d_i of the instruments:
    // d_i² carries an error of level · g_i (g_i its raw diagonal), so column i of L₃₂ a
    // relative error of level · g_i / d_i², and the row's residual 2 Σ_i L₃₂[r,i]² times that.
    // Past outputs that the inputs nearly explain (high SNR) have small pivots and make this
    // large where the row leans on them. Besides, each entry L₃₂[r,i] carries an absolute
    // rounding error of about level · √(g_r g_i) / d_i, which looks like noise to the
    // whitening: its floor for L₃₃'s row is also the residual that noise of that size would
    // leave (dof/w times the mean squared error of the row). Below `res_floor` a residual is
    // rounding (the CVA weighting is then singular), below `white_floor` the whitening
    // cannot tell noise from rounding.
    let dof = (j_eff - (d + lay.py()) as f64).max(1.0);
    let per_col = T::of(dof / w as f64);
    let mut res_floor = [T::zero(); H];
    let mut white_floor = [T::zero(); H];
    for (r, (v, wf)) in res_floor
        .iter_mut()
        .zip(white_floor.iter_mut())
        .enumerate()
        .take(f)
    {
        let row = packed(w + r, 0);
        let gr = at(g, w + r);
        let (mut e, mut noise) = (T::zero(), T::zero());
        for (i, &gi) in g.iter().enumerate().take(w) {
            let d = at(schur, packed(i, i));
            if d > T::zero() {
                let l = at(schur, row + i) / d;
                e += (l + l) * l * gi;
                noise += gr * gi / (d * d);
            }
        }
        // The row's own diagonal and the cross products are output sums; the pivots d_i
        // come from the input sums.
        *v = level_y * gr + level * e;
        *wf = v.max(level_y * level_y * noise * per_col);
    }

    // 5. Rᵀ from the QR of L₃₂ᵀ (w × f): L₃₂ = Rᵀ Qᵀ, so the SVDs of L₃₂ reduce to f × f.
    // For N4SID the same is done for (L₃₂ L₂₂⁻¹ L_W)ᵀ below.
    // The scratch (after B_f and the column blocks) is free from here on.
    let scratch = tail
        .get_mut(lay.bf() + lay.cache()..)
        .ok_or(too_small(lay, ws_len))?;
    let (x, tau) = scratch
        .split_at_mut_checked(lay.qr_parts().0)
        .ok_or(too_small(lay, ws_len))?;
    let tau = tau
        .get_mut(..lay.qr_parts().1)
        .ok_or(too_small(lay, ws_len))?;
    let load_l32 = |x: &mut [T]| {
        for i in 0..f {
            let row = packed(w + i, 0);
            let dst = sub_mut(x, i * w, (i + 1) * w);
            for (d, &v) in dst.iter_mut().zip(sub(schur, row, row + w)) {
                *d = v;
            }
        }
    };
    let r_transposed = |x: &mut [T], tau: &mut [T]| {
        householder_qr(x, w, f, tau);
        let mut rt = Small::<T, H>::zeros();
        for i in 0..f {
            for k in 0..=i {
                set_el(&mut rt, i, k, at(x, k + i * w));
            }
        }
        rt
    };
    load_l32(x);
    let rt = r_transposed(x, tau);
    // L₃₃ (f × f, lower) for the whitening and CVA.
    let mut l33 = Small::<T, H>::zeros();
    for r in 0..f {
        let row = packed(w + r, w);
        for c in 0..=r {
            set_el(&mut l33, r, c, at(schur, row + c));
        }
    }
    // With forgetting, the weighted Gram has the weight of j_eff = Σλ^i columns.
    let sqrt_j = T::of(libm::sqrt(j_eff));
    let (gamma, sv) = match lay.method {
        Method::Cva => {
            // L_yy L_yyᵀ = Ȳ_f Π⊥ Ȳ_fᵀ = RᵀR + L₃₃L₃₃ᵀ; SVD of L_yy⁻¹ Rᵀ. The weighting is
            // its inverse square root: a pivot at the rounding level of its row (noise-free
            // data: Ȳ_f Π⊥ has rank n) would turn rounding into canonical correlations.
            let gram = outer_gram(&rt, f) + outer_gram(&l33, f);
            let lyy = small_cholesky(&gram, f, &res_floor).ok_or(Error::RankDeficient {
                stage: Stage::CvaWeighting,
            })?;
            let wtd = lower_solve(&lyy, &rt, f);
            let (u, s, _) = svd_small(wtd, f, Stage::Projection, false)?;
            let t = product(&lyy, &u, f);
            (scale_columns(t, &s, f, T::one()), s)
        }
        Method::N4sid => {
            // O = L₃₂ L₂₂⁻¹ L_W, L_W the Cholesky factor of the instruments' Gram W_p W_pᵀ.
            cholesky_packed(wgram, w, pm, tol, floor).map_err(|_| Error::RankDeficient {
                stage: Stage::InputHankel,
            })?;
            load_l32(x);
            for col in x.chunks_exact_mut(w.max(1)).take(f) {
                // x L₂₂ = l₃₂ (back substitution), then x L_W.
                for c in (0..w).rev() {
                    let mut s = at(col, c);
                    for (r, &xr) in col.iter().enumerate().skip(c + 1) {
                        s -= xr * at(schur, packed(r, c));
                    }
                    let dgn = at(schur, packed(c, c));
                    set(col, c, if dgn > T::zero() { s / dgn } else { T::zero() });
                }
                for c in 0..w {
                    let mut s = T::zero();
                    for (r, &xr) in col.iter().enumerate().skip(c) {
                        s += xr * at(wgram, packed(r, c));
                    }
                    set(col, c, s);
                }
            }
            let ot = r_transposed(x, tau);
            let (u, s, _) = svd_small(ot, f, Stage::Projection, false)?;
            let mut sv = s;
            for v in sv.iter_mut() {
                *v /= sqrt_j;
            }
            (scale_columns(u, &s, f, T::one()), sv)
        }
        Method::PiMoesp | Method::PoMoesp => {
            let (u, s, _) = svd_small(rt, f, Stage::Projection, false)?;
            let mut sv = s;
            for v in sv.iter_mut() {
                *v /= sqrt_j;
            }
            (scale_columns(u, &s, f, T::one()), sv)
        }
    };

    // 6. Whitened singular values of L₃₂: √((j − d)/w) · L₃₃⁻¹ Rᵀ, with L₃₃'s diagonal
    // floored at the rounding level of its row (a residual below it is rounding, not noise;
    // noise-free data then do not divide by zero, and rounding does not pass for a state).
    let mut l33f = l33;
    for (i, &fl) in white_floor.iter().enumerate().take(f) {
        l33f[(i, i)] = l33f[(i, i)].max(fl.sqrt());
    }
    let wh = lower_solve(&l33f, &rt, f);
    let scale = T::of(libm::sqrt(dof / w as f64));
    let (_, sw, _) = svd_small(wh, f, Stage::Projection, false)?;
    let mut sv_white = [T::zero(); H];
    for (v, &s) in sv_white.iter_mut().zip(&sw).take(f) {
        *v = s * scale;
    }
    let mut svo = [T::zero(); H];
    for (v, &s) in svo.iter_mut().zip(&sv).take(f) {
        *v = s;
    }
    Ok(Projection {
        j,
        sv: svo,
        sv_white,
        gamma,
    })
}

/// Relative rounding level of the Gram entries and of what is computed from them, for sums
/// over `j` (effective) columns and factorisations of dimension `dim`: recursive summation
/// leaves a relative error of about `ε·√j` in each sum, the Schur complement and the
/// Cholesky factorisation about `ε·dim` more. A residual variance below this level times
/// its row's Gram diagonal cannot be told from rounding.
fn rounding_level<T: Real>(j: f64, dim: usize) -> T {
    T::EPS * T::of(libm::sqrt(j.max(1.0)) + libm::sqrt(dim as f64))
}

/// Columns `i < f` of `t` times `√s_i` (`s` raw singular values times `scale`).
fn scale_columns<T: Real, const H: usize>(
    mut t: Small<T, H>,
    s: &[T; H],
    f: usize,
    scale: T,
) -> Small<T, H> {
    let f = f.min(H);
    for (c, &sc) in s.iter().enumerate().take(f) {
        let w = (sc * scale).sqrt();
        for r in 0..f {
            t[(r, c)] *= w;
        }
    }
    t
}

/// Cholesky factor of the leading `n × n` block of a symmetric positive definite matrix;
/// `None` if a pivot is not above `floor[i]` (zero where `floor` is shorter).
fn small_cholesky<T: Real, const H: usize>(
    a: &Small<T, H>,
    n: usize,
    floor: &[T],
) -> Option<Small<T, H>> {
    let n = n.min(H);
    let mut l = Small::<T, H>::zeros();
    for i in 0..n {
        for j in 0..=i {
            let mut s = a[(i, j)];
            for k in 0..j {
                s -= l[(i, k)] * l[(j, k)];
            }
            if i == j {
                let fl = floor.get(i).copied().unwrap_or_default();
                let ok = s > fl.max(T::zero()) && s.finite();
                if !ok {
                    return None;
                }
                l[(i, i)] = s.sqrt();
            } else {
                l[(i, j)] = s / l[(j, j)];
            }
        }
    }
    Some(l)
}

/// `L⁻¹ B` for lower-triangular `L` (leading `n × n`), zero diagonal entries giving zero rows.
fn lower_solve<T: Real, const H: usize>(l: &Small<T, H>, b: &Small<T, H>, n: usize) -> Small<T, H> {
    let n = n.min(H);
    let mut x = *b;
    for c in 0..n {
        for r in 0..n {
            let mut v = x[(r, c)];
            for k in 0..r {
                v -= l[(r, k)] * x[(k, c)];
            }
            let d = l[(r, r)];
            x[(r, c)] = if d > T::zero() { v / d } else { T::zero() };
        }
    }
    x
}

/// `A Aᵀ` of the leading `n × n` block (zero outside it).
fn outer_gram<T: Real, const H: usize>(a: &Small<T, H>, n: usize) -> Small<T, H> {
    let n = n.min(H);
    let mut g = Small::<T, H>::zeros();
    for c in 0..n {
        for r in 0..n {
            let mut s = T::zero();
            for k in 0..n {
                s += a[(r, k)] * a[(c, k)];
            }
            g[(r, c)] = s;
        }
    }
    g
}

/// `A B` of the leading `n × n` blocks (zero outside them).
fn product<T: Real, const H: usize>(a: &Small<T, H>, b: &Small<T, H>, n: usize) -> Small<T, H> {
    let n = n.min(H);
    let mut p = Small::<T, H>::zeros();
    for c in 0..n {
        for r in 0..n {
            let mut s = T::zero();
            for k in 0..n {
                s += a[(r, k)] * b[(k, c)];
            }
            p[(r, c)] = s;
        }
    }
    p
}

/// The order: fixed, or counted from the whitened singular values.
pub(crate) fn select_order<T: Real, const H: usize>(
    order: Order,
    proj: &Projection<T, H>,
    lay: Layout,
) -> Result<usize, Error> {
    match order {
        Order::Fixed(n) => Ok(n),
        Order::Auto => {
            let edge = 1.0 + libm::sqrt(lay.f as f64 / lay.w() as f64);
            let thr = T::of(AUTO_ORDER_MARGIN * edge);
            let n = proj
                .sv_white
                .iter()
                .take(lay.f)
                .take_while(|&&s| s > thr)
                .count();
            match n {
                0 => Err(Error::NoDynamics),
                n => Ok(n.min(lay.f - 1)),
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The paper's layout with the default workspace: B_f, the two blocks of 32 columns and
    /// the scratch less the raw diagonals hold 83 columns of 140, so two panels of 75 with 8
    /// columns streamed, 75 columns regenerated in 12 passes (the two-block walk regenerated
    /// 320 columns in 16 passes, B_f's included).
    #[test]
    fn schedule_of_the_paper_layout() {
        let lay = Layout::new(14, 10, 10);
        let cols = (lay.bf() + lay.cache() + lay.scratch() - lay.q()) / lay.fm();
        assert_eq!(cols, 83);
        let plan = Schedule::choose(lay, cols);
        assert_eq!(
            plan,
            Schedule {
                width: 75,
                stream: 8
            }
        );
        assert_eq!(plan.work(lay.q()), (75, 12));
    }

    /// Every cache from the smallest (two columns) to more than `q`: the schedule fits it,
    /// streams whenever there is more than one panel, and one panel holds all when it can.
    #[test]
    fn schedule_fits_every_cache() {
        let lay = Layout::new(14, 10, 10);
        let q = lay.q();
        for cols in 2..=q + 10 {
            let plan = Schedule::choose(lay, cols);
            assert!(
                plan.width >= 1 && plan.width + plan.stream <= cols,
                "{cols}: {plan:?}"
            );
            assert!(plan.width >= q || plan.stream >= 1, "{cols}: {plan:?}");
            if cols >= q {
                assert_eq!(plan.work(q), (0, 1), "{cols}: {plan:?}");
            }
        }
    }
}
