//! Streaming accumulation of the block-Hankel products in memory independent of the number of
//! samples.
//!
//! Stack the signals as `w(t) = [z(t); ȳ(t)]`. Block row `a` of the `k = f + p` block-row
//! Hankel matrix holds `w(a), …, w(a + j − 1)`. Each block of its Gram matrix is a lagged sum
//! over a window (`τ = b − a ≥ 0`):
//!
//! ```text
//! G[a, b] = Σ_{t=a}^{a+j−1} w(t) w(t+τ)ᵀ = R_τ − Σ_{t<a} w(t) w(t+τ)ᵀ − Σ_{t≥a+j} w(t) w(t+τ)ᵀ
//! ```
//!
//! with the full-range lagged sums `R_τ = Σ_t w(t) w(t+τ)ᵀ`. The corrections involve only the
//! first `k` and the last `k` samples, so the accumulator keeps `R_0 … R_{k−1}`, the first `k`
//! samples and a ring of the last `k`: `k·(m+1)²` sums plus `2k` samples, whatever the length
//! of the experiment. The type's `M` and `K` are capacities (`m <= M`, `k <= K`): firmware
//! sets them to the exact sizes, a desktop tool to the largest it accepts. The Gram blocks it produces are those of the explicit Hankel matrices,
//! exactly (up to rounding). Samples are stored as their position on the nonlinearity
//! ([`Located`]) and `ȳ`; z(t) is re-expanded on demand, which for the hat basis touches at most
//! two channels, so one update costs `O(k)` multiply-adds.

use crate::error::Error;
use crate::regressor::{Basis, Direction, Knots, Located, for_each_nonzero};
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
        Self {
            zz: [[T::zero(); M]; M],
            zy: [T::zero(); M],
            yz: [T::zero(); M],
            yy: T::zero(),
        }
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
    fn add_outer(
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

/// The streaming accumulator: lagged sums for `τ = 0 … k−1`, the first `k` samples and the
/// last `k` samples, for up to `M` regressor channels and up to `K` block rows (`k = f + p`).
#[derive(Clone, Debug)]
pub struct Accumulator<T, const M: usize, const K: usize> {
    pub(crate) lags: [Lagged<T, M>; K],
    pub(crate) head: [Entry<T>; K],
    pub(crate) ring: [Entry<T>; K],
    pub(crate) k: usize,
    pub(crate) pos: usize,
    pub(crate) count: u64,
    pub(crate) sum_z: [T; M],
    pub(crate) sum_y: T,
}

/// Sums of `z` and `ȳ` over the columns of every block row of the Hankel matrix (for
/// centring the rows when μ0 is estimated from the data).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RowSums<T, const M: usize, const K: usize> {
    /// `Σ_c z(a + c)` for block row `a`.
    pub z: [[T; M]; K],
    /// `Σ_c ȳ(a + c)` for block row `a`.
    pub y: [T; K],
}

impl<T: Real, const M: usize, const K: usize> Accumulator<T, M, K> {
    /// An empty accumulator for `k = 2` block rows, usable in constant expressions so that a
    /// `static` can hold it; [`reset`](Self::reset) sets the block rows in place.
    pub const EMPTY: Self = Self {
        lags: [Lagged::ZERO; K],
        head: [Entry::ZERO; K],
        ring: [Entry::ZERO; K],
        k: 2,
        pos: 0,
        count: 0,
        sum_z: [T::ZERO; M],
        sum_y: T::ZERO,
    };

    /// Empties the accumulator in place for `k` block rows (`2 <= k <= K`), without building
    /// a new value on the stack.
    pub fn reset(&mut self, k: usize) -> Result<(), Error> {
        if !(2..=K).contains(&k) {
            return Err(Error::InvalidHorizon { f: 0, k });
        }
        for l in self.lags.iter_mut() {
            *l = Lagged::ZERO;
        }
        self.head.fill(Entry::ZERO);
        self.ring.fill(Entry::ZERO);
        self.sum_z.fill(T::ZERO);
        self.sum_y = T::ZERO;
        self.k = k;
        self.pos = 0;
        self.count = 0;
        Ok(())
    }

    /// An empty accumulator for `k = f + p` block rows (`2 <= k <= K`).
    pub fn new(k: usize) -> Result<Self, Error> {
        const { assert!(K >= 2, "K (block rows f + p) must be at least 2") };
        const { assert!(M >= 2, "M (segments on both paths) must be at least 2") };
        if !(2..=K).contains(&k) {
            return Err(Error::InvalidHorizon { f: 0, k });
        }
        Ok(Self {
            lags: [Lagged::default(); K],
            head: [Entry::default(); K],
            ring: [Entry::default(); K],
            k,
            pos: 0,
            count: 0,
            sum_z: [T::zero(); M],
            sum_y: T::zero(),
        })
    }

    /// Block rows `k = f + p`.
    pub fn block_rows(&self) -> usize {
        self.k
    }

    /// Samples accumulated so far (`N`).
    pub fn count(&self) -> u64 {
        self.count
    }

    /// Hankel columns `j = N − k + 1` (0 while `N < k`).
    pub fn columns(&self) -> u64 {
        (self.count + 1).saturating_sub(self.k as u64)
    }

    /// Sums of `z` and `ȳ` over all samples.
    pub fn sums(&self) -> (&[T; M], T) {
        (&self.sum_z, self.sum_y)
    }

    /// Row sums of every block row over its `j` columns: the total minus the samples before
    /// the row's window (head) and after it (tail).
    pub fn row_sums(&self, knots: &Knots<T, M>, basis: Basis) -> RowSums<T, M, K> {
        let mut out = RowSums {
            z: [self.sum_z; K],
            y: [self.sum_y; K],
        };
        let j = self.columns();
        for (a, (rz, ry)) in out
            .z
            .iter_mut()
            .zip(out.y.iter_mut())
            .enumerate()
            .take(self.k)
        {
            let a64 = a as u64;
            let outside = (0..a64).chain((a64 + j)..self.count);
            for t in outside {
                if let Some(e) = self.sample(t) {
                    for_each_nonzero(knots, basis, &e.at, |i, v| {
                        if let Some(s) = rz.get_mut(i) {
                            *s -= v;
                        }
                    });
                    *ry -= e.y;
                }
            }
        }
        out
    }

    /// The lagged sum `R_τ` (`None` for `τ >= k`).
    pub fn lag(&self, tau: usize) -> Option<&Lagged<T, M>> {
        self.lags.get(..self.k).and_then(|l| l.get(tau))
    }

    /// Adds one sample. `O(k)` work for the hat basis; no allocation, no failure.
    pub fn push(&mut self, knots: &Knots<T, M>, basis: Basis, at: Located<T>, y: T) {
        let new = Entry { at, y };
        if let Some(slot) = usize::try_from(self.count)
            .ok()
            .and_then(|t| self.head.get_mut(t))
        {
            *slot = new;
        }
        if let Some(slot) = self.ring.get_mut(self.pos) {
            *slot = new;
        }
        let k = self.k.clamp(1, K);
        let lags_now = usize::try_from(self.count).map_or(k, |c| c.saturating_add(1).min(k));
        for tau in 0..lags_now {
            let idx = (self.pos + k - tau) % k;
            if let (Some(old), Some(lag)) = (self.ring.get(idx), self.lags.get_mut(tau)) {
                lag.add_outer(knots, basis, old, &new, T::one());
            }
        }
        self.pos = (self.pos + 1) % k;
        for_each_nonzero(knots, basis, &at, |i, v| {
            if let Some(s) = self.sum_z.get_mut(i) {
                *s += v;
            }
        });
        self.sum_y += y;
        self.count += 1;
    }

    /// Sample `t` if it is still stored (among the first `k` or the last `k`).
    fn sample(&self, t: u64) -> Option<&Entry<T>> {
        let k = self.k.clamp(1, K);
        if t < k as u64 {
            return self.head.get(t as usize);
        }
        if t >= self.count || t + (k as u64) < self.count {
            return None;
        }
        // The ring slot of sample t: pos points at sample `count`'s slot.
        let back = (self.count - t) as usize; // 1..=k
        self.ring.get((self.pos + k - back) % k)
    }

    /// Visits every upper block `G[a, b]` (`a <= b < k`) of the Gram of the stacked Hankel
    /// matrix with `j = N − k + 1` columns, as `sink(a, b, block)`. Needs `N >= k`.
    ///
    /// Blocks along one lag are produced with a running correction, so the whole Gram costs
    /// `O(k²·M²)` and one `Lagged` of scratch.
    pub fn for_each_block(
        &self,
        knots: &Knots<T, M>,
        basis: Basis,
        sink: impl FnMut(usize, usize, &Lagged<T, M>),
    ) {
        self.for_each_block_where(knots, basis, |_, _| true, sink);
    }

    /// [`for_each_block`](Self::for_each_block) for the blocks `(a, b)` with `want(a, b)`
    /// only: the running corrections are still updated for every block, but the others are
    /// neither formed nor passed on.
    pub fn for_each_block_where(
        &self,
        knots: &Knots<T, M>,
        basis: Basis,
        want: impl Fn(usize, usize) -> bool,
        mut sink: impl FnMut(usize, usize, &Lagged<T, M>),
    ) {
        let j = self.columns();
        if j == 0 {
            return;
        }
        let n = self.count;
        let mut block = Lagged::<T, M>::default();
        let k = self.k;
        for (tau, r) in self.lags.iter().take(k).enumerate() {
            let tau64 = tau as u64;
            let mut corr = Lagged::<T, M>::default();
            // Tail correction for a = 0: samples t = j … N−1−τ.
            let mut t = j;
            while t + tau64 < n {
                if let (Some(e), Some(l)) = (self.sample(t), self.sample(t + tau64)) {
                    corr.add_outer(knots, basis, e, l, T::one());
                }
                t += 1;
            }
            for a in 0..(k - tau) {
                if want(a, a + tau) {
                    subtract(&mut block, r, &corr);
                    sink(a, a + tau, &block);
                }
                let a64 = a as u64;
                // Move the window one column: the head gains w(a), the tail loses w(a + j).
                if let (Some(e), Some(l)) = (self.sample(a64), self.sample(a64 + tau64)) {
                    corr.add_outer(knots, basis, e, l, T::one());
                }
                if let (Some(e), Some(l)) = (self.sample(a64 + j), self.sample(a64 + j + tau64)) {
                    corr.add_outer(knots, basis, e, l, -T::one());
                }
            }
        }
    }
}

/// `out = r − c`, block by block.
fn subtract<T: Real, const M: usize>(out: &mut Lagged<T, M>, r: &Lagged<T, M>, c: &Lagged<T, M>) {
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
