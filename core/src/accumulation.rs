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
//! two channels. For the hat basis the ring also keeps each sample's two terms of z(t), expanded
//! once when it enters (and rebuilt from the stored samples on restore; checkpoints do not hold
//! them), so one update costs `O(k)` multiply-adds and no expansion per lag.

use crate::direction::Direction;
use crate::error::Error;
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
    fn scale(&mut self, f: T) {
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
fn add_scaled<T: Real, const M: usize>(out: &mut [T; M], z: &HatTerms<T>, a: T) {
    let [j0, j1] = z.channel;
    let [z0, z1] = z.value;
    if let Some(v) = out.get_mut(usize::from(j0)) {
        *v += a * z0;
    }
    if let Some(v) = out.get_mut(usize::from(j1)) {
        *v += a * z1;
    }
}

/// `s += x` by compensated (Kahan) summation: the carry `c` keeps the low-order part of the
/// last addition that the rounded sum lost and takes it off the next addend, so the rounding
/// error of a long sum stays at a few ulps instead of growing with its length.
#[inline(always)]
fn kahan<T: Real>(s: &mut T, c: &mut T, x: T) {
    let y = x - *c;
    let t = *s + y;
    *c = (t - *s) - y;
    *s = t;
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
    z: HatTerms<T>,
    /// `ȳ(t)`.
    y: T,
}

impl<T: Real> Expanded<T> {
    /// No terms, `ȳ = 0`.
    const ZERO: Self = Self {
        z: HatTerms::NONE,
        y: T::ZERO,
    };

    /// The expansion of a stored sample.
    #[inline(always)]
    fn of<const M: usize>(knots: &Knots<T, M>, e: &Entry<T>) -> Self {
        Self {
            z: HatTerms::of(knots, &e.at),
            y: e.y,
        }
    }
}

/// The carries of the compensated sums of one lag: those of the products with the output.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OutputCarry<T, const M: usize> {
    /// Carries of `Σ z_i(t) ȳ(t+τ)`.
    pub zy: [T; M],
    /// Carries of `Σ ȳ(t) z_j(t+τ)`.
    pub yz: [T; M],
    /// Carry of `Σ ȳ(t) ȳ(t+τ)`.
    pub yy: T,
}

impl<T: Real, const M: usize> OutputCarry<T, M> {
    /// All carries zero.
    pub const ZERO: Self = Self {
        zy: [T::ZERO; M],
        yz: [T::ZERO; M],
        yy: T::ZERO,
    };

    /// `self *= f`.
    fn scale(&mut self, f: T) {
        for v in self.zy.iter_mut().chain(self.yz.iter_mut()) {
            *v *= f;
        }
        self.yy *= f;
    }
}

/// The carries of compensated summation ([`Compensated`]): what the rounded sums of products
/// with the output (`zy`, `yz`, `yy` of every lag, and `Σ ȳ`) lost in their last additions.
///
/// Only those sums are compensated: on the paper's experiment in `f32` at 10^6 samples,
/// compensating them brings the model and the singular values within the long-run tolerance
/// (the largest deviation a quarter of the tolerance), compensating the input sums `zz` alone
/// changes nothing, and compensating those as well gains little (`docs/reliability.md`, *Long
/// runs*) for `k·m²` more carries. The output sums feed the difference
/// `Ȳ_f Ȳ_fᵀ − (its projection on the instruments)`, whose small remainder is the noise floor.
#[derive(Clone, Debug, PartialEq)]
pub struct Carries<T, const M: usize, const K: usize> {
    /// Carries of the output sums of the lagged sums `R_τ`.
    pub lags: [OutputCarry<T, M>; K],
    /// Carry of `Σ ȳ`.
    pub sum_y: T,
}

impl<T: Real, const M: usize, const K: usize> Carries<T, M, K> {
    /// All carries zero.
    pub const ZERO: Self = Self {
        lags: [OutputCarry::ZERO; K],
        sum_y: T::ZERO,
    };

    /// `self *= f`, every carry (with the sums, on renormalisation).
    fn scale(&mut self, f: T) {
        for lag in self.lags.iter_mut() {
            lag.scale(f);
        }
        self.sum_y *= f;
    }
}

/// How an identifier forms its sums, chosen by type: [`Plain`] floating-point sums (the
/// default; no extra memory) or [`Compensated`] sums, which keep a Kahan carry for each sum of
/// products with the output (`k·(2m + 1) + 1` scalars: 2.3 KB for the paper's `f32`
/// configuration, m = 14, k = 20) and cost about 780 more instructions per sample on a
/// Cortex-M4F, but keep `f32` models within the long-run tolerance of `f64` at 10^6 samples,
/// where plain `f32` sums are 14 times outside it. In `f64` plain sums are exact enough for
/// any practical record. Numbers: `docs/reliability.md`, *Long runs*.
pub trait Summation<T: Real, const M: usize, const K: usize>:
    Copy + Clone + core::fmt::Debug + Default + PartialEq + Eq + 'static
{
    /// What is kept besides the sums: `()` (zero-sized) for [`Plain`], [`Carries`] for
    /// [`Compensated`].
    type Carry: Clone + core::fmt::Debug + PartialEq;
    /// The carry of empty sums, usable in constant expressions.
    const ZERO: Self::Carry;
    /// Code of the summation in checkpoints (0 plain, 1 compensated).
    const CODE: u8;
    /// How the sums of products with the output round, which sets the rounding level the
    /// solve assumes for them.
    const OUTPUT_ROUNDING: OutputRounding;
    /// The carries, if this summation keeps any.
    fn carries(carry: &Self::Carry) -> Option<&Carries<T, M, K>>;
    /// The carries, mutable, if this summation keeps any.
    fn carries_mut(carry: &mut Self::Carry) -> Option<&mut Carries<T, M, K>>;
}

/// How the accumulated sums of products with the output (`zy`, `yz`, `yy`) round.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OutputRounding {
    /// Recursive summation: a relative error of about `ε·√j` over `j` columns.
    Recursive,
    /// Kahan-compensated summation: about `2ε`, whatever `j` (up to `O(j·ε²)`).
    Compensated,
}

/// Plain floating-point sums: no memory beyond the sums themselves.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Plain;

/// Compensated (Kahan) sums of the products with the output ([`Carries`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Compensated;

impl<T: Real, const M: usize, const K: usize> Summation<T, M, K> for Plain {
    type Carry = ();
    const ZERO: () = ();
    const CODE: u8 = 0;
    const OUTPUT_ROUNDING: OutputRounding = OutputRounding::Recursive;
    #[inline(always)]
    fn carries(_: &()) -> Option<&Carries<T, M, K>> {
        None
    }
    #[inline(always)]
    fn carries_mut(_: &mut ()) -> Option<&mut Carries<T, M, K>> {
        None
    }
}

impl<T: Real, const M: usize, const K: usize> Summation<T, M, K> for Compensated {
    type Carry = Carries<T, M, K>;
    const ZERO: Carries<T, M, K> = Carries::ZERO;
    const CODE: u8 = 1;
    const OUTPUT_ROUNDING: OutputRounding = OutputRounding::Compensated;
    #[inline(always)]
    fn carries(carry: &Carries<T, M, K>) -> Option<&Carries<T, M, K>> {
        Some(carry)
    }
    #[inline(always)]
    fn carries_mut(carry: &mut Carries<T, M, K>) -> Option<&mut Carries<T, M, K>> {
        Some(carry)
    }
}

/// The streaming accumulator: lagged sums for `τ = 0 … k−1`, the first `k` samples and the
/// last `k` samples, for up to `M` regressor channels and up to `K` block rows (`k = f + p`).
#[derive(Clone, Debug)]
pub struct Accumulator<T, const M: usize, const K: usize> {
    pub(crate) lags: [Lagged<T, M>; K],
    pub(crate) head: [Entry<T>; K],
    pub(crate) ring: [Entry<T>; K],
    /// The ring's samples expanded in the hat basis, slot for slot (unused for the ramps).
    pub(crate) expanded: [Expanded<T>; K],
    pub(crate) k: usize,
    pub(crate) pos: usize,
    pub(crate) count: u64,
    pub(crate) sum_z: [T; M],
    pub(crate) sum_y: T,
    /// Forgetting factor λ (1: none). Column `c` of the Hankel matrices has weight
    /// `λ^{j−1−c}`: the newest column 1, older ones less.
    pub(crate) lambda: T,
    /// Stored sums are the true λ-weighted sums times `scale`; new products enter multiplied
    /// by it, and it grows by `1/λ` per sample until a renormalisation folds it back to 1.
    pub(crate) scale: T,
}

/// Renormalise the stored sums when their scale passes this (a power of two, so the
/// renormalisation is exact in binary floating point up to the sums' own rounding).
pub(crate) const RENORM: f64 = 65536.0;

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
        expanded: [Expanded::ZERO; K],
        k: 2,
        pos: 0,
        count: 0,
        sum_z: [T::ZERO; M],
        sum_y: T::ZERO,
        lambda: T::ONE,
        scale: T::ONE,
    };

    /// Empties the accumulator in place for `k` block rows (`2 <= k <= K`), without building
    /// a new value on the stack. No forgetting ([`set_forgetting`](Self::set_forgetting)).
    pub fn reset(&mut self, k: usize) -> Result<(), Error> {
        if !(2..=K).contains(&k) {
            return Err(Error::InvalidHorizon {
                f: 0,
                k,
                max_f: K.saturating_sub(1),
                max_k: K,
            });
        }
        self.lambda = T::one();
        self.scale = T::one();
        for l in self.lags.iter_mut() {
            *l = Lagged::ZERO;
        }
        self.head.fill(Entry::ZERO);
        self.ring.fill(Entry::ZERO);
        self.expanded.fill(Expanded::ZERO);
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
        let mut acc = Self::EMPTY;
        acc.reset(k)?;
        Ok(acc)
    }

    /// Sets the forgetting factor λ (`0 < λ <= 1`; 1 = none) for the samples to come.
    pub fn set_forgetting(&mut self, lambda: T) -> Result<(), Error> {
        self.lambda = checked_forgetting(lambda)?;
        Ok(())
    }

    /// The forgetting factor λ (1: none).
    pub fn forgetting(&self) -> T {
        self.lambda
    }

    /// `λ^e` for a non-negative integer exponent (0 for underflow), in `f64`.
    fn lambda_pow(&self, e: u64) -> T {
        if self.lambda == T::one() {
            T::one()
        } else {
            T::of(libm::pow(self.lambda.to_f64(), e as f64))
        }
    }

    /// Sum of the column weights: `j` without forgetting, `(1 − λ^j)/(1 − λ)` with.
    pub fn effective_columns(&self) -> T {
        self.weight_sum(self.columns())
    }

    /// `Σ_{i<n} λ^i`.
    fn weight_sum(&self, n: u64) -> T {
        if self.lambda == T::one() {
            T::of(n as f64)
        } else {
            let l = self.lambda.to_f64();
            T::of((1.0 - libm::pow(l, n as f64)) / (1.0 - l))
        }
    }

    /// The λ-weighted means of z and ȳ over all samples (weight `λ^{N−1−t}`).
    pub fn weighted_means(&self) -> ([T; M], T) {
        let w = self.weight_sum(self.count) * self.scale;
        let mut z = self.sum_z;
        for v in z.iter_mut() {
            *v /= w;
        }
        (z, self.sum_y / w)
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
        self.count.saturating_add(1).saturating_sub(self.k as u64)
    }

    /// Sums of `z` and `ȳ` over all samples, as stored (λ-weighted and scaled when
    /// forgetting; see [`weighted_means`](Self::weighted_means)).
    pub fn sums(&self) -> (&[T; M], T) {
        (&self.sum_z, self.sum_y)
    }

    /// Row sums of every block row over its `j` columns: the total minus the samples before
    /// the row's window (head) and after it (tail).
    pub fn row_sums(&self, knots: &Knots<T, M>, basis: Basis) -> RowSums<T, M, K> {
        // Stored sums carry the weight λ^{N−1−t}·scale; a row's window gets λ^{j−1−c}, which
        // is λ^{N−1−t}·λ^{a−(k−1)}: remove the samples outside the window with their stored
        // weights, then rescale.
        let mut out = RowSums {
            z: [self.sum_z; K],
            y: [self.sum_y; K],
        };
        let j = self.columns();
        let n = self.count;
        let k = self.k;
        for (a, (rz, ry)) in out.z.iter_mut().zip(out.y.iter_mut()).enumerate().take(k) {
            let a64 = a as u64;
            let outside = (0..a64).chain(a64.saturating_add(j)..n);
            for t in outside {
                if let Some(e) = self.sample(t) {
                    let wt = self.lambda_pow(n - 1 - t) * self.scale;
                    for_each_nonzero(knots, basis, &e.at, |i, v| {
                        if let Some(s) = rz.get_mut(i) {
                            *s -= v * wt;
                        }
                    });
                    *ry -= e.y * wt;
                }
            }
            let f = self.row_factor(a);
            for v in rz.iter_mut() {
                *v *= f;
            }
            *ry *= f;
        }
        out
    }

    /// From stored (scaled, λ^{N−1−·}-weighted) sums to the weighted Hankel Gram of a block
    /// whose later block row is `b`: `λ^{−(k−1−b)} / scale`.
    fn row_factor(&self, b: usize) -> T {
        let up = self.k.saturating_sub(1).saturating_sub(b) as u64;
        if self.lambda == T::one() {
            T::one() / self.scale
        } else {
            T::one() / (self.lambda_pow(up) * self.scale)
        }
    }

    /// The lagged sum `R_τ` (`None` for `τ >= k`).
    pub fn lag(&self, tau: usize) -> Option<&Lagged<T, M>> {
        self.lags.get(..self.k).and_then(|l| l.get(tau))
    }

    /// Adds one sample. `O(k)` work for the hat basis; no allocation, no failure.
    pub fn push(&mut self, knots: &Knots<T, M>, basis: Basis, at: Located<T>, y: T) {
        self.push_with(PlainSums, knots, basis, at, y);
    }

    /// [`push`](Self::push) with compensated (Kahan) summation of the output sums, their
    /// carries kept in `carries` (which must have started at [`Carries::ZERO`] with the
    /// accumulator and seen every sample since).
    pub fn push_compensated(
        &mut self,
        carries: &mut Carries<T, M, K>,
        knots: &Knots<T, M>,
        basis: Basis,
        at: Located<T>,
        y: T,
    ) {
        self.push_with(carries, knots, basis, at, y);
    }

    /// One sample, the additions made by `add` (plain or compensated, each its own code).
    #[inline(always)]
    fn push_with<A: Adder<T, M, K>>(
        &mut self,
        mut add: A,
        knots: &Knots<T, M>,
        basis: Basis,
        at: Located<T>,
        y: T,
    ) {
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
        // Forgetting: every stored sum decays by λ, which is the same as new products
        // entering 1/λ larger.
        if self.lambda != T::one() {
            self.scale /= self.lambda;
        }
        let w = self.scale;
        let lags_now = usize::try_from(self.count).map_or(k, |c| c.saturating_add(1).min(k));
        match basis {
            Basis::Hat => self.add_lags_hat(&mut add, knots, &new, lags_now, w),
            Basis::Ramp => {
                for tau in 0..lags_now {
                    let idx = (self.pos + k - tau) % k;
                    if let (Some(old), Some(lag)) = (self.ring.get(idx), self.lags.get_mut(tau)) {
                        add.lag(tau, lag, knots, basis, old, &new, w);
                    }
                }
                for_each_nonzero(knots, basis, &at, |i, v| {
                    if let Some(s) = self.sum_z.get_mut(i) {
                        *s += v * w;
                    }
                });
            }
        }
        self.pos = (self.pos + 1) % k;
        add.sum_y(&mut self.sum_y, y * w);
        // Saturating: 2^64 samples are out of reach, but the per-sample path must not be able
        // to overflow whatever state it was restored to.
        self.count = self.count.saturating_add(1);
        if self.scale > T::of(RENORM) {
            let inv = self.renormalise();
            add.scale(inv);
        }
    }

    /// The lagged sums `R_τ`, `τ < lags`, and `Σ z` of the sample `new` (just stored in the
    /// ring at `pos`) in the hat basis: `new` is expanded once, the older samples were when
    /// they entered. The same products in the same order as the general path, so the same sums
    /// bit for bit.
    #[inline(always)]
    fn add_lags_hat<A: Adder<T, M, K>>(
        &mut self,
        add: &mut A,
        knots: &Knots<T, M>,
        new: &Entry<T>,
        lags: usize,
        w: T,
    ) {
        let z = Expanded::of(knots, new);
        if let Some(slot) = self.expanded.get_mut(self.pos) {
            *slot = z;
        }
        // The common case, both terms present and no forgetting (w = 1), gets its own copy of
        // the loop, in which the bounds of the new sample's channels are checked once and the
        // products with w (exact, x·1 = x) vanish: 157 fewer instructions per sample (about 8
        // per lag) on the Cortex-M4F. Same operations on the sums either way.
        let [j0, j1] = z.z.channel;
        if usize::from(j0) < M && usize::from(j1) < M && w == T::one() {
            self.lag_loop_hat(add, &z, lags, T::one());
        } else {
            self.lag_loop_hat(add, &z, lags, w);
        }
        add_scaled(&mut self.sum_z, &z.z, w);
    }

    /// `R_τ += w · x(count − τ) zᵀ` for `τ < lags`, the older samples from the ring.
    #[inline(always)]
    fn lag_loop_hat<A: Adder<T, M, K>>(&mut self, add: &mut A, z: &Expanded<T>, lags: usize, w: T) {
        // Sample `count − τ` is in slot `pos − τ`, walking back around the ring: slots
        // `pos, pos − 1, …, 0`, then `k − 1, k − 2, …`. Two loops over slices, one per stretch,
        // so that no slot index is computed or checked (about 10 instructions per lag fewer
        // than indexing the ring on the Cortex-M4F).
        let k = self.k.clamp(1, K);
        let ring = self.expanded.get(..k).unwrap_or(&[]);
        let (to_start, from_end) = ring
            .split_at_checked(self.pos.saturating_add(1))
            .unwrap_or((ring, &[]));
        let mut lags = self
            .lags
            .get_mut(..lags)
            .unwrap_or(&mut [])
            .iter_mut()
            .enumerate();
        for (old, (tau, lag)) in to_start.iter().rev().zip(&mut lags) {
            add.lag_hat(tau, lag, old, z, w);
        }
        for (old, (tau, lag)) in from_end.iter().rev().zip(lags) {
            add.lag_hat(tau, lag, old, z, w);
        }
    }

    /// Re-expands the ring's samples ([`Expanded`]) after they were set from outside the
    /// per-sample path (restoring a checkpoint). `knots` must be those of the pushes.
    pub(crate) fn rebuild_expanded(&mut self, knots: &Knots<T, M>) {
        for (x, e) in self.expanded.iter_mut().zip(&self.ring) {
            *x = Expanded::of(knots, e);
        }
    }

    /// Folds the scale back into the stored sums (rare: every
    /// `log(RENORM)/log(1/λ)` samples).
    /// Returns the factor applied, for the carries.
    fn renormalise(&mut self) -> T {
        let inv = T::one() / self.scale;
        for lag in self.lags.iter_mut() {
            lag.scale(inv);
        }
        for v in self.sum_z.iter_mut() {
            *v *= inv;
        }
        self.sum_y *= inv;
        self.scale = T::one();
        inv
    }

    /// Sample `t` if it is still stored (among the first `k` or the last `k`).
    pub(crate) fn sample(&self, t: u64) -> Option<&Entry<T>> {
        let k = self.k.clamp(1, K);
        if t < k as u64 {
            return self.head.get(t as usize);
        }
        if t >= self.count || t.saturating_add(k as u64) < self.count {
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
            // Stored weight of the product w(t) w(t+τ)ᵀ: λ^{N−1−t−τ}·scale.
            let weight = |t: u64| self.lambda_pow(n - 1 - t - tau64) * self.scale;
            // Tail correction for a = 0: samples t = j … N−1−τ.
            let mut t = j;
            while t.saturating_add(tau64) < n {
                if let (Some(e), Some(l)) = (self.sample(t), self.sample(t + tau64)) {
                    corr.add_outer(knots, basis, e, l, weight(t));
                }
                t += 1;
            }
            for a in 0..(k - tau) {
                if want(a, a + tau) {
                    subtract(&mut block, r, &corr);
                    let f = self.row_factor(a + tau);
                    if f != T::one() {
                        block.scale(f);
                    }
                    sink(a, a + tau, &block);
                }
                let a64 = a as u64;
                // Move the window one column: the head gains w(a), the tail loses w(a + j).
                if let (Some(e), Some(l)) = (self.sample(a64), self.sample(a64 + tau64)) {
                    corr.add_outer(knots, basis, e, l, weight(a64));
                }
                let late = a64.saturating_add(j);
                if let (Some(e), Some(l)) =
                    (self.sample(late), self.sample(late.saturating_add(tau64)))
                {
                    corr.add_outer(knots, basis, e, l, -weight(late));
                }
            }
        }
    }
}

/// The additions of one sample: plain ([`PlainSums`]) or compensated ([`Carries`]), each
/// monomorphised on its own so that plain sums pay nothing for the other.
trait Adder<T: Real, const M: usize, const K: usize> {
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
struct PlainSums;

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

/// A forgetting factor if it lies in `(0, 1]`.
pub(crate) fn checked_forgetting<T: Real>(lambda: T) -> Result<T, Error> {
    let valid = lambda > T::zero() && lambda <= T::one() && lambda.finite();
    if valid {
        Ok(lambda)
    } else {
        Err(Error::InvalidForgetting {
            lambda: lambda.to_f64(),
        })
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
