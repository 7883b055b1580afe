//! The Gram of `[Z_f; Z_p; Ȳ_p; Ȳ_f]` entry by entry, centred if asked, from the blocks of
//! lagged sums the accumulator keeps.

use super::Layout;
use crate::accumulation::{Accumulator, RowSums};
use crate::linalg::at;
use crate::regressor::{Basis, Knots};
use crate::scalar::Real;

/// Visits every entry `(r, c, v)`, `r >= c`, of the Gram of `[Z_f; Z_p; Ȳ_f]` (rows centred
/// if `sums` is given), block by block from the accumulator.
pub(super) fn for_each_entry<T: Real, const M: usize, const K: usize>(
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
