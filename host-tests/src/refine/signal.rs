//! Signals of the refinement: rational filters in `q⁻¹` and the hat-basis regressors.
//!
//! The border functions are written in the hat basis with the border *values* as coefficients:
//! `P(u) = Σᵢ vᵢ φᵢ(u)` with `φᵢ` the linear B-spline peaking at knot `nᵢ` (`Σᵢ φᵢ = 1`). Both
//! paths share `v₀ = μ0 = P_a(u_min) = P_d(u_min)`, so the nonlinearity output is linear in
//! `β = (μ0, v₁ᵃ … v_{n_a}ᵃ, v₁ᵈ … v_{n_d}ᵈ)`:
//! `H[u(t)] = Σ_k β_k w_k(t)`, where `w_0(t) = φ₀(u(t))` on the current path, `w_i(t) =
//! φᵢᵃ(u(t)) δ(t)` for the ascending channels and `φᵢᵈ(u(t)) (1 − δ(t))` for the descending
//! ones. At most two `w_k(t)` are non-zero at any `t`.
//!
//! δ(t) follows the core's convention: `u(−1) = u_min` and the initial direction descending.

use hsid::Direction;

use super::RefineError;
use crate::numerics::direction::directions;
use crate::numerics::hat::hat_weights;

/// Filters `x` through `b(q⁻¹) / a(q⁻¹)` from zero initial state; `a[0]` must be 1.
///
/// `y(t) = Σ_k b_k x(t−k) − Σ_{k≥1} a_k y(t−k)`.
pub fn filter(b: &[f64], a: &[f64], x: &[f64]) -> Vec<f64> {
    let mut y = vec![0.0; x.len()];
    filter_into(b, a, x, &mut y);
    y
}

/// [`filter`] into a caller-provided buffer of the same length as `x`.
pub(crate) fn filter_into(b: &[f64], a: &[f64], x: &[f64], y: &mut [f64]) {
    let n = x.len().min(y.len());
    let warm = b.len().max(a.len()).min(n);
    for t in 0..warm {
        let mut acc = 0.0;
        for (k, bk) in b.iter().enumerate().take(t + 1) {
            acc += bk * x[t - k];
        }
        for (k, ak) in a.iter().enumerate().take(t + 1).skip(1) {
            acc -= ak * y[t - k];
        }
        y[t] = acc;
    }
    // Past the first samples every tap exists: no branch in the loop.
    for t in warm..n {
        let mut acc = 0.0;
        for (k, bk) in b.iter().enumerate() {
            acc += bk * x[t - k];
        }
        for (k, ak) in a.iter().enumerate().skip(1) {
            acc -= ak * y[t - k];
        }
        y[t] = acc;
    }
}

/// `x` delayed by `k` samples with zeros shifted in.
pub fn delay(x: &[f64], k: usize) -> Vec<f64> {
    let mut y = vec![0.0; x.len()];
    if k < x.len() {
        y[k..].copy_from_slice(&x[..x.len() - k]);
    }
    y
}

/// A causal filter `b(q)/a(q)` (`a₀ = 1`) from rest, one sample at a time: the values of
/// [`filter`] on the whole signal, with a state of the filter's length rather than the
/// signal's.
#[derive(Clone, Debug)]
pub(crate) struct Stepped {
    b: Vec<f64>,
    a: Vec<f64>,
    /// `x(t − k)` at `k`.
    x: Vec<f64>,
    /// `y(t − k)` at `k` (the slot `k = 0` is the newest output).
    y: Vec<f64>,
}

impl Stepped {
    /// The filter `b/a` at rest.
    pub(crate) fn new(b: &[f64], a: &[f64]) -> Self {
        Self {
            b: b.to_vec(),
            a: a.to_vec(),
            x: vec![0.0; b.len()],
            y: vec![0.0; a.len().max(1)],
        }
    }

    /// The output for the next input sample `v`.
    pub(crate) fn step(&mut self, v: f64) -> f64 {
        push_lag(&mut self.x, v);
        self.y.rotate_right(1);
        let mut acc = 0.0;
        for (b, x) in self.b.iter().zip(&self.x) {
            acc += b * x;
        }
        for (a, y) in self.a.iter().zip(&self.y).skip(1) {
            acc -= a * y;
        }
        if let Some(y0) = self.y.first_mut() {
            *y0 = acc;
        }
        acc
    }
}

/// Shifts a history `h[k] = x(t − k)` by one sample, `v` the newest.
pub(crate) fn push_lag(h: &mut [f64], v: f64) {
    h.rotate_right(1);
    if let Some(h0) = h.first_mut() {
        *h0 = v;
    }
}

/// Checks a knot vector: at least two finite, strictly increasing values.
pub(crate) fn check_knots(k: &[f64], which: &'static str) -> Result<(), RefineError> {
    if k.len() < 2 {
        return Err(RefineError::InvalidKnots(which));
    }
    if k.iter().any(|v| !v.is_finite()) || k.windows(2).any(|w| w[1] <= w[0]) {
        return Err(RefineError::InvalidKnots(which));
    }
    Ok(())
}

/// The hat-basis regressors `w(t)` of a record (see the [module docs](self)).
///
/// With a static (memoryless) nonlinearity both directions share one border: the descending
/// samples use the ascending channels and there are no descending ones.
#[derive(Clone, Debug, PartialEq)]
pub struct HatRegressors {
    n_asc: usize,
    n_desc: usize,
    shared: bool,
    /// Per sample: two channels (the second may have weight 0) and the second's weight `θ`
    /// (the first's is `1 − θ`).
    idx: Vec<[u16; 2]>,
    theta: Vec<f64>,
}

impl HatRegressors {
    /// Builds the regressors of `u` on the given knots (both paths from `u_min` to `u_max`).
    pub fn new(u: &[f64], knots_asc: &[f64], knots_desc: &[f64]) -> Result<Self, RefineError> {
        Self::build(u, knots_asc, knots_desc, false)
    }

    /// The regressors of a static nonlinearity: one border on `knots` for both directions.
    pub fn shared(u: &[f64], knots: &[f64]) -> Result<Self, RefineError> {
        Self::build(u, knots, knots, true)
    }

    /// [`new`](Self::new) or [`shared`](Self::shared).
    pub fn build(
        u: &[f64],
        knots_asc: &[f64],
        knots_desc: &[f64],
        shared: bool,
    ) -> Result<Self, RefineError> {
        check_knots(knots_asc, "ascending knots must be strictly increasing")?;
        check_knots(knots_desc, "descending knots must be strictly increasing")?;
        let (lo, hi) = (knots_asc[0], knots_asc[knots_asc.len() - 1]);
        if knots_desc[0] != lo || knots_desc[knots_desc.len() - 1] != hi {
            return Err(RefineError::InvalidKnots(
                "both paths must start at u_min and end at u_max",
            ));
        }
        if u.iter().any(|v| !v.is_finite()) {
            return Err(RefineError::NonFinite);
        }
        if u.iter().any(|&v| v < lo || v > hi) {
            return Err(RefineError::InvalidKnots(
                "an input lies outside [u_min, u_max]",
            ));
        }
        let n_asc = knots_asc.len() - 1;
        let n_desc = if shared { 0 } else { knots_desc.len() - 1 };
        // Channel numbers are kept in 16 bits (four bytes a sample instead of sixteen).
        if 1 + n_asc + n_desc > usize::from(u16::MAX) {
            return Err(RefineError::InvalidKnots(
                "more than 65,535 border channels: give fewer knots",
            ));
        }
        let mut idx = Vec::with_capacity(u.len());
        let mut theta = Vec::with_capacity(u.len());
        for (&ut, dir) in u.iter().zip(directions(u, lo)) {
            let (k, off) = if dir == Direction::Ascending || shared {
                (knots_asc, 0)
            } else {
                (knots_desc, n_asc)
            };
            let (s, th) = hat_weights(k, ut);
            // φ_s with weight 1 − θ, φ_{s+1} with weight θ; φ_0 is channel 0 on both paths.
            let ch = |i: usize| u16::try_from(if i == 0 { 0 } else { off + i }).unwrap_or(u16::MAX);
            idx.push([ch(s), ch(s + 1)]);
            theta.push(th);
        }
        Ok(Self {
            n_asc,
            n_desc,
            shared,
            idx,
            theta,
        })
    }

    /// The two weights of every sample.
    fn weights(&self) -> impl Iterator<Item = [f64; 2]> + '_ {
        self.theta.iter().map(|&th| [1.0 - th, th])
    }

    /// Samples.
    pub fn len(&self) -> usize {
        self.idx.len()
    }

    /// Whether there are no samples.
    pub fn is_empty(&self) -> bool {
        self.idx.is_empty()
    }

    /// Channels: `1 + n_a + n_d` (μ0 first; `1 + n` for a static nonlinearity).
    pub fn channels(&self) -> usize {
        1 + self.n_asc + self.n_desc
    }

    /// `H[u(t)] = Σ_k β_k w_k(t)` for every sample.
    pub fn output(&self, beta: &[f64]) -> Vec<f64> {
        self.idx
            .iter()
            .zip(self.weights())
            .map(|(i, w)| {
                beta.get(usize::from(i[0])).copied().unwrap_or(0.0) * w[0]
                    + beta.get(usize::from(i[1])).copied().unwrap_or(0.0) * w[1]
            })
            .collect()
    }

    /// Channel `k` as a dense signal.
    pub fn channel(&self, k: usize) -> Vec<f64> {
        self.idx
            .iter()
            .zip(self.weights())
            .map(|(i, w)| {
                let mut v = 0.0;
                if usize::from(i[0]) == k {
                    v += w[0];
                }
                if usize::from(i[1]) == k {
                    v += w[1];
                }
                v
            })
            .collect()
    }

    /// The channels' values at sample `t` into `out` (one per channel; zero where the sample
    /// has no weight, and everywhere past the record).
    pub(crate) fn sample_into(&self, t: usize, out: &mut [f64]) {
        out.iter_mut().for_each(|v| *v = 0.0);
        if let (Some(i), Some(&th)) = (self.idx.get(t), self.theta.get(t)) {
            for (i, w) in i.iter().zip([1.0 - th, th]) {
                if let Some(o) = out.get_mut(usize::from(*i)) {
                    *o += w;
                }
            }
        }
    }

    /// All channels as dense signals (channel-major).
    pub fn dense(&self) -> Vec<Vec<f64>> {
        let mut out = vec![vec![0.0; self.len()]; self.channels()];
        for (t, (i, w)) in self.idx.iter().zip(self.weights()).enumerate() {
            out[usize::from(i[0])][t] += w[0];
            out[usize::from(i[1])][t] += w[1];
        }
        out
    }

    /// `β` from border values at the knots: `(μ0, P_a(n₁) …, P_d(n₁) …)` (the descending
    /// values are left out for a static nonlinearity).
    pub fn beta_of(&self, mu0: f64, border_asc: &[f64], border_desc: &[f64]) -> Vec<f64> {
        let mut beta = vec![mu0];
        beta.extend(border_asc.iter().skip(1));
        if !self.shared {
            beta.extend(border_desc.iter().skip(1));
        }
        beta
    }

    /// Border values at the knots from `β`: `(P_a at the ascending knots, P_d at the
    /// descending knots)`, both starting with μ0.
    pub fn borders_from_beta(&self, beta: &[f64]) -> (Vec<f64>, Vec<f64>) {
        let mu0 = beta.first().copied().unwrap_or(f64::NAN);
        let mut asc = vec![mu0];
        asc.extend(beta.iter().skip(1).take(self.n_asc));
        if self.shared {
            return (asc.clone(), asc);
        }
        let mut desc = vec![mu0];
        desc.extend(beta.iter().skip(1 + self.n_asc).take(self.n_desc));
        (asc, desc)
    }
}
