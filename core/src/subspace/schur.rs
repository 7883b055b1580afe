//! The Schur complement of `[Z_p; Ȳ_f]` given `Z_f`: `S = G_QQ − XᵀX` from panels of the
//! cross block `X`.

use super::cross::cross_block;
use super::gram::Source;
use super::schedule::Schedule;
use super::workspace::too_small;
use crate::error::Error;
use crate::linalg::{dot, dot4, packed};
use crate::scalar::Real;

/// Step 2 of the solve: `S = G_QQ − XᵀX` with `X = L₁₁⁻¹ G_{Z_f Q}` in the packed `schur`
/// (which holds `G_QQ`), `lff` holding `L₁₁`. A panel of X's columns stays in the cache `xs`
/// while the columns left of it are regenerated a few at a time (see [`Schedule`]).
///
/// Returns where in `xs` the last panel holds `X_Y` (the last `f` columns of `X`, for `B_f`),
/// if it holds all of them; [`Error::WorkspaceTooSmall`] (for a workspace of `ws_len`) if the
/// cache holds no panel.
pub(super) fn schur_complement<T: Real, const M: usize, const K: usize>(
    src: &Source<'_, T, M, K>,
    lff: &[T],
    schur: &mut [T],
    xs: &mut [T],
    ws_len: usize,
) -> Result<Option<usize>, Error> {
    let lay = src.lay;
    let (f, fm, q, w) = (lay.f, lay.fm(), lay.q(), lay.w());
    let plan = Schedule::choose(lay, xs.len() / fm.max(1));
    let mut y_at = None;
    for p0 in (0..q).step_by(plan.width.max(1)) {
        let pw = plan.width.min(q - p0);
        let (xa, rest) = xs
            .split_at_mut_checked(pw * fm)
            .ok_or(too_small(lay, ws_len))?;
        cross_block(src, lff, p0, pw, xa);
        subtract_products(schur, xa, xa, fm, p0, p0, true);
        let mut i0 = 0;
        while i0 < p0 {
            let iw = plan.stream.max(1).min(p0 - i0);
            let xb = rest.get_mut(..iw * fm).ok_or(too_small(lay, ws_len))?;
            cross_block(src, lff, i0, iw, xb);
            subtract_products(schur, xa, xb, fm, p0, i0, false);
            i0 += iw;
        }
        // X_Y (the last f columns) for step 3, if this panel (the last) holds all of them.
        y_at = (p0 <= w && w + f <= p0 + pw).then_some((w - p0) * fm);
    }
    Ok(y_at)
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
