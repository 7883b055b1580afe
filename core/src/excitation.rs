//! The excitation of Table I: an initial hold at `u_min` (for μ0), then the cycle
//! random level, `u_max`, random level, `u_min`, repeated.
//!
//! Random levels are uniform on the open interval `]u_min, u_max[` (Remark 2). Every ascending
//! run starts at `u_min` and ends at `u_max` and every descending run the reverse, so the
//! nonlinearity always travels the same ascending and descending paths, and the random level
//! one sample in two makes the input persistently exciting.
//!
//! ```
//! use hsid::Excitation;
//! use rand_pcg::Pcg32;
//! use rand_core::SeedableRng;
//!
//! let u: Vec<f64> = Excitation::new(-3.0, 3.0, 2, Pcg32::seed_from_u64(1))?.take(7).collect();
//! assert_eq!(&u[..2], &[-3.0, -3.0]);         // the hold
//! assert!(u[2] > -3.0 && u[2] < 3.0);          // step 1: random level (ascending)
//! assert_eq!(u[3], 3.0);                       // step 2: u_max
//! assert!(u[4] > -3.0 && u[4] < 3.0);          // step 3: random level (descending)
//! assert_eq!(u[5], -3.0);                      // step 4: u_min
//! # Ok::<(), hsid::Error>(())
//! ```

use rand_core::Rng;

use crate::error::Error;
use crate::scalar::Real;

/// Generator of the Table I excitation, an endless [`Iterator`] (use `take`). Reproducible:
/// the same seed of the same generator gives the same sequence on every target.
#[derive(Clone, Debug)]
pub struct Excitation<T, R> {
    u_min: T,
    u_max: T,
    hold_left: usize,
    step: u8,
    rng: R,
}

impl<T: Real, R: Rng> Excitation<T, R> {
    /// A generator over `[u_min, u_max]` that first holds `u_min` for `hold` samples.
    /// With `hold = 0` the sequence starts with the paper's `u(0) = u_min` and step 1.
    pub fn new(u_min: T, u_max: T, hold: usize, rng: R) -> Result<Self, Error> {
        if !(u_min.finite() && u_max.finite() && u_min < u_max) {
            return Err(Error::InvalidInterval {
                u_min: u_min.to_f64(),
                u_max: u_max.to_f64(),
            });
        }
        Ok(Self {
            u_min,
            u_max,
            hold_left: hold.max(1),
            step: 0,
            rng,
        })
    }

    /// A uniform level strictly inside `]u_min, u_max[`: the midpoint of one of 2^24 equal
    /// cells, so neither end can occur even after rounding to `f32`.
    fn level(&mut self) -> T {
        let k = self.rng.next_u32() >> 8; // 24 bits
        let frac = (k as f64 + 0.5) / 16_777_216.0;
        let (lo, hi) = (self.u_min.to_f64(), self.u_max.to_f64());
        let x = T::of(lo + (hi - lo) * frac);
        // Rounding to the scalar type can land on an end only for intervals narrower than a
        // few ulps; nudge inside rather than emit an end point.
        if x <= self.u_min || x >= self.u_max {
            (self.u_min + self.u_max) / T::of(2.0)
        } else {
            x
        }
    }
}

impl<T: Real, R: Rng> Iterator for Excitation<T, R> {
    type Item = T;

    fn next(&mut self) -> Option<T> {
        if self.hold_left > 0 {
            self.hold_left -= 1;
            return Some(self.u_min);
        }
        let u = match self.step {
            0 | 2 => self.level(),
            1 => self.u_max,
            _ => self.u_min,
        };
        self.step = (self.step + 1) & 3;
        Some(u)
    }
}
