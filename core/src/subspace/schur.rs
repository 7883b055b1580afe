//! The Schur complement of `[Z_p; Ȳ_f]` given `Z_f`: `S = G_QQ − XᵀX` from panels of the
//! cross block `X`.

use crate::linalg::{dot, dot4, packed};
use crate::scalar::Real;

/// `S[r0 + a, c0 + b] −= x_aᵀ y_b` for the columns `x_a` of `xa` and `y_b` of `xb` (each `fm`
/// long) into the packed `schur`, only `b <= a` if `diagonal` (`xa` and `xb` the same panel).
pub(super) fn subtract_products<T: Real>(
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
