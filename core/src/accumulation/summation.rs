//! How the sums are formed, chosen by type ([`Summation`]): plain floating-point sums, or sums
//! of the products with the output compensated by Kahan summation, with the carries they keep
//! ([`Carries`], one [`OutputCarry`] per lag).

use crate::scalar::Real;

/// `s += x` by compensated (Kahan) summation: the carry `c` keeps the low-order part of the
/// last addition that the rounded sum lost and takes it off the next addend, so the rounding
/// error of a long sum stays at a few ulps instead of growing with its length.
#[inline(always)]
pub(super) fn kahan<T: Real>(s: &mut T, c: &mut T, x: T) {
    let y = x - *c;
    let t = *s + y;
    *c = (t - *s) - y;
    *s = t;
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
    pub(super) fn scale(&mut self, f: T) {
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
