//! One lagged sum `R_τ = Σ_t w(t) w(t+τ)ᵀ` ([`Lagged`]), the samples it is formed from
//! ([`Entry`], and `Expanded` in the hat basis), and the products one pair of samples adds to
//! it, plain or compensated (`Adder`).

use super::summation::{Carries, OutputCarry, kahan};
use crate::direction::Direction;
use crate::regressor::{Basis, HatTerms, Knots, Located, for_each_nonzero};
use crate::scalar::Real;

/// One lagged second moment of `w = [z; ȳ]`: `Σ w(t) w(t+τ)ᵀ` split into its blocks.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lagged<T, const M: usize> {
    /// `Σ z_i(t) z_j(t+τ)`, indexed `[i][j]`.
    pub zz: [[T; M]; M],
    /// `Σ z_i(t) ȳ(t+τ)`.
    pub zy: [T; M],
    /// `Σ ȳ(t) z_j(t+τ)`.
    pub yz: [T; M],
    /// `Σ ȳ(t) ȳ(t+τ)`.
    pub yy: T,
}

impl<T: Real, const M: usize> Default for Lagged<T, M> {
    fn default() -> Self {
        Self::ZERO
    }
}

impl<T: Real, const M: usize> Lagged<T, M> {
    /// All sums zero.
    pub const ZERO: Self = Self {
        zz: [[T::ZERO; M]; M],
        zy: [T::ZERO; M],
        yz: [T::ZERO; M],
        yy: T::ZERO,
    };

    /// Adds `sign · w(s) w(s+τ)ᵀ` for the samples `early = w(s)` and `late = w(s+τ)`.
    #[inline(always)]
    pub(super) fn add_outer(
        &mut self,
        knots: &Knots<T, M>,
        basis: Basis,
        early: &Entry<T>,
        late: &Entry<T>,
        sign: T,
    ) {
        let (ye, yl) = (early.y * sign, late.y);
        for_each_nonzero(knots, basis, &early.at, |i, zi| {
            let zi = zi * sign;
            if let Some(row) = self.zz.get_mut(i) {
                for_each_nonzero(knots, basis, &late.at, |j, zj| {
                    if let Some(v) = row.get_mut(j) {
                        *v += zi * zj;
                    }
                });
            }
            if let Some(v) = self.zy.get_mut(i) {
                *v += zi * yl;
            }
        });
        for_each_nonzero(knots, basis, &late.at, |j, zj| {
            if let Some(v) = self.yz.get_mut(j) {
                *v += ye * zj;
            }
        });
        self.yy += ye * yl;
    }

    /// [`add_outer`](Self::add_outer) with the sums of products with the output (`zy`, `yz`,
    /// `yy`) compensated, their carries in `carry`.
    ///
    /// A copy of `add_outer` rather than one function generic over the addition: the generic
    /// form cost 59 more instructions per plain sample on the Cortex-M4F
    /// (`scripts/firmware-measure.sh`: 4,423 against 4,364) when this was the per-sample path
    /// of the hat basis too; it is now that of the ramps.
    #[inline(always)]
    fn add_outer_compensated(
        &mut self,
        carry: &mut OutputCarry<T, M>,
        knots: &Knots<T, M>,
        basis: Basis,
        early: &Entry<T>,
        late: &Entry<T>,
        sign: T,
    ) {
        let (ye, yl) = (early.y * sign, late.y);
        for_each_nonzero(knots, basis, &early.at, |i, zi| {
            let zi = zi * sign;
            if let Some(row) = self.zz.get_mut(i) {
                for_each_nonzero(knots, basis, &late.at, |j, zj| {
                    if let Some(v) = row.get_mut(j) {
                        *v += zi * zj;
                    }
                });
            }
            if let (Some(v), Some(c)) = (self.zy.get_mut(i), carry.zy.get_mut(i)) {
                kahan(v, c, zi * yl);
            }
        });
        for_each_nonzero(knots, basis, &late.at, |j, zj| {
            if let (Some(v), Some(c)) = (self.yz.get_mut(j), carry.yz.get_mut(j)) {
                kahan(v, c, ye * zj);
            }
        });
        kahan(&mut self.yy, &mut carry.yy, ye * yl);
    }

    /// [`add_outer`](Self::add_outer) for samples already expanded in the hat basis: the same
    /// products added in the same order, so the sums are bit for bit those of `add_outer`.
    /// The two terms of each sample are written out rather than looped over: the loop kept
    /// them in memory and cost about 40 more instructions per lag on the Cortex-M4F.
    #[inline(always)]
    fn add_hat(&mut self, early: &Expanded<T>, late: &Expanded<T>, sign: T) {
        let (ye, yl) = (early.y * sign, late.y);
        let mut row = |i: u16, zi: T| {
            let (i, zi) = (usize::from(i), zi * sign);
            if let Some(row) = self.zz.get_mut(i) {
                add_scaled(row, &late.z, zi);
            }
            if let Some(v) = self.zy.get_mut(i) {
                *v += zi * yl;
            }
        };
        let [i0, i1] = early.z.channel;
        let [z0, z1] = early.z.value;
        row(i0, z0);
        row(i1, z1);
        add_scaled(&mut self.yz, &late.z, ye);
        self.yy += ye * yl;
    }

    /// [`add_hat`](Self::add_hat) with the output sums compensated, as
    /// [`add_outer_compensated`](Self::add_outer_compensated) (a copy for the same reason).
    #[inline(always)]
    fn add_hat_compensated(
        &mut self,
        carry: &mut OutputCarry<T, M>,
        early: &Expanded<T>,
        late: &Expanded<T>,
        sign: T,
    ) {
        let (ye, yl) = (early.y * sign, late.y);
        let mut row = |i: u16, zi: T| {
            let (i, zi) = (usize::from(i), zi * sign);
            if let Some(row) = self.zz.get_mut(i) {
                add_scaled(row, &late.z, zi);
            }
            if let (Some(v), Some(c)) = (self.zy.get_mut(i), carry.zy.get_mut(i)) {
                kahan(v, c, zi * yl);
            }
        };
        let [i0, i1] = early.z.channel;
        let [z0, z1] = early.z.value;
        row(i0, z0);
        row(i1, z1);
        let mut col = |j: u16, zj: T| {
            let j = usize::from(j);
            if let (Some(v), Some(c)) = (self.yz.get_mut(j), carry.yz.get_mut(j)) {
                kahan(v, c, ye * zj);
            }
        };
        let [j0, j1] = late.z.channel;
        let [z0, z1] = late.z.value;
        col(j0, z0);
        col(j1, z1);
        kahan(&mut self.yy, &mut carry.yy, ye * yl);
    }

    /// `self *= f`, every sum.
    pub(super) fn scale(&mut self, f: T) {
        for row in self.zz.iter_mut() {
            for v in row.iter_mut() {
                *v *= f;
            }
        }
        for v in self.zy.iter_mut().chain(self.yz.iter_mut()) {
            *v *= f;
        }
        self.yy *= f;
    }
}

/// `out[j] += a · z_j` for the (at most two) terms `z` of a hat expansion, in their order.
#[inline(always)]
pub(super) fn add_scaled<T: Real, const M: usize>(out: &mut [T; M], z: &HatTerms<T>, a: T) {
    let [j0, j1] = z.channel;
    let [z0, z1] = z.value;
    if let Some(v) = out.get_mut(usize::from(j0)) {
        *v += a * z0;
    }
    if let Some(v) = out.get_mut(usize::from(j1)) {
        *v += a * z1;
    }
}

impl<T: Real> Entry<T> {
    /// A zero sample (descending, segment 0).
    pub const ZERO: Self = Self {
        at: Located {
            dir: Direction::Descending,
            segment: 0,
            theta: T::ZERO,
        },
        y: T::ZERO,
    };
}

/// One stored sample: where it is on the nonlinearity, and `ȳ = y − μ0`.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Entry<T> {
    /// Path, segment and position: determines z(t).
    pub at: Located<T>,
    /// `ȳ(t)`.
    pub y: T,
}

/// A sample of the ring as the per-sample update reads it: z(t) in the hat basis, expanded when
/// the sample entered, and `ȳ(t)`. Derived from the ring's [`Entry`]s (and rebuilt from them on
/// restore), never stored in a checkpoint.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Expanded<T> {
    /// The non-zero terms of z(t).
    pub(super) z: HatTerms<T>,
    /// `ȳ(t)`.
    y: T,
}

impl<T: Real> Expanded<T> {
    /// No terms, `ȳ = 0`.
    pub(super) const ZERO: Self = Self {
        z: HatTerms::NONE,
        y: T::ZERO,
    };

    /// The expansion of a stored sample.
    #[inline(always)]
    pub(super) fn of<const M: usize>(knots: &Knots<T, M>, e: &Entry<T>) -> Self {
        Self {
            z: HatTerms::of(knots, &e.at),
            y: e.y,
        }
    }
}

/// The additions of one sample: plain ([`PlainSums`]) or compensated ([`Carries`]), each
/// monomorphised on its own so that plain sums pay nothing for the other.
pub(super) trait Adder<T: Real, const M: usize, const K: usize> {
    /// `R_τ += w · old newᵀ`.
    #[allow(clippy::too_many_arguments)]
    fn lag(
        &mut self,
        tau: usize,
        lag: &mut Lagged<T, M>,
        knots: &Knots<T, M>,
        basis: Basis,
        old: &Entry<T>,
        new: &Entry<T>,
        w: T,
    );
    /// [`lag`](Self::lag) for samples expanded in the hat basis.
    fn lag_hat(
        &mut self,
        tau: usize,
        lag: &mut Lagged<T, M>,
        old: &Expanded<T>,
        new: &Expanded<T>,
        w: T,
    );
    /// `Σ ȳ += x`.
    fn sum_y(&mut self, s: &mut T, x: T);
    /// The sums were multiplied by `f` (renormalisation).
    fn scale(&mut self, f: T);
}

/// Plain additions.
pub(super) struct PlainSums;

impl<T: Real, const M: usize, const K: usize> Adder<T, M, K> for PlainSums {
    #[inline(always)]
    fn lag(
        &mut self,
        _: usize,
        lag: &mut Lagged<T, M>,
        knots: &Knots<T, M>,
        basis: Basis,
        old: &Entry<T>,
        new: &Entry<T>,
        w: T,
    ) {
        lag.add_outer(knots, basis, old, new, w);
    }
    #[inline(always)]
    fn lag_hat(
        &mut self,
        _: usize,
        lag: &mut Lagged<T, M>,
        old: &Expanded<T>,
        new: &Expanded<T>,
        w: T,
    ) {
        lag.add_hat(old, new, w);
    }
    #[inline(always)]
    fn sum_y(&mut self, s: &mut T, x: T) {
        *s += x;
    }
    #[inline(always)]
    fn scale(&mut self, _: T) {}
}

impl<T: Real, const M: usize, const K: usize> Adder<T, M, K> for &mut Carries<T, M, K> {
    #[inline(always)]
    fn lag(
        &mut self,
        tau: usize,
        lag: &mut Lagged<T, M>,
        knots: &Knots<T, M>,
        basis: Basis,
        old: &Entry<T>,
        new: &Entry<T>,
        w: T,
    ) {
        match self.lags.get_mut(tau) {
            Some(c) => lag.add_outer_compensated(c, knots, basis, old, new, w),
            None => lag.add_outer(knots, basis, old, new, w),
        }
    }
    #[inline(always)]
    fn lag_hat(
        &mut self,
        tau: usize,
        lag: &mut Lagged<T, M>,
        old: &Expanded<T>,
        new: &Expanded<T>,
        w: T,
    ) {
        match self.lags.get_mut(tau) {
            Some(c) => lag.add_hat_compensated(c, old, new, w),
            None => lag.add_hat(old, new, w),
        }
    }
    #[inline(always)]
    fn sum_y(&mut self, s: &mut T, x: T) {
        kahan(s, &mut self.sum_y, x);
    }
    #[inline(always)]
    fn scale(&mut self, f: T) {
        Carries::scale(self, f);
    }
}

/// `out = r − c`, block by block.
pub(super) fn subtract<T: Real, const M: usize>(
    out: &mut Lagged<T, M>,
    r: &Lagged<T, M>,
    c: &Lagged<T, M>,
) {
    for ((o, a), b) in out.zz.iter_mut().zip(&r.zz).zip(&c.zz) {
        for ((o, &a), &b) in o.iter_mut().zip(a).zip(b) {
            *o = a - b;
        }
    }
    for ((o, &a), &b) in out.zy.iter_mut().zip(&r.zy).zip(&c.zy) {
        *o = a - b;
    }
    for ((o, &a), &b) in out.yz.iter_mut().zip(&r.yz).zip(&c.yz) {
        *o = a - b;
    }
    out.yy = r.yy - c.yy;
}
