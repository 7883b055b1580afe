//! The direction signal δ(t) of the paper (Section II-B): which border the output follows.

use core::fmt;

use crate::scalar::Real;

/// Which path the nonlinearity is on: δ(t) = 1 (ascending) or δ(t) = 0 (descending).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Direction {
    /// δ(t) = 1: `u` went up, the output follows `P_a`.
    Ascending,
    /// δ(t) = 0: `u` went down, the output follows `P_d`. The initial direction.
    #[default]
    Descending,
}

impl Direction {
    /// The paper's δ(t): `Ascending` if `u > u_prev`, `Descending` if `u < u_prev`, otherwise
    /// the previous direction (first display of δ in Section II-B).
    #[inline]
    pub fn next<T: Real>(self, u_prev: T, u: T) -> Self {
        if u > u_prev {
            Direction::Ascending
        } else if u < u_prev {
            Direction::Descending
        } else {
            self
        }
    }

    /// δ as a number: 1 ascending, 0 descending.
    pub fn delta(self) -> u8 {
        match self {
            Direction::Ascending => 1,
            Direction::Descending => 0,
        }
    }
}

impl fmt::Display for Direction {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Direction::Ascending => "ascending",
            Direction::Descending => "descending",
        })
    }
}
