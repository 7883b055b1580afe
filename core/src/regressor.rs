//! Knots and the regressor z(t) of the over-parameterised model (eq. 4).
//!
//! The borders `P_a` / `P_d` are continuous piecewise-linear functions on user knots
//! `n_0 = u_min < n_1 < … < n_{n_p} = u_max`, chosen separately for each path and possibly
//! with a different count per path (Remark 3). Two bases span the same functions:
//!
//! * [`Basis::Ramp`], the paper's `P_i(u)`: `0` below `n_{i-1}`, `u - n_{i-1}` on the segment,
//!   `n_i - n_{i-1}` above. The coefficients `μ_i` are the slopes of the border.
//! * [`Basis::Hat`], linear B-splines `φ_i(u)` peaking at `n_i`. The coefficients are the border
//!   values at the knots minus `μ0`. At most two are non-zero at any `u`, which makes the
//!   streaming accumulation cheap, and the basis is better conditioned.
//!
//! Both give the same projection, singular values, order, `A` and `C` (up to rounding): the
//! change of basis is a fixed invertible map per path applied to every block row of the input
//! Hankel matrices, which leaves their row spaces unchanged. The rank-1 split of eq. (14) is
//! done in the chosen coordinates, and a best rank-1 approximation is not invariant under a
//! non-orthogonal change of coordinates: with noise, `B`, `D` and the borders differ. On the
//! paper's Monte Carlo the split in hat coordinates is the better estimate (the ramp
//! coordinates are slopes, differences of border values, which amplify noise and bias the
//! split; see the README). [`Basis::Ramp`] reproduces the paper's estimator exactly.

use heapless::Vec;

use crate::direction::Direction;
use crate::error::{Error, KnotEnd};
use crate::scalar::Real;

/// The basis the border functions are expanded in. See the [module docs](self).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Basis {
    /// Linear B-splines (hat functions): sparse, well conditioned. The default.
    #[default]
    Hat,
    /// The paper's ramp functions `P_i`: the paper's estimator, step for step.
    Ramp,
}

/// `TooFewKnots` if a path has fewer than two knots.
fn too_few<T>(path: Direction, knots: &[T]) -> Result<(), Error> {
    if knots.len() < 2 {
        return Err(Error::TooFewKnots {
            path,
            count: knots.len(),
        });
    }
    Ok(())
}

/// The knots of both paths, with the input interval. `M` is the capacity in segments
/// (regressor channels): `m = n_a + n_d <= M`.
#[derive(Clone, Debug, PartialEq)]
pub struct Knots<T, const M: usize> {
    asc: Vec<T, M>,
    desc: Vec<T, M>,
    shared: bool,
}

impl<T: Real, const M: usize> Knots<T, M> {
    /// No knots: a placeholder for constant initialisation of a `static` identifier. Every
    /// identifier built from it is rejected until real knots are set.
    pub const EMPTY: Self = Self {
        asc: Vec::new(),
        desc: Vec::new(),
        shared: false,
    };

    /// Knots for each path, both end points included (`asc[0] = desc[0] = u_min`,
    /// last = `u_max`). The segment counts `asc.len() - 1` and `desc.len() - 1` may differ
    /// (Remark 3) and must add up to at most `M`; knots need not be uniform.
    pub fn new(asc: &[T], desc: &[T]) -> Result<Self, Error> {
        // A short path is named before the count: its segment count is meaningless.
        too_few(Direction::Ascending, asc)?;
        too_few(Direction::Descending, desc)?;
        let ascending = asc.len() - 1;
        let descending = desc.len() - 1;
        if ascending + descending > M {
            return Err(Error::SegmentCount {
                expected: M,
                ascending,
                descending,
            });
        }
        Self::new_unchecked_count(asc, desc)
    }

    /// One knot vector for both directions: a static (memoryless) piecewise-linear
    /// nonlinearity `P_a = P_d`, for data without hysteresis or not recorded with the Table I
    /// excitation. Both directions use the same `n` channels. The `n + 1` knots are stored in
    /// the capacity, so `n < M`.
    pub fn shared(knots: &[T]) -> Result<Self, Error> {
        let n = knots.len().saturating_sub(1);
        if n >= M {
            return Err(Error::SegmentCount {
                expected: M - 1,
                ascending: n,
                descending: 0,
            });
        }
        // Validate as two paths of n segments each, then keep one set of channels.
        let mut k = Self::new_unchecked_count(knots, knots)?;
        k.shared = true;
        Ok(k)
    }

    fn new_unchecked_count(asc: &[T], desc: &[T]) -> Result<Self, Error> {
        let mut a = Vec::new();
        let mut d = Vec::new();
        let full = Error::SegmentCount {
            expected: M,
            ascending: asc.len().saturating_sub(1),
            descending: 0,
        };
        a.extend_from_slice(asc).map_err(|_| full)?;
        d.extend_from_slice(desc).map_err(|_| full)?;
        let k = Self {
            asc: a,
            desc: d,
            shared: false,
        };
        k.validate()?;
        Ok(k)
    }

    /// Checks both knot vectors: at least two knots, finite, strictly increasing, same ends.
    fn validate(&self) -> Result<(), Error> {
        for (path, k) in [
            (Direction::Ascending, &self.asc[..]),
            (Direction::Descending, &self.desc[..]),
        ] {
            too_few(path, k)?;
            for (i, w) in k.windows(2).enumerate() {
                if let [a, b] = w
                    && (!a.finite() || !b.finite() || b <= a)
                {
                    return Err(Error::KnotsNotIncreasing { path, index: i + 1 });
                }
            }
        }
        for (end, a, d) in [
            (KnotEnd::First, self.asc.first(), self.desc.first()),
            (KnotEnd::Last, self.asc.last(), self.desc.last()),
        ] {
            if a != d {
                let value = |v: Option<&T>| v.map_or(f64::NAN, |v| v.to_f64());
                return Err(Error::KnotEndpoints {
                    end,
                    ascending: value(a),
                    descending: value(d),
                });
            }
        }
        Ok(())
    }

    /// `true` for a static nonlinearity ([`Knots::shared`]).
    pub fn is_shared(&self) -> bool {
        self.shared
    }

    /// Uniform knots on `[u_min, u_max]` with `n_asc` and `n_desc` segments (`n_asc + n_desc <= M`).
    pub fn uniform(u_min: T, u_max: T, n_asc: usize, n_desc: usize) -> Result<Self, Error> {
        if !(u_min.finite() && u_max.finite() && u_min < u_max) {
            return Err(Error::InvalidInterval {
                u_min: u_min.to_f64(),
                u_max: u_max.to_f64(),
            });
        }
        if n_asc + n_desc > M {
            return Err(Error::SegmentCount {
                expected: M,
                ascending: n_asc,
                descending: n_desc,
            });
        }
        let make = |n: usize| -> Vec<T, M> {
            let mut v = Vec::new();
            for i in 0..=n {
                let x = if i == n {
                    u_max
                } else {
                    u_min + (u_max - u_min) * T::of_usize(i) / T::of_usize(n.max(1))
                };
                if v.push(x).is_err() {
                    break;
                }
            }
            v
        };
        let (a, d) = (make(n_asc), make(n_desc));
        Self::new(&a, &d)
    }

    /// Knots of one path, end points included.
    pub fn path(&self, dir: Direction) -> &[T] {
        match dir {
            Direction::Ascending => &self.asc,
            Direction::Descending => &self.desc,
        }
    }

    /// Regressor channels in use, `m = n_a + n_d` (`n` for a shared, static nonlinearity).
    pub fn channels(&self) -> usize {
        if self.shared {
            self.segments(Direction::Ascending)
        } else {
            self.segments(Direction::Ascending) + self.segments(Direction::Descending)
        }
    }

    /// Number of segments on a path.
    pub fn segments(&self, dir: Direction) -> usize {
        self.path(dir).len().saturating_sub(1)
    }

    /// `u_min`, the first knot.
    pub fn u_min(&self) -> T {
        self.asc.first().copied().unwrap_or_default()
    }

    /// `u_max`, the last knot.
    pub fn u_max(&self) -> T {
        self.asc.last().copied().unwrap_or_default()
    }

    /// First regressor channel of a path: the ascending channels come first.
    pub fn offset(&self, dir: Direction) -> usize {
        match dir {
            Direction::Ascending => 0,
            Direction::Descending if self.shared => 0,
            Direction::Descending => self.segments(Direction::Ascending),
        }
    }

    /// Locates `u` on a path: the segment `s` (0-based, `n_s <= u <= n_{s+1}`) and the
    /// position `θ ∈ [0, 1]` inside it. `u` is clamped to the interval by the caller's checks.
    pub fn locate(&self, dir: Direction, u: T) -> Located<T> {
        let k = self.path(dir);
        let segs = k.len().saturating_sub(1);
        // Binary search for the last knot <= u among knots 0..segs-1.
        let (mut lo, mut hi) = (0usize, segs);
        while hi - lo > 1 {
            let mid = lo + (hi - lo) / 2;
            match k.get(mid) {
                Some(&x) if x <= u => lo = mid,
                _ => hi = mid,
            }
        }
        let (a, b) = match (k.get(lo), k.get(lo + 1)) {
            (Some(&a), Some(&b)) => (a, b),
            _ => (T::zero(), T::one()),
        };
        let mut theta = (u - a) / (b - a);
        if theta < T::zero() {
            theta = T::zero();
        } else if theta > T::one() {
            theta = T::one();
        }
        Located {
            dir,
            segment: lo as u16,
            theta,
        }
    }
}

/// A sample's position on the nonlinearity: the path, the knot segment and the position
/// inside it. This is all z(t) depends on; it is what the accumulator stores per sample.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Located<T> {
    /// The path (δ(t)).
    pub dir: Direction,
    /// Segment index `s`: `n_s <= u <= n_{s+1}`.
    pub segment: u16,
    /// Position in the segment, `(u - n_s) / (n_{s+1} - n_s)`.
    pub theta: T,
}

/// Evaluates z(t) for a located sample: calls `visit(channel, value)` for every channel that
/// can be non-zero (at most two for hats, at most `n_p` for ramps). Channels not visited are 0.
#[inline(always)]
pub fn for_each_nonzero<T: Real, const M: usize>(
    knots: &Knots<T, M>,
    basis: Basis,
    at: &Located<T>,
    mut visit: impl FnMut(usize, T),
) {
    let off = knots.offset(at.dir);
    let s = at.segment as usize;
    match basis {
        Basis::Hat => {
            // φ_s (peak at n_s) and φ_{s+1}; φ_0 is excluded (its coefficient is zero).
            if s >= 1 {
                visit(off + s - 1, T::one() - at.theta);
            }
            visit(off + s, at.theta);
        }
        Basis::Ramp => {
            let k = knots.path(at.dir);
            for i in 0..=s {
                let len = match (k.get(i), k.get(i + 1)) {
                    (Some(&a), Some(&b)) => b - a,
                    _ => T::zero(),
                };
                let v = if i < s { len } else { at.theta * len };
                visit(off + i, v);
            }
        }
    }
}

/// z(t) of a located sample in the hat basis, expanded once: the (at most two) channels
/// [`for_each_nonzero`] visits, in its order, with their values. An absent term (segment 0 has
/// one) has channel [`HatTerms::ABSENT`], past every capacity, and value 0.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct HatTerms<T> {
    /// Channel of each term.
    pub(crate) channel: [u16; 2],
    /// Value of each term.
    pub(crate) value: [T; 2],
}

impl<T: Real> HatTerms<T> {
    /// The channel of an absent term.
    pub(crate) const ABSENT: u16 = u16::MAX;

    /// No terms.
    pub(crate) const NONE: Self = Self {
        channel: [Self::ABSENT; 2],
        value: [T::ZERO; 2],
    };

    /// The terms of `at`: `φ_s` (peak at `n_s`, absent for `s = 0`) and `φ_{s+1}`.
    #[inline(always)]
    pub(crate) fn of<const M: usize>(knots: &Knots<T, M>, at: &Located<T>) -> Self {
        // Channels index arrays of M entries, so M < u16::MAX keeps every real channel apart
        // from ABSENT.
        const { assert!(M < u16::MAX as usize, "M (segments) must be below 65535") };
        let c = knots.offset(at.dir) + at.segment as usize;
        let channel = |c: usize| u16::try_from(c).unwrap_or(Self::ABSENT);
        let first = match c.checked_sub(1) {
            Some(c) if at.segment >= 1 => channel(c),
            _ => Self::ABSENT,
        };
        let first_value = if first == Self::ABSENT {
            T::ZERO
        } else {
            T::one() - at.theta
        };
        Self {
            channel: [first, channel(c)],
            value: [first_value, at.theta],
        }
    }
}

/// The dense regressor z(t) ∈ R^M of a located sample (for tests, examples and host code;
/// the accumulator uses [`for_each_nonzero`]).
pub fn dense<T: Real, const M: usize>(
    knots: &Knots<T, M>,
    basis: Basis,
    at: &Located<T>,
) -> [T; M] {
    let mut z = [T::zero(); M];
    for_each_nonzero(knots, basis, at, |i, v| {
        if let Some(slot) = z.get_mut(i) {
            *slot = v;
        }
    });
    z
}
