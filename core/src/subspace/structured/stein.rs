//! The blocks read from the generator by their Stein equations (the shift `F` is nilpotent,
//! so each is a recursion along the diagonals): `B_f` after `Z_f` is eliminated, written over
//! the dead identity rows, and `S_Φ` at the end.

use super::slots::Slots;
use crate::linalg::{at, dot, packed, set, sub, sub_mut};
use crate::scalar::Real;

/// The signature-weighted product `a J bᵀ` of the generator rows in slots `a` and `b` of `x`
/// (`x` starting at slot `first`).
fn jdot<T: Real>(x: &[T], sl: &Slots, first: usize, a: usize, b: usize) -> T {
    let row = |slot: usize| {
        let o = sl.off(slot.saturating_sub(first));
        sub(x, o, o + sl.r)
    };
    let (ap, an) = row(a).split_at_checked(sl.pos).unwrap_or((&[], &[]));
    let (bp, bn) = row(b).split_at_checked(sl.pos).unwrap_or((&[], &[]));
    dot(ap, bp) - dot(an, bn)
}

/// `B_f` from the block `C = −B_f` of the Schur complement between the output rows and the
/// identity rows, `C − F_Y C F_Iᵀ = X_Y J X_Iᵀ`, after the last `Z_f` step. Identity row `I_q`
/// is replaced by `B_f`'s column of natural index `(f − 1 − ⌊q/m⌋)·m + q mod m` (its first `f`
/// scalars, by output row in the natural order): column `q` needs the generator's row `I_q`
/// and the column already written over `I_{q−m}`, so increasing `q` reads each row before it
/// is overwritten. `col` is scratch of `f`.
pub(super) fn regression_in_place<T: Real>(x: &mut [T], sl: &Slots, col: &mut [T]) {
    let (f, m) = (sl.f, sl.m);
    for q in 0..sl.fm {
        for (a, v) in col.iter_mut().enumerate().take(f) {
            let prev = if a + 1 < f && q >= m {
                at(x, sl.off(q - m) + a + 1)
            } else {
                T::zero()
            };
            *v = prev - jdot(x, sl, 0, sl.y(f - 1 - a), q);
        }
        for (d, &v) in sub_mut(x, sl.off(q), sl.off(q) + f)
            .iter_mut()
            .zip(col.iter())
        {
            *d = v;
        }
    }
}

/// `B_f[a, jj·m + c]` from the identity slots of `x` after [`regression_in_place`].
pub(crate) fn bf_at<T: Real>(x: &[T], sl: &Slots, a: usize, jj: usize, c: usize) -> T {
    let q = sl.f.saturating_sub(1 + jj) * sl.m + c;
    at(x, sl.off(q) + a)
}

/// `S_Φ` (`S − F S Fᵀ = X_Y J X_Yᵀ` on the output rows `ys`, the slots from `Ȳ_0` on) into
/// the packed lower `out`, by output row in the natural order.
pub(super) fn outputs_packed<T: Real>(ys: &[T], sl: &Slots, out: &mut [T]) {
    let f = sl.f;
    let slot = |a: usize| sl.y(f - 1 - a);
    for a in (0..f).rev() {
        for b in (0..=a).rev() {
            let prev = if a + 1 < f {
                at(out, packed(a + 1, b + 1))
            } else {
                T::zero()
            };
            set(
                out,
                packed(a, b),
                jdot(ys, sl, sl.y(0), slot(a), slot(b)) + prev,
            );
        }
    }
}
