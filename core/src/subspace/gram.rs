//! The Gram of `[Z_f; Z_p; Ȳ_p; Ȳ_f]` entry by entry, centred if asked, from the blocks of
//! lagged sums the accumulator keeps.

use super::layout::Layout;
use crate::accumulation::{Accumulator, RowSums};
use crate::error::{Error, Stage};
use crate::linalg::{all_finite, at, packed, set};
use crate::regressor::{Basis, Knots};
use crate::scalar::Real;

/// Where the Gram's entries come from: the accumulator's blocks of lagged sums (read with
/// `knots` and `basis`), the layout of the rows, and the row sums that centre them (if the
/// solve centres).
pub(super) struct Source<'a, T, const M: usize, const K: usize> {
    /// The accumulated lagged sums.
    pub acc: &'a Accumulator<T, M, K>,
    /// The knots the regressor was accumulated with.
    pub knots: &'a Knots<T, M>,
    /// The regressor's basis.
    pub basis: Basis,
    /// The rows of `[Z_f; Z_p; Ȳ_p; Ȳ_f]`.
    pub lay: Layout,
    /// The row sums, if the rows are centred.
    pub sums: Option<&'a RowSums<T, M, K>>,
}

impl<'a, T, const M: usize, const K: usize> Source<'a, T, M, K> {
    /// The source of the accumulator's Gram for `knots`, `basis` and `lay`, centred with
    /// `sums` if given.
    pub(super) fn new(
        acc: &'a Accumulator<T, M, K>,
        knots: &'a Knots<T, M>,
        basis: Basis,
        lay: Layout,
        sums: Option<&'a RowSums<T, M, K>>,
    ) -> Self {
        Self {
            acc,
            knots,
            basis,
            lay,
            sums,
        }
    }
}

/// Step 1 of the solve: `G_{Z_f Z_f}` into the packed `lff`, `G_QQ` (`Q = [Z_p; Ȳ_f]`) into
/// the packed `schur` and its leading `W_p` block into `wgram`, in one pass. Both must be
/// finite: an overflow of the sums (y² above the scalar's range) is reported as such, before
/// any factorisation (a non-finite cross block `G_{Z_f Q}` shows in the Schur complement).
pub(super) fn diagonal_blocks<T: Real, const M: usize, const K: usize>(
    src: &Source<'_, T, M, K>,
    lff: &mut [T],
    schur: &mut [T],
    wgram: &mut [T],
) -> Result<(), Error> {
    let (fm, w) = (src.lay.fm(), src.lay.w());
    for_each_entry(
        src,
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
    Ok(())
}

/// Visits every entry `(r, c, v)`, `r >= c`, of the Gram of `[Z_f; Z_p; Ȳ_f]` (rows centred
/// if `src` has row sums), block by block from the accumulator.
fn for_each_entry<T: Real, const M: usize, const K: usize>(
    src: &Source<'_, T, M, K>,
    want: impl Fn(usize, usize) -> bool,
    mut sink: impl FnMut(usize, usize, T),
) {
    let Source {
        acc,
        knots,
        basis,
        lay,
        sums,
    } = *src;
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
