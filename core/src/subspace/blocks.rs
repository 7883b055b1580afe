//! The blocks `L₃₂` (`f × w`) and `L₃₃` (`f × f`) of the Schur complement's Cholesky factor,
//! and `Rᵀ` from the QR of `L₃₂ᵀ`: `L₃₂ = Rᵀ Qᵀ`, so the SVDs of `L₃₂` reduce to `f × f`.

use super::layout::Layout;
use super::workspace::too_small;
use crate::error::Error;
use crate::linalg::{Small, at, householder_qr, packed, set_el, sub, sub_mut};
use crate::scalar::Real;

/// The QR's scratch in the scratch region of `tail` (after `B_f` and the column blocks,
/// free from step 5 on): the `w × f` matrix and the `f` reflector scalars
/// ([`Error::WorkspaceTooSmall`], for a workspace of `ws_len`, if it is too short).
pub(super) fn qr_scratch<T>(
    lay: Layout,
    tail: &mut [T],
    ws_len: usize,
) -> Result<(&mut [T], &mut [T]), Error> {
    let scratch = tail
        .get_mut(lay.bf() + lay.cache()..)
        .ok_or(too_small(lay, ws_len))?;
    let (x, tau) = scratch
        .split_at_mut_checked(lay.qr_parts().0)
        .ok_or(too_small(lay, ws_len))?;
    let tau = tau
        .get_mut(..lay.qr_parts().1)
        .ok_or(too_small(lay, ws_len))?;
    Ok((x, tau))
}

/// `L₃₂ᵀ` (`w × f`, column-major) into `x` from the factored packed `schur`.
pub(super) fn load_l32<T: Real>(x: &mut [T], schur: &[T], w: usize, f: usize) {
    for i in 0..f {
        let row = packed(w + i, 0);
        let dst = sub_mut(x, i * w, (i + 1) * w);
        for (d, &v) in dst.iter_mut().zip(sub(schur, row, row + w)) {
            *d = v;
        }
    }
}

/// `Rᵀ` (`f × f`, lower) from the QR of the `w × f` column-major `x` (overwritten), `tau`
/// the reflector scalars.
pub(super) fn r_transposed<T: Real, const H: usize>(
    x: &mut [T],
    tau: &mut [T],
    w: usize,
    f: usize,
) -> Small<T, H> {
    householder_qr(x, w, f, tau);
    let mut rt = Small::<T, H>::zeros();
    for i in 0..f {
        for k in 0..=i {
            set_el(&mut rt, i, k, at(x, k + i * w));
        }
    }
    rt
}

/// `L₃₃` (`f × f`, lower) from the factored packed `schur`, for the whitening and CVA.
pub(super) fn l33<T: Real, const H: usize>(schur: &[T], w: usize, f: usize) -> Small<T, H> {
    let mut l33 = Small::<T, H>::zeros();
    for r in 0..f {
        let row = packed(w + r, w);
        for c in 0..=r {
            set_el(&mut l33, r, c, at(schur, row + c));
        }
    }
    l33
}
