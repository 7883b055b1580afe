//! Substitutions with the packed lower-triangular `L₁₁`: forward (one column, four at once,
//! a column-major panel) and transposed back substitution.

use crate::linalg::{at, dot, dot4, packed, set};
use crate::scalar::Real;

/// `X ← L⁻¹ X` for the first `width` columns (`n` long) of the column-major `x`, four at a
/// time (the same bits as one at a time: [`dot4`]).
pub(super) fn forward_substitution_columns<T: Real>(l: &[T], x: &mut [T], n: usize, width: usize) {
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
pub(super) fn back_substitution_transposed<T: Real>(l: &[T], x: &mut [T]) {
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
