//! The lagged sums and edge samples a record's Hankel Gram is built from, and its entries.

use hsid::Real;

use super::DisplacementError;

/// What the Gram of the stacked Hankel rows needs from a record: the lagged sums and the edge
/// samples, with `w(t) = [z_0(t) … z_{m−1}(t); ȳ(t)]` (`c = m + 1` channels, the output last),
/// `k = f + p` block rows and `j` columns (`N = j + k − 1` samples).
#[derive(Clone, Debug, PartialEq)]
pub struct LaggedSums<T> {
    /// Input-regressor channels per lag.
    pub m: usize,
    /// Future horizon (block rows of `Z_f`, rows of `Ȳ_f`).
    pub f: usize,
    /// Past horizon (block rows of `Z_p`).
    pub p: usize,
    /// Hankel columns.
    pub j: usize,
    /// `R_τ[i][i'] = Σ_{t=0}^{N−1−τ} w_i(t) w_{i'}(t+τ)` at `lags[(τ·c + i)·c + i']`,
    /// `τ = 0 … k−1`.
    pub lags: Vec<T>,
    /// The first `k − 1` samples, `w_i(t)` at `head[t·c + i]`.
    pub head: Vec<T>,
    /// The last `k − 1` samples, `w_i(j + t)` at `tail[t·c + i]`.
    pub tail: Vec<T>,
}

impl<T: Real> LaggedSums<T> {
    /// The lagged sums and edge samples of the record `w` (`w_i(t)` at `w[t·c + i]`, `N`
    /// samples, so `j = N − k + 1`), accumulated in `T`.
    pub fn from_samples(m: usize, f: usize, p: usize, w: &[T]) -> Result<Self, DisplacementError> {
        let (c, k) = (m + 1, f + p);
        if m == 0 || f == 0 || p == 0 || !w.len().is_multiple_of(c) || w.len() / c < 2 * k {
            return Err(DisplacementError::Shape);
        }
        let n = w.len() / c;
        let j = n + 1 - k;
        let mut lags = vec![T::ZERO; k * c * c];
        for tau in 0..k {
            for t in 0..n - tau {
                let (a, b) = (&w[t * c..(t + 1) * c], &w[(t + tau) * c..(t + tau + 1) * c]);
                for (i, &ai) in a.iter().enumerate() {
                    let row = &mut lags[(tau * c + i) * c..(tau * c + i + 1) * c];
                    for (v, &bi) in row.iter_mut().zip(b) {
                        *v += ai * bi;
                    }
                }
            }
        }
        Ok(Self {
            m,
            f,
            p,
            j,
            lags,
            head: w[..(k - 1) * c].to_vec(),
            tail: w[j * c..].to_vec(),
        })
    }

    /// Channels per sample, `m + 1`.
    pub fn c(&self) -> usize {
        self.m + 1
    }

    /// Block rows, `f + p`.
    pub fn k(&self) -> usize {
        self.f + self.p
    }

    /// The same sums rounded to another precision.
    pub fn cast<U: Real>(&self) -> LaggedSums<U> {
        let conv = |v: &[T]| v.iter().map(|x| U::of(x.to_f64())).collect();
        LaggedSums {
            m: self.m,
            f: self.f,
            p: self.p,
            j: self.j,
            lags: conv(&self.lags),
            head: conv(&self.head),
            tail: conv(&self.tail),
        }
    }

    /// Whether the lengths fit `m`, `f`, `p` (and `j ≥ k`).
    pub(super) fn consistent(&self) -> bool {
        let (c, k) = (self.c(), self.k());
        self.m > 0
            && self.f > 0
            && self.p > 0
            && self.j >= k
            && self.lags.len() == k * c * c
            && self.head.len() == (k - 1) * c
            && self.tail.len() == (k - 1) * c
    }

    /// `w_i(t)` for an edge sample (`t < k − 1` or `t ≥ j`); zero elsewhere (never asked).
    pub(super) fn sample(&self, t: usize, i: usize) -> T {
        let c = self.c();
        if t + 1 < self.k() {
            self.head[t * c + i]
        } else if t >= self.j {
            self.tail[(t - self.j) * c + i]
        } else {
            T::ZERO
        }
    }

    /// One entry of the Hankel Gram, `Σ_{s<j} w_i(a + s) w_{i'}(b + s)` (channels `i, i' < c`,
    /// lags `a, b < k`): `R_{|b−a|}` less the products outside the window, which involve edge
    /// samples only. `None` for an index out of range or inconsistent sums.
    pub fn gram(&self, i: usize, a: usize, i2: usize, b: usize) -> Option<T> {
        let (c, k) = (self.c(), self.k());
        (self.consistent() && i < c && i2 < c && a < k && b < k).then(|| self.entry(i, a, i2, b))
    }

    /// [`gram`](Self::gram) without the checks.
    pub(super) fn entry(&self, i: usize, a: usize, i2: usize, b: usize) -> T {
        if a > b {
            return self.entry(i2, b, i, a);
        }
        let (c, k, tau) = (self.c(), self.k(), b - a);
        let mut s = self.lags[(tau * c + i) * c + i2];
        for t in 0..a {
            s -= self.sample(t, i) * self.sample(t + tau, i2);
        }
        for t in a + self.j..self.j + k - 1 - tau {
            s -= self.sample(t, i) * self.sample(t + tau, i2);
        }
        s
    }
}
