//! One step of the generalised Schur algorithm: reduce the pivot row to a single non-zero
//! (two Householder reflections and a hyperbolic rotation), then shift the column of `L`.

use super::slots::Slots;
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
    for (x, v) in row.as_chunks::<4>().0.iter().zip(w4) {
        a[0] += x[0] * v[0];
        a[1] += x[1] * v[1];
        a[2] += x[2] * v[2];
        a[3] += x[3] * v[3];
    }
    let d = beta * ((a[0] + a[1]) + (a[2] + a[3]));
    for (x, v) in row.as_chunks_mut::<4>().0.iter_mut().zip(w4) {
        x[0] -= d * v[0];
        x[1] -= d * v[1];
        x[2] -= d * v[2];
        x[3] -= d * v[3];
    }
}

/// [`reflect`] on two rows at once (each chunk of `w` loaded once for both),
/// four columns at a time (lengths a multiple of 4); each row gets the bits it would get
/// alone.
#[inline(always)]
fn reflect2<T: Real>(ra: &mut [T], rb: &mut [T], w: &[T], beta: T) {
    let (w4, _) = w.as_chunks::<4>();
    let (mut a, mut b) = ([T::zero(); 4], [T::zero(); 4]);
    for ((x, y), v) in ra
        .as_chunks::<4>()
        .0
        .iter()
        .zip(rb.as_chunks::<4>().0)
        .zip(w4)
    {
        a[0] += x[0] * v[0];
        a[1] += x[1] * v[1];
        a[2] += x[2] * v[2];
        a[3] += x[3] * v[3];
        b[0] += y[0] * v[0];
        b[1] += y[1] * v[1];
        b[2] += y[2] * v[2];
        b[3] += y[3] * v[3];
    }
    let da = beta * ((a[0] + a[1]) + (a[2] + a[3]));
    let db = beta * ((b[0] + b[1]) + (b[2] + b[3]));
    let rows = ra
        .as_chunks_mut::<4>()
        .0
        .iter_mut()
        .zip(rb.as_chunks_mut::<4>().0);
    for ((x, y), v) in rows.zip(w4) {
        x[0] -= da * v[0];
        x[1] -= da * v[1];
        x[2] -= da * v[2];
        x[3] -= da * v[3];
        y[0] -= db * v[0];
        y[1] -= db * v[1];
        y[2] -= db * v[2];
        y[3] -= db * v[3];
    }
}

/// One step's transformation of the generator's rows: the reflectors of each signature's
/// columns (`None`: the identity) and the hyperbolic rotation of columns 0 and `pos`.
struct Kernel<'a, T> {
    pos: usize,
    plus: (&'a [T], Option<T>),
    minus: (&'a [T], Option<T>),
    rho: T,
    sigma: T,
}

impl<T: Real> Kernel<'_, T> {
    /// The rotation of one row's columns 0 and `pos`.
    #[inline(always)]
    fn rotate(&self, p: &mut [T], n: &mut [T]) {
        if let (Some(x0), Some(xq)) = (p.first_mut(), n.first_mut()) {
            let y0 = (*x0 - self.rho * *xq) / self.sigma;
            *x0 = y0;
            *xq = self.sigma * *xq - self.rho * y0;
        }
    }

    /// The step on one row (`r` scalars).
    #[inline(always)]
    fn row(&self, row: &mut [T]) {
        let Some((p, n)) = row.split_at_mut_checked(self.pos) else {
            return;
        };
        let n = sub_mut(n, 0, self.pos);
        if let (w, Some(beta)) = self.plus {
            reflect(p, w, beta);
        }
        if let (w, Some(beta)) = self.minus {
            reflect(n, w, beta);
        }
        self.rotate(p, n);
    }

    /// The step on two rows (`r` scalars each).
    #[inline(always)]
    fn pair(&self, ra: &mut [T], rb: &mut [T]) {
        let (Some((pa, na)), Some((pb, nb))) = (
            ra.split_at_mut_checked(self.pos),
            rb.split_at_mut_checked(self.pos),
        ) else {
            return;
        };
        let (na, nb) = (sub_mut(na, 0, self.pos), sub_mut(nb, 0, self.pos));
        if let (w, Some(beta)) = self.plus {
            reflect2(pa, pb, w, beta);
        }
        if let (w, Some(beta)) = self.minus {
            reflect2(na, nb, w, beta);
        }
        self.rotate(pa, na);
        self.rotate(pb, nb);
    }
}

/// Reduces pivot row `Z_s` to `[δ, 0, …, 0]` on every active row (`v`: scratch of `r`) and
/// returns `δ²`, or `None` if the pivot is not positive (`|ρ| ≥ 1`, or not finite): a
/// Householder reflection on the columns of each signature, then a hyperbolic rotation of
/// columns 0 and `pos` in the mixed form (`y₀ = (x₀ − ρ x_q)/σ`, `y_q = σ x_q − ρ y₀`), which
/// keeps it stable; one pass over the rows, two at a time.
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
    let kernel = Kernel {
        pos,
        plus: (vp, bp),
        minus: (vn, bn),
        rho,
        sigma: ((T::one() - rho) * (T::one() + rho)).sqrt(),
    };
    let stride = sl.stride.max(1);
    for rg in sl.active(s) {
        let rows = sub_mut(x, sl.off(rg.start), sl.off(rg.end));
        let mut pairs = rows.chunks_exact_mut(stride.saturating_mul(2));
        for two in &mut pairs {
            if let Some((ra, rb)) = two.split_at_mut_checked(stride) {
                kernel.pair(ra, rb);
            }
        }
        kernel.row(pairs.into_remainder());
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
