//! Column panels of the cross block `X = L₁₁⁻¹ G_{Z_f, [Z_p; Ȳ_f]}`, formed from the lagged
//! sums a few columns at a time instead of stored whole.

use super::Layout;
use super::triangular::forward_substitution_columns;
use crate::accumulation::{Accumulator, RowSums};
use crate::linalg::at;
use crate::regressor::{Basis, Knots};
use crate::scalar::Real;

/// Columns `c0 .. c0 + width` of `X = L₁₁⁻¹ G_{Z_f, [Z_p; Ȳ_f]}` into `out` (column-major,
/// leading dimension `f·m`): one pass over the Gram, then forward substitution.
///
/// The pass takes from each block only the entries of the cross Gram in the wanted columns
/// (centred as [`for_each_entry`](super::gram::for_each_entry) centres them, with the same roundings): the blocks of a past
/// block row `a` and a future one `b` give `Z_p(a) × Z_f(b)` (and `Ȳ_p(a) × Z_f(b)`), the
/// blocks of two future block rows give `Z_f × ȳ_f` in both orders.
#[allow(clippy::too_many_arguments)]
pub(super) fn cross_block<T: Real, const M: usize, const K: usize>(
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
