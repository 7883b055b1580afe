//! Simulator of the true Hammerstein systems of the paper, independent of any identification
//! parameterisation.
//!
//! The system is `y(t) = G(q) H[u(t)] + v(t)` with `v(t) = G_v(q) e(t)` (paper eq. 1 and
//! Section IV). This module provides
//!
//! * the hysteretic input elements as state machines ([`Switch`], [`Backlash`]) behind the
//!   [`Nonlinearity`] trait, with arbitrary border functions `H_a`, `H_d`,
//! * the true ascending / descending paths `P_a`, `P_d` travelled under the Table I excitation
//!   ([`TruePaths`]),
//! * a SISO discrete transfer function in `q^-1` ([`Lti`]) with poles, frequency response,
//!   static gain and impulse energy,
//! * the paper's plant, noise model and nonlinearities ([`paper_plant`], [`paper_noise_model`],
//!   [`paper_switch`], [`paper_backlash`]),
//! * the Table I excitation ([`table1_excitation`], [`with_hold`]) and the simulation of one
//!   experiment with output noise at a requested SNR ([`simulate`]).
//!
//! Nothing here knows about knots, ramp functions or the direction signal `δ(t)` of the paper:
//! the elements react to the input sequence only, as a physical element would.

use std::fmt;
use std::ops::Range;
use std::sync::Arc;

use hsid::Direction;
use nalgebra::DMatrix;
use rand::{Rng, RngExt};
use rand_distr::{Distribution, StandardNormal};

use crate::numerics::direction::DirectionTracker;
use crate::numerics::poly::eigenvalues;

/// A border function `H_a` or `H_d` of a switch or backlash element: any `Fn(f64) -> f64` that
/// can be shared between threads.
pub type Border = Arc<dyn Fn(f64) -> f64 + Send + Sync>;

/// Wraps a closure or function into a [`Border`].
pub fn border<F>(f: F) -> Border
where
    F: Fn(f64) -> f64 + Send + Sync + 'static,
{
    Arc::new(f)
}

/// Errors of the simulator.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SimError {
    /// The transfer function's denominator is empty, has a zero or non-finite leading
    /// coefficient `a[0]`, or a non-finite coefficient.
    #[error("invalid denominator: it must be non-empty and finite with a[0] != 0")]
    InvalidDenominator,
    /// The transfer function's numerator is empty or has a non-finite coefficient.
    #[error("invalid numerator: it must be non-empty and finite")]
    InvalidNumerator,
    /// The interval `[u_min, u_max]` is empty or not finite.
    #[error("invalid input interval [{u_min}, {u_max}]")]
    InvalidInterval {
        /// Lower end requested.
        u_min: f64,
        /// Upper end requested.
        u_max: f64,
    },
    /// The range of samples used for the signal variance is empty or outside the input.
    #[error(
        "variance range {}..{} is empty or outside the {len} input samples",
        .range.start,
        .range.end
    )]
    InvalidVarianceRange {
        /// Range requested.
        range: Range<usize>,
        /// Number of samples available.
        len: usize,
    },
    /// The requested SNR is not finite.
    #[error("invalid SNR {0} dB")]
    InvalidSnr(f64),
    /// The noise-free output has zero (or non-finite) variance over the requested range, so no
    /// noise level can be derived from an SNR.
    #[error("noise-free output variance {0} over the chosen range cannot define an SNR")]
    DegenerateSignal(f64),
    /// The noise model has zero or non-finite impulse energy.
    #[error("noise model impulse energy {0} is zero or not finite")]
    DegenerateNoiseModel(f64),
    /// The eigenvalue iteration for the poles did not converge.
    #[error("eigenvalue computation did not converge")]
    EigenFailed,
}

/// A causal single-input single-output static-or-hysteretic input element `H[·]`.
pub trait Nonlinearity {
    /// Returns the element to its initial state.
    fn reset(&mut self);
    /// Feeds the next input sample `u(t)` and returns `H[u(t)]`.
    fn step(&mut self, u: f64) -> f64;
}

/// The true ascending and descending paths `P_a`, `P_d` travelled by an element under the
/// Table I excitation between `u_min` and `u_max` (every ascending run starts at `u_min` and
/// ends at `u_max`, every descending run starts at `u_max` and ends at `u_min`).
#[derive(Clone)]
pub struct TruePaths {
    asc: Border,
    desc: Border,
}

impl TruePaths {
    /// Builds the paths from two functions.
    pub fn new(asc: Border, desc: Border) -> Self {
        Self { asc, desc }
    }

    /// The ascending path `P_a(u)`.
    pub fn asc(&self, u: f64) -> f64 {
        (self.asc)(u)
    }

    /// The descending path `P_d(u)`.
    pub fn desc(&self, u: f64) -> f64 {
        (self.desc)(u)
    }
}

impl fmt::Debug for TruePaths {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("TruePaths").finish_non_exhaustive()
    }
}

/// A switch element (paper Fig. 3): the output is `H_a(u(t))` while the input rises
/// (`u(t) > u(t-1)`), `H_d(u(t))` while it falls (`u(t) < u(t-1)`), and stays on the branch of
/// the previous sample when the input is unchanged. Initially the branch is descending and there
/// is no previous input, so the first sample is evaluated on the descending branch.
#[derive(Clone)]
pub struct Switch {
    h_a: Border,
    h_d: Border,
    /// δ(t) and the previous input; `None` before the first sample.
    direction: Option<DirectionTracker>,
}

impl Switch {
    /// Creates a switch with ascending border `h_a` and descending border `h_d`.
    pub fn new(h_a: Border, h_d: Border) -> Self {
        Self {
            h_a,
            h_d,
            direction: None,
        }
    }

    /// Creates a switch from two closures.
    pub fn from_fns<A, D>(h_a: A, h_d: D) -> Self
    where
        A: Fn(f64) -> f64 + Send + Sync + 'static,
        D: Fn(f64) -> f64 + Send + Sync + 'static,
    {
        Self::new(border(h_a), border(h_d))
    }

    /// The ascending border `H_a(u)`.
    pub fn h_a(&self, u: f64) -> f64 {
        (self.h_a)(u)
    }

    /// The descending border `H_d(u)`.
    pub fn h_d(&self, u: f64) -> f64 {
        (self.h_d)(u)
    }

    /// Whether the element is currently on its ascending branch.
    pub fn is_ascending(&self) -> bool {
        self.direction
            .is_some_and(|d| d.direction() == Direction::Ascending)
    }

    /// The true paths over the Table I cycle: for a switch `P_a = H_a` and `P_d = H_d`
    /// (the interval does not matter).
    pub fn true_paths(&self, _u_min: f64, _u_max: f64) -> TruePaths {
        TruePaths::new(self.h_a.clone(), self.h_d.clone())
    }
}

impl fmt::Debug for Switch {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Switch")
            .field("prev_u", &self.direction.map(|d| d.previous()))
            .field("ascending", &self.is_ascending())
            .finish_non_exhaustive()
    }
}

impl Nonlinearity for Switch {
    fn reset(&mut self) {
        self.direction = None;
    }

    fn step(&mut self, u: f64) -> f64 {
        // Before the first sample there is no previous input: the first sample keeps δ.
        let tracker = self
            .direction
            .get_or_insert_with(|| DirectionTracker::new(u));
        match tracker.step(u) {
            Direction::Ascending => self.h_a(u),
            Direction::Descending => self.h_d(u),
        }
    }
}

/// A backlash element (paper Fig. 2): the play operator with memory on general borders,
/// `w(t) = min(max(w(t-1), H_a(u(t))), H_d(u(t)))`, which requires `H_a <= H_d` everywhere.
/// The initial output `w(-1)` is configurable (default `0.0`); the first sample clamps it into
/// `[H_a(u(0)), H_d(u(0))]`.
#[derive(Clone)]
pub struct Backlash {
    h_a: Border,
    h_d: Border,
    w0: f64,
    w: f64,
}

impl Backlash {
    /// Creates a backlash with ascending (lower-right) border `h_a` and descending
    /// (upper-left) border `h_d`, initial output `0.0`.
    pub fn new(h_a: Border, h_d: Border) -> Self {
        Self {
            h_a,
            h_d,
            w0: 0.0,
            w: 0.0,
        }
    }

    /// Creates a backlash from two closures.
    pub fn from_fns<A, D>(h_a: A, h_d: D) -> Self
    where
        A: Fn(f64) -> f64 + Send + Sync + 'static,
        D: Fn(f64) -> f64 + Send + Sync + 'static,
    {
        Self::new(border(h_a), border(h_d))
    }

    /// Sets the initial output `w(-1)` (also used by [`Nonlinearity::reset`]) and resets.
    pub fn with_initial_output(mut self, w0: f64) -> Self {
        self.w0 = w0;
        self.w = w0;
        self
    }

    /// The ascending border `H_a(u)`.
    pub fn h_a(&self, u: f64) -> f64 {
        (self.h_a)(u)
    }

    /// The descending border `H_d(u)`.
    pub fn h_d(&self, u: f64) -> f64 {
        (self.h_d)(u)
    }

    /// The current output `w(t)` (the last value returned by `step`, or the initial output).
    pub fn output(&self) -> f64 {
        self.w
    }

    /// The true paths over the Table I cycle between `u_min` and `u_max`, including the flat
    /// parts: `P_a(u) = max(H_d(u_min), H_a(u))` and `P_d(u) = min(H_a(u_max), H_d(u))`.
    ///
    /// This is exact for non-decreasing borders with `H_a <= H_d`, the usual backlash setting.
    pub fn true_paths(&self, u_min: f64, u_max: f64) -> TruePaths {
        let lo = self.h_d(u_min);
        let hi = self.h_a(u_max);
        let h_a = self.h_a.clone();
        let h_d = self.h_d.clone();
        TruePaths::new(
            border(move |u| h_a(u).max(lo)),
            border(move |u| h_d(u).min(hi)),
        )
    }
}

impl fmt::Debug for Backlash {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Backlash")
            .field("w0", &self.w0)
            .field("w", &self.w)
            .finish_non_exhaustive()
    }
}

impl Nonlinearity for Backlash {
    fn reset(&mut self) {
        self.w = self.w0;
    }

    fn step(&mut self, u: f64) -> f64 {
        self.w = self.w.max(self.h_a(u)).min(self.h_d(u));
        self.w
    }
}

/// `H_0 = (atan(3) - atan(1)) / 2` of the paper's switch (Section IV-A).
pub fn paper_switch_h0() -> f64 {
    0.5 * (3.0_f64.atan() - 1.0_f64.atan())
}

/// The paper's switch (Section IV-A): `H_d(u) = atan(u+1) - H_0` and `H_a(u) = atan(u-1) + H_0`
/// on `]-2, 2]`, `-1` for `u <= -2` and `1` for `u > 2`.
pub fn paper_switch() -> Switch {
    let h0 = paper_switch_h0();
    let clip = move |u: f64, inner: f64| {
        if u <= -2.0 {
            -1.0
        } else if u <= 2.0 {
            inner
        } else {
            1.0
        }
    };
    Switch::from_fns(
        move |u| clip(u, (u - 1.0).atan() + h0),
        move |u| clip(u, (u + 1.0).atan() - h0),
    )
}

/// The paper's backlash (Section IV-B): `H_d(u) = atan(u+1)`, `H_a(u) = atan(u-1)`.
pub fn paper_backlash() -> Backlash {
    Backlash::from_fns(|u| (u - 1.0).atan(), |u| (u + 1.0).atan())
}

/// A SISO discrete-time transfer function in the backward shift `q^-1`,
/// `G(q) = (b_0 + b_1 q^-1 + ...) / (1 + a_1 q^-1 + ...)`, simulated in direct form from zero
/// initial conditions.
#[derive(Debug, Clone, PartialEq)]
pub struct Lti {
    b: Vec<f64>,
    a: Vec<f64>,
    /// Past inputs `x(t-1), x(t-2), ...` (length `b.len() - 1`).
    x_hist: Vec<f64>,
    /// Past outputs `y(t-1), y(t-2), ...` (length `a.len() - 1`).
    y_hist: Vec<f64>,
}

impl Lti {
    /// Creates `G(q) = B(q^-1) / A(q^-1)` from the numerator `b` and denominator `a`
    /// coefficients (ascending powers of `q^-1`). Both are normalised by `a[0]`.
    pub fn new(b: Vec<f64>, a: Vec<f64>) -> Result<Self, SimError> {
        let a0 = *a.first().ok_or(SimError::InvalidDenominator)?;
        if a0 == 0.0 || a.iter().any(|c| !c.is_finite()) {
            return Err(SimError::InvalidDenominator);
        }
        if b.is_empty() || b.iter().any(|c| !c.is_finite()) {
            return Err(SimError::InvalidNumerator);
        }
        let b = b.into_iter().map(|c| c / a0).collect();
        let a = a.into_iter().map(|c| c / a0).collect();
        Ok(Self::from_normalized(b, a))
    }

    /// Builds from already validated coefficients with `a[0] = 1`.
    fn from_normalized(b: Vec<f64>, a: Vec<f64>) -> Self {
        let x_hist = vec![0.0; b.len().saturating_sub(1)];
        let y_hist = vec![0.0; a.len().saturating_sub(1)];
        Self {
            b,
            a,
            x_hist,
            y_hist,
        }
    }

    /// Numerator coefficients `b_0, b_1, ...` (normalised so that `a_0 = 1`).
    pub fn num(&self) -> &[f64] {
        &self.b
    }

    /// Denominator coefficients `1, a_1, ...`.
    pub fn den(&self) -> &[f64] {
        &self.a
    }

    /// Returns to zero initial conditions.
    pub fn reset(&mut self) {
        self.x_hist.iter_mut().for_each(|v| *v = 0.0);
        self.y_hist.iter_mut().for_each(|v| *v = 0.0);
    }

    /// Feeds `x(t)` and returns `y(t) = sum_k b_k x(t-k) - sum_{k>=1} a_k y(t-k)`.
    pub fn step(&mut self, x: f64) -> f64 {
        let mut y = self.b[0] * x;
        for (bk, xk) in self.b.iter().skip(1).zip(&self.x_hist) {
            y += bk * xk;
        }
        for (ak, yk) in self.a.iter().skip(1).zip(&self.y_hist) {
            y -= ak * yk;
        }
        if !self.x_hist.is_empty() {
            self.x_hist.rotate_right(1);
            self.x_hist[0] = x;
        }
        if !self.y_hist.is_empty() {
            self.y_hist.rotate_right(1);
            self.y_hist[0] = y;
        }
        y
    }

    /// Filters a whole sequence from zero initial conditions (the filter's own state is not
    /// touched).
    pub fn filter(&self, x: &[f64]) -> Vec<f64> {
        let mut g = Self::from_normalized(self.b.clone(), self.a.clone());
        x.iter().map(|&v| g.step(v)).collect()
    }

    /// The first `n` samples of the impulse response `g_0, g_1, ...` (the Markov parameters).
    pub fn impulse_response(&self, n: usize) -> Vec<f64> {
        let mut g = Self::from_normalized(self.b.clone(), self.a.clone());
        (0..n)
            .map(|t| g.step(if t == 0 { 1.0 } else { 0.0 }))
            .collect()
    }

    /// The poles: roots of `z^n + a_1 z^(n-1) + ... + a_n` (`n = a.len() - 1`), computed as the
    /// eigenvalues of the companion matrix, as `(re, im)` pairs sorted by decreasing real part
    /// then decreasing imaginary part.
    pub fn poles(&self) -> Result<Vec<(f64, f64)>, SimError> {
        let n = self.a.len().saturating_sub(1);
        if n == 0 {
            return Ok(Vec::new());
        }
        let mut m = DMatrix::<f64>::zeros(n, n);
        for k in 0..n {
            m[(0, k)] = -self.a[k + 1];
        }
        for k in 1..n {
            m[(k, k - 1)] = 1.0;
        }
        eigenvalues(m).ok_or(SimError::EigenFailed)
    }

    /// The frequency response `G(e^{jw})` as `(re, im)`.
    pub fn freq_response(&self, w: f64) -> (f64, f64) {
        let poly = |c: &[f64]| {
            c.iter().enumerate().fold((0.0, 0.0), |(re, im), (k, ck)| {
                let phi = -w * k as f64;
                (re + ck * phi.cos(), im + ck * phi.sin())
            })
        };
        let (nr, ni) = poly(&self.b);
        let (dr, di) = poly(&self.a);
        let den = dr * dr + di * di;
        ((nr * dr + ni * di) / den, (ni * dr - nr * di) / den)
    }

    /// The static gain `G(1) = sum(b) / sum(a)` (infinite or NaN if `A(1) = 0`).
    pub fn static_gain(&self) -> f64 {
        self.b.iter().sum::<f64>() / self.a.iter().sum::<f64>()
    }

    /// The energy of the impulse response `sum_k g_k^2`, truncated once the last
    /// `max(a.len(), b.len())` squared samples are each below `1e-14` times the running sum,
    /// and after at most 10^7 samples (so an unstable or very slow filter returns a large or
    /// infinite value rather than looping forever).
    pub fn impulse_energy(&self) -> f64 {
        const MAX_ITER: usize = 10_000_000;
        let window = self.a.len().max(self.b.len());
        let mut g = Self::from_normalized(self.b.clone(), self.a.clone());
        let mut sum = 0.0;
        let mut small_run = 0usize;
        for t in 0..MAX_ITER {
            let h = g.step(if t == 0 { 1.0 } else { 0.0 });
            let h2 = h * h;
            sum += h2;
            if !sum.is_finite() {
                return sum;
            }
            if h2 <= 1e-14 * sum {
                small_run += 1;
            } else {
                small_run = 0;
            }
            if t + 1 >= window && small_run >= window {
                break;
            }
        }
        sum
    }
}

/// The paper's plant `G(q) = q^-1 (0.1994 - 0.1804 q^-1) / (1 - 1.8858 q^-1 + 0.9048 q^-2)`.
pub fn paper_plant() -> Lti {
    Lti::from_normalized(vec![0.0, 0.1994, -0.1804], vec![1.0, -1.8858, 0.9048])
}

/// The paper's noise model `G_v(q) = (1 + 0.5 q^-1) / (1 - 0.85 q^-1)`.
pub fn paper_noise_model() -> Lti {
    Lti::from_normalized(vec![1.0, 0.5], vec![1.0, -0.85])
}

/// The paper's working interval `[u_min, u_max] = [-3, 3]`.
pub const PAPER_U_MIN: f64 = -3.0;
/// Upper end of the paper's working interval.
pub const PAPER_U_MAX: f64 = 3.0;

/// The Table I excitation of `len` samples: `u(0) = u_min`, then the cycle
/// "uniform random in `]u_min, u_max[`, `u_max`, uniform random, `u_min`" repeated (the last
/// cycle is cut at `len`).
pub fn table1_excitation<R: Rng + ?Sized>(
    len: usize,
    u_min: f64,
    u_max: f64,
    rng: &mut R,
) -> Result<Vec<f64>, SimError> {
    if !(u_min.is_finite() && u_max.is_finite() && u_min < u_max) {
        return Err(SimError::InvalidInterval { u_min, u_max });
    }
    let mut open_uniform = || loop {
        let r = rng.random_range(u_min..u_max);
        if r > u_min {
            return r;
        }
    };
    let mut u = Vec::with_capacity(len);
    for t in 0..len {
        let v = if t == 0 {
            u_min
        } else {
            match (t - 1) % 4 {
                0 | 2 => open_uniform(),
                1 => u_max,
                _ => u_min,
            }
        };
        u.push(v);
    }
    Ok(u)
}

/// Prepends an initial hold of `hold` samples at `u_hold` (the paper recommends `u_min`, which
/// lets the mean of the settled output estimate `mu_0`).
pub fn with_hold(hold: usize, u_hold: f64, excitation: &[f64]) -> Vec<f64> {
    let mut u = vec![u_hold; hold];
    u.extend_from_slice(excitation);
    u
}

/// The signals of one simulated experiment.
#[derive(Debug, Clone, PartialEq)]
pub struct Simulated {
    /// Measured output `y(t) = y_clean(t) + v(t)`.
    pub y: Vec<f64>,
    /// Noise-free output `G(q) H[u(t)]`.
    pub y_clean: Vec<f64>,
    /// Output of the nonlinearity `H[u(t)]`.
    pub h: Vec<f64>,
    /// Additive output noise `v(t) = G_v(q) e(t)` (all zero when noise free).
    pub v: Vec<f64>,
    /// Standard deviation of the white noise `e(t)` (0 when noise free).
    pub e_std: f64,
}

/// Population variance of a slice (0 for an empty slice).
pub fn variance(x: &[f64]) -> f64 {
    if x.is_empty() {
        return 0.0;
    }
    let n = x.len() as f64;
    let mean = x.iter().sum::<f64>() / n;
    x.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / n
}

/// Simulates `y = G(q) H[u] + v` with `v = G_v(q) e`, `e` white Gaussian.
///
/// The nonlinearity is reset first; `plant` and `noise_model` are simulated from zero initial
/// conditions (they are cloned, not modified). With `snr_db = Some(s)` the variance of `e` is
/// `var(y_clean[var_range]) / (10^(s/10) * impulse_energy(G_v))`, so that the stationary SNR
/// `var(y_clean) / var(v)` over `var_range` (typically the excitation part, excluding the
/// initial hold) is `s` dB; `None` gives a noise-free output and `var_range` is ignored.
pub fn simulate<R: Rng + ?Sized>(
    u: &[f64],
    nonlinearity: &mut dyn Nonlinearity,
    plant: &Lti,
    noise_model: &Lti,
    snr_db: Option<f64>,
    var_range: Range<usize>,
    rng: &mut R,
) -> Result<Simulated, SimError> {
    nonlinearity.reset();
    let h: Vec<f64> = u.iter().map(|&ut| nonlinearity.step(ut)).collect();
    let y_clean = plant.filter(&h);
    let Some(snr) = snr_db else {
        return Ok(Simulated {
            y: y_clean.clone(),
            y_clean,
            h,
            v: vec![0.0; u.len()],
            e_std: 0.0,
        });
    };
    if !snr.is_finite() {
        return Err(SimError::InvalidSnr(snr));
    }
    if var_range.start >= var_range.end || var_range.end > u.len() {
        return Err(SimError::InvalidVarianceRange {
            range: var_range,
            len: u.len(),
        });
    }
    let var_y = variance(&y_clean[var_range]);
    if !(var_y.is_finite() && var_y > 0.0) {
        return Err(SimError::DegenerateSignal(var_y));
    }
    let energy = noise_model.impulse_energy();
    if !(energy.is_finite() && energy > 0.0) {
        return Err(SimError::DegenerateNoiseModel(energy));
    }
    let e_std = (var_y / (10f64.powf(snr / 10.0) * energy)).sqrt();
    let e: Vec<f64> = (0..u.len())
        .map(|_| {
            let n: f64 = StandardNormal.sample(rng);
            e_std * n
        })
        .collect();
    let v = noise_model.filter(&e);
    let y = y_clean.iter().zip(&v).map(|(a, b)| a + b).collect();
    Ok(Simulated {
        y,
        y_clean,
        h,
        v,
        e_std,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lti_step_matches_difference_equation() {
        let mut g = paper_plant();
        let y: Vec<f64> = (0..4).map(|_| g.step(1.0)).collect();
        assert_eq!(y[0], 0.0);
        assert!((y[1] - 0.1994).abs() < 1e-15);
        let y2 = 0.1994 - 0.1804 + 1.8858 * y[1];
        assert!((y[2] - y2).abs() < 1e-15);
    }
}
