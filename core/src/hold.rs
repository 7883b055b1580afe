//! μ0 = P_a(u_min) = P_d(u_min) from an initial hold at `u_min` (Section III): the mean of the
//! output once the plant has settled.

use crate::error::Error;
use crate::scalar::Real;

/// Where μ0 comes from.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum MuZero<T> {
    /// The first `len` samples hold `u = u_min`; μ0 is the mean of `y` over the last
    /// `len − settle` of them (the first `settle` let the plant's transient die out).
    Hold {
        /// Samples in the hold.
        len: usize,
        /// Samples skipped at the start of the hold.
        settle: usize,
    },
    /// μ0 is known (e.g. measured separately); every sample is excitation.
    Known(T),
    /// No hold: μ0 is estimated with the model. Every Hankel row is centred (the constant is
    /// projected out of eq. 11 and of the least squares for `B`, `D`), and after the rank-1
    /// split `μ0 = mean(y) − μ·mean(z)`, which holds because `G(1) = 1`. For records that did
    /// not start with a hold, or whose input is not the Table I excitation.
    Estimate,
}

impl<T: Real> MuZero<T> {
    /// Checks the hold leaves samples to average, and that a known μ0 is finite.
    pub fn validate(&self) -> Result<(), Error> {
        match *self {
            MuZero::Hold { len, settle } if settle >= len => {
                Err(Error::HoldTooShort { len, settle })
            }
            MuZero::Known(v) if !v.finite() => Err(Error::InvalidMu0 { value: v.to_f64() }),
            _ => Ok(()),
        }
    }

    /// Number of leading samples that belong to the hold.
    pub fn hold_len(&self) -> usize {
        match *self {
            MuZero::Hold { len, .. } => len,
            MuZero::Known(_) | MuZero::Estimate => 0,
        }
    }
}

/// Running mean of the settled part of the hold, with compensated (Kahan) summation so that
/// long holds in `f32` lose no precision.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct HoldMean<T> {
    pub(crate) sum: T,
    pub(crate) comp: T,
    pub(crate) count: u32,
}

impl<T: Real> HoldMean<T> {
    /// Nothing accumulated.
    pub const ZERO: Self = Self {
        sum: T::ZERO,
        comp: T::ZERO,
        count: 0,
    };

    /// Adds one settled hold sample.
    #[inline]
    pub fn push(&mut self, y: T) {
        let v = y - self.comp;
        let s = self.sum + v;
        self.comp = (s - self.sum) - v;
        self.sum = s;
        self.count = self.count.saturating_add(1);
    }

    /// The mean so far (`None` before the first sample).
    pub fn mean(&self) -> Option<T> {
        (self.count > 0).then(|| self.sum / T::of(self.count as f64))
    }
}
