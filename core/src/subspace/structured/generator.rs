//! The generator of the bordered Gram, built from the accumulator's lagged sums and its first
//! and last samples: `u = T[:, 𝓕] L₀⁻ᵀ`, `h₊`, `v` (`u` off the first rows), `h₋`.

use super::slots::Slots;
use crate::accumulation::Accumulator;
use crate::linalg::{at, set, sub, sub_mut};
use crate::regressor::{Basis, Knots, for_each_nonzero};
use crate::scalar::Real;

/// The Gram's entries as the generator needs them: rows against the lag-`k−1` channels, and
/// diagonals, from `R_τ` less the products of the samples outside a row's window
/// (no forgetting, no centring: the structured solve refuses both before it gets here).
pub(super) struct Sums<'a, T, const M: usize, const K: usize> {
    /// The accumulated lagged sums and the first and last samples.
    pub acc: &'a Accumulator<T, M, K>,
    /// The knots the regressor was accumulated with.
    pub knots: &'a Knots<T, M>,
    /// The regressor's basis.
    pub basis: Basis,
    /// The generator's rows.
    pub sl: Slots,
}

impl<T: Real, const M: usize, const K: usize> Sums<'_, T, M, K> {
    /// Hankel columns `j`.
    fn j(&self) -> u64 {
        self.acc.columns()
    }

    /// `w(t) = [z(t); ȳ(t)]` into `out` (`c` scalars); zero if the sample is not stored.
    pub(super) fn sample(&self, t: u64, out: &mut [T]) {
        out.fill(T::zero());
        if let Some(e) = self.acc.sample(t) {
            for_each_nonzero(self.knots, self.basis, &e.at, |i, v| set(out, i, v));
            set(out, self.sl.m, e.y);
        }
    }

    /// Row `ch` of `R_τ` (channel `m` is `ȳ`) into `out`, unscaled.
    fn lagged_row(&self, tau: usize, ch: usize, out: &mut [T]) {
        let m = self.sl.m;
        out.fill(T::zero());
        let Some(r) = self.acc.lag(tau) else { return };
        let inv = T::one() / self.acc.scale;
        if ch < m {
            let row = r.zz.get(ch).map_or(&[][..], |x| &x[..]);
            for (o, &v) in out.iter_mut().zip(row).take(m) {
                *o = v * inv;
            }
            set(out, m, at(&r.zy, ch) * inv);
        } else {
            for (o, &v) in out.iter_mut().zip(&r.yz).take(m) {
                *o = v * inv;
            }
            set(out, m, r.yy * inv);
        }
    }

    /// `G[(ch, lag), 𝓕]`: row `(ch, lag)` of the Gram against the channels at lag `k − 1`,
    /// `R_τ` (`τ = k − 1 − lag`) less the products of the samples before the row's window
    /// (none fall after it at this lag difference). `ws` holds two vectors of `c`.
    pub(super) fn against_first(&self, ch: usize, lag: usize, out: &mut [T], ws: &mut [T]) {
        let c = self.sl.c;
        let tau = self.sl.k.saturating_sub(1 + lag);
        self.lagged_row(tau, ch, out);
        let (early, late) = ws.split_at_mut_checked(c).unwrap_or((&mut [], &mut []));
        for t in 0..lag as u64 {
            self.sample(t, early);
            let a = at(early, ch);
            if a == T::zero() {
                continue;
            }
            self.sample(t + tau as u64, late);
            for (o, &b) in out.iter_mut().zip(late.iter()) {
                *o -= a * b;
            }
        }
    }

    /// The Gram's diagonal entry of row `(ch, lag)`: `R_0` less the squares outside the
    /// row's window. `ws` holds a vector of `c`.
    pub(super) fn diagonal(&self, ch: usize, lag: usize, ws: &mut [T]) -> T {
        let Some(r) = self.acc.lag(0) else {
            return T::zero();
        };
        let m = self.sl.m;
        let raw = if ch < m {
            r.zz.get(ch).map_or(T::zero(), |x| at(x, ch))
        } else {
            r.yy
        };
        let mut g = raw / self.acc.scale;
        let outside = (0..lag as u64).chain(lag as u64 + self.j()..self.acc.count());
        for t in outside {
            self.sample(t, ws);
            let v = at(ws, ch);
            g -= v * v;
        }
        g
    }

    /// `w_ch(ℓ)` and `w_ch(ℓ + j)`: the entries of `h₊` and `h₋` of row `(ch, ℓ)`.
    fn edges(&self, ch: usize, lag: usize, ws: &mut [T]) -> (T, T) {
        self.sample(lag as u64, ws);
        let plus = at(ws, ch);
        self.sample(lag as u64 + self.j(), ws);
        (plus, at(ws, ch))
    }
}

/// `x ← L⁻¹ x` for the lower triangular row-major `n × n` `l`.
fn forward_solve<T: Real>(l: &[T], n: usize, x: &mut [T]) {
    for i in 0..n {
        let mut s = at(x, i);
        for (jj, &lv) in sub(l, i * n, i * n + i).iter().enumerate() {
            s -= lv * at(x, jj);
        }
        set(x, i, s / at(l, i * n + i));
    }
}

/// Cholesky factor (lower, row-major, in place) of the `n × n` `a`; `false` at a pivot not
/// above `tol` times its diagonal entry (or not finite).
fn cholesky_small<T: Real>(a: &mut [T], n: usize, tol: T) -> bool {
    for i in 0..n {
        for jj in 0..=i {
            let mut s = at(a, i * n + jj);
            for l in 0..jj {
                s -= at(a, i * n + l) * at(a, jj * n + l);
            }
            if i == jj {
                let orig = at(a, i * n + i);
                if !(s > tol * orig && s.finite()) {
                    return false;
                }
                set(a, i * n + i, s.sqrt());
            } else {
                set(a, i * n + jj, s / at(a, jj * n + jj));
            }
        }
        for jj in i + 1..n {
            set(a, i * n + jj, T::zero());
        }
    }
    true
}

/// Writes the generator into `x` (the slots) using `aux` ([`Slots::aux_len`]); `false` if the
/// Gram of the lag-`k−1` channels is not positive definite (relative pivot tolerance `tol`).
pub(super) fn build<T: Real, const M: usize, const K: usize>(
    src: &Sums<'_, T, M, K>,
    x: &mut [T],
    aux: &mut [T],
    tol: T,
) -> bool {
    let sl = src.sl;
    let (c, k, m) = (sl.c, sl.k, sl.m);
    let (l0, rest) = aux
        .split_at_mut_checked(c * c)
        .unwrap_or((&mut [], &mut []));
    let (t, ws) = rest.split_at_mut_checked(c).unwrap_or((&mut [], &mut []));
    for a in 0..c {
        src.against_first(a, k.saturating_sub(1), t, ws);
        for (d, &v) in sub_mut(l0, a * c, a * c + c).iter_mut().zip(t.iter()) {
            *d = v;
        }
    }
    if !cholesky_small(l0, c, tol) {
        return false;
    }
    x.fill(T::zero());
    let outputs = (0..sl.f).map(|a| (sl.y(a), m, k.saturating_sub(1 + a)));
    let inputs = (0..sl.km).map(|z| {
        let (ch, lag) = sl.z_row(z);
        (sl.z(z), ch, lag)
    });
    for (slot, ch, lag) in inputs.chain(outputs) {
        src.against_first(ch, lag, t, ws);
        forward_solve(l0, c, t);
        let first = lag + 1 == k;
        let (plus, minus) = if first {
            (T::zero(), T::zero())
        } else {
            src.edges(ch, lag, ws)
        };
        let row = sub_mut(x, sl.off(slot), sl.off(slot) + sl.r);
        for (s, &ts) in t.iter().enumerate() {
            set(row, s, ts);
            set(row, sl.pos + s, if first { T::zero() } else { ts });
        }
        set(row, c, plus);
        set(row, sl.pos + c, minus);
    }
    // The identity's first block: T[I_q, 𝓕] = e_q, and I_q is not a first row.
    for q in 0..m {
        t.fill(T::zero());
        set(t, q, T::one());
        forward_solve(l0, c, t);
        let row = sub_mut(x, sl.off(q), sl.off(q) + sl.r);
        for (s, &ts) in t.iter().enumerate() {
            set(row, s, ts);
            set(row, sl.pos + s, ts);
        }
    }
    true
}
