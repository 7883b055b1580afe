//! Column panels of the cross block `X = L₁₁⁻¹ G_{Z_f, [Z_p; Ȳ_f]}`, formed from the lagged
//! sums a few columns at a time instead of stored whole.

use super::gram::Source;
use super::layout::Layout;
use super::triangular::forward_substitution_columns;
use crate::linalg::at;
use crate::scalar::Real;

/// Columns `c0 .. c0 + width` of `X = L₁₁⁻¹ G_{Z_f, [Z_p; Ȳ_f]}` into `out` (column-major,
/// leading dimension `f·m`): one pass over the Gram, then forward substitution.
///
/// The pass takes from each block only the entries of the cross Gram in the wanted columns
/// (centred as the Gram's diagonal blocks are, with the same roundings,): the blocks of a past
/// block row `a` and a future one `b` give `Z_p(a) × Z_f(b)` (and `Ȳ_p(a) × Z_f(b)`), the
/// blocks of two future block rows give `Z_f × ȳ_f` in both orders.
pub(super) fn cross_block<T: Real, const M: usize, const K: usize>(
    src: &Source<'_, T, M, K>,
    lff: &[T],
    c0: usize,
    width: usize,
    out: &mut [T],
) {
    let Source {
        acc,
        knots,
        basis,
        lay,
        sums,
    } = *src;
    let (fm, p, m) = (lay.fm(), lay.p, lay.m);
    let pm = p * m;
    let in_range = |col: usize| col >= c0 && col < c0 + width;
    let py = lay.py();
    let want = wanted_blocks(lay, c0, width);
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

/// Whether the block of block rows `(x, y)` holds entries of the columns `c0 .. c0 + width`
/// of the cross Gram: the block rows whose `Z_p` channels, or whose `ȳ` (in `Ȳ_p` or `Ȳ_f`),
/// fall in those columns.
fn wanted_blocks(lay: Layout, c0: usize, width: usize) -> impl Fn(usize, usize) -> bool {
    let (p, m, py) = (lay.p, lay.m, lay.py());
    let pm = p * m;
    let in_range = move |col: usize| col >= c0 && col < c0 + width;
    // Block rows whose Z_p channels, or whose ȳ (in Ȳ_f), fall in the wanted columns.
    let zp = move |b: usize| b < p && c0 < (b + 1) * m && b * m < c0 + width;
    let yp = move |b: usize| b < p && py > 0 && in_range(pm + b);
    let yf = move |a: usize| a >= p && in_range(pm + py + a - p);
    move |x: usize, y: usize| (x < p && y >= p && (zp(x) || yp(x))) || (x >= p && (yf(x) || yf(y)))
}

/// The `m` entries of `out` from `from` on (none if `from` is `None` or out of range).
fn dest<T>(out: &mut [T], from: Option<usize>, m: usize) -> &mut [T] {
    from.and_then(|f| out.get_mut(f..f.saturating_add(m)))
        .unwrap_or(&mut [])
}
