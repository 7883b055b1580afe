//! One step of the generalised Schur algorithm: reduce the pivot row to a single non-zero
//! (two Householder reflections and a hyperbolic rotation), then shift the column of `L`.

use super::Slots;
use crate::linalg::{at, dot, set, sub, sub_mut};
use crate::scalar::Real;

/// The Householder reflection `I − β w wᵀ` that maps `v` onto its first axis, as `w` (in
/// `v`) and `β`: `None` if `v` is already there. Returns the image's first entry too.
fn reflector<T: Real>(v: &mut [T]) -> (Option<T>, T) {
    let Some((&a0, tail)) = v.split_first() else {
        return (None, T::zero());
    };
    if tail.iter().all(|a| *a == T::zero()) {
        return (None, a0);
    }
    let norm = dot(v, v).sqrt();
    let alpha = if a0 >= T::zero() { -norm } else { norm };
    set(v, 0, a0 - alpha);
    (Some(T::one() / (norm * (norm + a0.abs()))), alpha)
}

/// `row ← row − β (row·w) w`, four columns at a time (`row`, `w` of a length that is a
/// multiple of 4).
#[inline(always)]
fn reflect<T: Real>(row: &mut [T], w: &[T], beta: T) {
    let (w4, _) = w.as_chunks::<4>();
    let mut a = [T::zero(); 4];
    for (x, y) in row.as_chunks::<4>().0.iter().zip(w4) {
        a[0] += x[0] * y[0];
        a[1] += x[1] * y[1];
        a[2] += x[2] * y[2];
        a[3] += x[3] * y[3];
    }
    let d = beta * ((a[0] + a[1]) + (a[2] + a[3]));
    for (x, y) in row.as_chunks_mut::<4>().0.iter_mut().zip(w4) {
        x[0] -= d * y[0];
        x[1] -= d * y[1];
        x[2] -= d * y[2];
        x[3] -= d * y[3];
    }
}

/// Reduces pivot row `Z_s` to `[δ, 0, …, 0]` on every active row (`v`: scratch of `r`) and
/// returns `δ²`, or `None` if the pivot is not positive (`|ρ| ≥ 1`, or not finite): a
/// Householder reflection on the columns of each signature, then a hyperbolic rotation of
/// columns 0 and `pos` in the mixed form (`y₀ = (x₀ − ρ x_q)/σ`, `y_q = σ x_q − ρ y₀`), which
/// keeps it stable; one pass over each row.
pub(super) fn reduce<T: Real>(x: &mut [T], sl: &Slots, s: usize, v: &mut [T]) -> Option<T> {
    let (pos, r, piv) = (sl.pos, sl.r, sl.z(s));
    let v = sub_mut(v, 0, r);
    for (d, &e) in v.iter_mut().zip(sub(x, sl.off(piv), sl.off(piv) + r)) {
        *d = e;
    }
    let (vp, vn) = v.split_at_mut_checked(pos)?;
    let (bp, a) = reflector(vp);
    let (bn, b) = reflector(vn);
    if a.abs().partial_cmp(&b.abs()) != Some(core::cmp::Ordering::Greater) {
        return None;
    }
    let rho = b / a;
    let sc = ((T::one() - rho) * (T::one() + rho)).sqrt();
    for rg in sl.active(s) {
        let rows = sub_mut(x, sl.off(rg.start), sl.off(rg.end));
        for chunk in rows.chunks_exact_mut(sl.stride.max(1)) {
            let Some((p, n)) = chunk.split_at_mut_checked(pos) else {
                continue;
            };
            let n = sub_mut(n, 0, pos);
            if let Some(beta) = bp {
                reflect(p, vp, beta);
            }
            if let Some(beta) = bn {
                reflect(n, vn, beta);
            }
            if let (Some(x0), Some(xq)) = (p.first_mut(), n.first_mut()) {
                let y0 = (*x0 - rho * *xq) / sc;
                *x0 = y0;
                *xq = sc * *xq - rho * y0;
            }
        }
    }
    Some((a - b) * (a + b))
}

/// The end of step `s`: column 0 (the column `l` of `L`) becomes `F l` on the rows alive at
/// step `s + 1`; the identity row `I_{s+m}` enters in the pivot's slot.
pub(super) fn shift<T: Real>(x: &mut [T], sl: &Slots, s: usize) {
    let m = sl.m;
    let first = |slot: usize| sl.off(slot);
    for a in (1..sl.f).rev() {
        set(x, first(sl.y(a)), at(x, first(sl.y(a - 1))));
    }
    set(x, first(sl.y(0)), T::zero());
    for z in (s + 1..sl.km).rev() {
        let v = if z >= s + m {
            at(x, first(sl.z(z - m)))
        } else {
            T::zero()
        };
        set(x, first(sl.z(z)), v);
    }
    if s >= sl.fm {
        return;
    }
    let alive = (s + 1 + m).min(sl.fm);
    if s + m < sl.fm {
        sub_mut(x, first(s + m), first(s + m) + sl.stride).fill(T::zero());
    }
    for q in (m..alive).rev() {
        set(x, first(q), at(x, first(q - m)));
    }
    for q in 0..m.min(alive) {
        set(x, first(q), T::zero());
    }
}
