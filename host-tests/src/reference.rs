//! Reference implementation of the identification method, written straight from the paper's
//! equations with dense `nalgebra` matrices and explicit block Hankel matrices.
//!
//! Clarity is preferred over speed: this is the independent truth that the streaming `no_std`
//! core is tested against, so it does not depend on the core crate at all.
//!
//! Conventions (shared with the core so that both agree to about `1e-9`):
//!
//! * Knot vectors include both end points (`knots[0] = u_min`, `knots.last() = u_max`, strictly
//!   increasing); `n_a = knots_asc.len() - 1`, `n_d = knots_desc.len() - 1`, `m = n_a + n_d`.
//! * The direction signal `δ(t)` is the paper's, started with `u(-1) = u_min` and `δ(-1) = 0`
//!   (descending). The samples given to [`identify`] are the excitation only (no hold).
//! * `z(t)` holds the `n_a` ascending ramps `P_i^a(u(t)) δ(t)` followed by the `n_d` descending
//!   ramps `P_i^d(u(t)) (1 - δ(t))` (paper eq. 4).
//! * `ȳ(t) = y(t) - mu0`; `N = u.len()`, `k = f + p`, `j = N - k + 1`. Block row `a` of a block
//!   Hankel matrix holds samples `a, a+1, ..., a+j-1`; `Z_p` is block rows `0..p`, `Z_f` block
//!   rows `p..k`, `Ȳ_f` rows `p..k` of `ȳ`, and `Φ = [Z_p; Z_f]`.
//! * `O_f = Ȳ_f Φᵀ (Φ Φᵀ)^{-1} Φ Π⊥_{Z_f}` (eq. 11), with `X Π⊥ = X - (X Z_fᵀ)(Z_f Z_fᵀ)^{-1} Z_f`
//!   so that the `j × j` projector is never formed.
//! * `Γ_f = U_1 diag(sqrt(s))`, `C = Γ_f(0, :)`, `A` the least-squares solution of
//!   `Γ_f(0..f-1, :) A = Γ_f(1..f, :)`.
//! * Bold `B`, `D` by the MOESP procedure: `U_2ᵀ Ξ_f(B, D) = U_2ᵀ Ȳ_f Z_fᵀ (Z_f Z_fᵀ)^{-1}`.
//! * Rank-1 split (eq. 14) of `X = [bold D; bold B] ≈ s u vᵀ`: `[D; B] = γ s u`, `μ = vᵀ / γ`,
//!   `γ` such that `G(1) = C (I - A)^{-1} B + D = 1`.

use nalgebra::{DMatrix, DVector, RowDVector};

use crate::numerics::poly::eigenvalues;

/// Errors of the reference identification.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RefError {
    /// A knot vector has fewer than two values, is not strictly increasing, or does not start
    /// at `u_min` and end at `u_max`.
    #[error("invalid knots: {0}")]
    InvalidKnots(&'static str),
    /// `order`, `f` or `p` are inconsistent (`order >= 1`, `f > order`, `p >= 1` are required).
    #[error(
        "invalid dimensions f = {f}, p = {p}, order = {order} (need order >= 1, f > order, p >= 1)"
    )]
    InvalidDimensions {
        /// Future horizon.
        f: usize,
        /// Past horizon.
        p: usize,
        /// Model order.
        order: usize,
    },
    /// `u` and `y` have different lengths.
    #[error("u has {u} samples but y has {y}")]
    LengthMismatch {
        /// Length of `u`.
        u: usize,
        /// Length of `y`.
        y: usize,
    },
    /// Too few samples: `j = N - f - p + 1` must be at least `(f + p) m`.
    #[error("too few samples: {got} given, at least {needed} needed")]
    TooFewSamples {
        /// Samples needed.
        needed: usize,
        /// Samples given.
        got: usize,
    },
    /// An input, output or `mu0` value is not finite.
    #[error("non-finite input, output or mu0")]
    NonFinite,
    /// A Gram matrix that must be inverted is singular or numerically singular.
    #[error("singular Gram matrix {0}")]
    SingularGram(&'static str),
    /// `I - A` is singular (a pole at 1), so the static gain cannot be normalised.
    #[error("I - A is singular (pole at 1)")]
    PoleAtOne,
    /// The static gain of the rank-1 direction is zero: `γ` cannot be chosen.
    #[error("zero static gain: gamma cannot be chosen")]
    ZeroStaticGain,
    /// A singular value decomposition did not converge.
    #[error("SVD of {0} did not converge")]
    SvdFailed(&'static str),
    /// The eigenvalues of `A` could not be computed.
    #[error("eigenvalues of A did not converge")]
    EigenFailed,
}

/// Settings of the reference identification.
#[derive(Debug, Clone, PartialEq)]
pub struct RefConfig {
    /// Lower end of the working interval.
    pub u_min: f64,
    /// Upper end of the working interval.
    pub u_max: f64,
    /// Knots of the ascending path, including both ends `u_min` and `u_max`.
    pub knots_asc: Vec<f64>,
    /// Knots of the descending path, including both ends `u_min` and `u_max`.
    pub knots_desc: Vec<f64>,
    /// Future horizon `f` (block rows of `Z_f`, `Ȳ_f`).
    pub f: usize,
    /// Past horizon `p` (block rows of `Z_p`).
    pub p: usize,
    /// Model order `n`.
    pub order: usize,
}

/// `n + 1` uniformly spaced knots from `lo` to `hi`, both included (the last one exactly `hi`).
pub fn uniform_knots(lo: f64, hi: f64, segments: usize) -> Vec<f64> {
    let segments = segments.max(1);
    (0..=segments)
        .map(|i| {
            if i == segments {
                hi
            } else {
                lo + (hi - lo) * i as f64 / segments as f64
            }
        })
        .collect()
}

impl RefConfig {
    /// Uniform knots with `seg_asc` / `seg_desc` segments on `[u_min, u_max]`.
    pub fn uniform(
        u_min: f64,
        u_max: f64,
        seg_asc: usize,
        seg_desc: usize,
        f: usize,
        p: usize,
        order: usize,
    ) -> Self {
        Self {
            u_min,
            u_max,
            knots_asc: uniform_knots(u_min, u_max, seg_asc),
            knots_desc: uniform_knots(u_min, u_max, seg_desc),
            f,
            p,
            order,
        }
    }

    /// The paper's settings: `[-3, 3]`, 7 uniform segments per path, `f = p = 10`, order 2.
    pub fn paper() -> Self {
        Self::uniform(-3.0, 3.0, 7, 7, 10, 10, 2)
    }

    /// Number of ascending segments `n_a`.
    pub(crate) fn n_asc(&self) -> usize {
        self.knots_asc.len().saturating_sub(1)
    }

    /// Number of descending segments `n_d`.
    pub(crate) fn n_desc(&self) -> usize {
        self.knots_desc.len().saturating_sub(1)
    }

    /// Number of inputs `m = n_a + n_d` of the over-parameterised model.
    pub fn m(&self) -> usize {
        self.n_asc() + self.n_desc()
    }

    /// Checks the knots and dimensions.
    pub fn validate(&self) -> Result<(), RefError> {
        if !(self.u_min.is_finite() && self.u_max.is_finite() && self.u_min < self.u_max) {
            return Err(RefError::InvalidKnots("u_min < u_max (finite) is required"));
        }
        for knots in [&self.knots_asc, &self.knots_desc] {
            if knots.len() < 2 {
                return Err(RefError::InvalidKnots("at least two knots per path"));
            }
            if knots.first() != Some(&self.u_min) || knots.last() != Some(&self.u_max) {
                return Err(RefError::InvalidKnots(
                    "knots must start at u_min and end at u_max",
                ));
            }
            if knots.iter().any(|k| !k.is_finite()) || knots.windows(2).any(|w| w[0] >= w[1]) {
                return Err(RefError::InvalidKnots("knots must be strictly increasing"));
            }
        }
        if self.order == 0 || self.f <= self.order || self.p == 0 {
            return Err(RefError::InvalidDimensions {
                f: self.f,
                p: self.p,
                order: self.order,
            });
        }
        Ok(())
    }

    /// Minimum number of excitation samples: `j >= (f + p) m` Hankel columns.
    pub fn min_samples(&self) -> usize {
        let k = self.f + self.p;
        k * self.m() + k - 1
    }
}

/// The ramp functions `P_1(u), ..., P_n(u)` of the paper (Fig. 5) on the given knots:
/// `P_i(u) = 0` if `u <= n_{i-1}`, `u - n_{i-1}` on `[n_{i-1}, n_i]`, `n_i - n_{i-1}` above.
pub fn ramps(u: f64, knots: &[f64]) -> Vec<f64> {
    knots
        .windows(2)
        .map(|w| (u.min(w[1]) - w[0]).max(0.0))
        .collect()
}

/// The direction signal `δ(t)` (true = ascending) with `u(-1) = u_min` and `δ(-1) = 0`.
pub fn direction(u: &[f64], u_min: f64) -> Vec<bool> {
    let mut prev = u_min;
    let mut asc = false;
    u.iter()
        .map(|&ut| {
            if ut > prev {
                asc = true;
            } else if ut < prev {
                asc = false;
            }
            prev = ut;
            asc
        })
        .collect()
}

/// The regressors `z(t)` of paper eq. (4) as the columns of an `m × N` matrix: the `n_a`
/// ascending ramps times `δ(t)` then the `n_d` descending ramps times `1 - δ(t)`.
pub fn regressors(u: &[f64], cfg: &RefConfig) -> DMatrix<f64> {
    let (n_a, m) = (cfg.n_asc(), cfg.m());
    let delta = direction(u, cfg.u_min);
    let mut z = DMatrix::zeros(m, u.len());
    for (t, (&ut, &asc)) in u.iter().zip(&delta).enumerate() {
        if asc {
            for (i, r) in ramps(ut, &cfg.knots_asc).into_iter().enumerate() {
                z[(i, t)] = r;
            }
        } else {
            for (i, r) in ramps(ut, &cfg.knots_desc).into_iter().enumerate() {
                z[(n_a + i, t)] = r;
            }
        }
    }
    z
}

/// Block Hankel matrix of the `r × N` signal `data`: `blocks` block rows of `r` rows and `j`
/// columns, block row `b` holding samples `first + b, first + b + 1, ..., first + b + j - 1`.
/// The caller guarantees `first + blocks + j - 1 <= N`.
pub fn block_hankel(data: &DMatrix<f64>, first: usize, blocks: usize, j: usize) -> DMatrix<f64> {
    let r = data.nrows();
    let mut h = DMatrix::zeros(r * blocks, j);
    for b in 0..blocks {
        h.view_mut((b * r, 0), (r, j))
            .copy_from(&data.view((0, first + b), (r, j)));
    }
    h
}

/// `mu_0` from the output of the initial hold at `u_min`: the mean of `y_hold[settle..]`
/// (NaN if nothing is left after `settle`).
pub fn mu0_from_hold(y_hold: &[f64], settle: usize) -> f64 {
    let tail = &y_hold[settle.min(y_hold.len())..];
    tail.iter().sum::<f64>() / tail.len() as f64
}

/// The identified model.
#[derive(Debug, Clone, PartialEq)]
pub struct RefModel {
    /// Singular values of `O_f` (eq. 11) divided by `sqrt(j)`, all `f` of them, descending.
    pub singular_values: Vec<f64>,
    /// State matrix `A` (`n × n`).
    pub a: DMatrix<f64>,
    /// Input matrix `B` (`n`), after the rank-1 split and `γ`.
    pub b: DVector<f64>,
    /// Output matrix `C` (`1 × n`).
    pub c: RowDVector<f64>,
    /// Feed-through `D`, after the rank-1 split and `γ`.
    pub d: f64,
    /// `mu_0 = P_a(u_min) = P_d(u_min)` as given to [`identify`].
    pub mu0: f64,
    /// Slopes `μ_1^a, ..., μ_{n_a}^a` of the ascending ramps, after `γ`.
    pub mu_asc: Vec<f64>,
    /// Slopes `μ_1^d, ..., μ_{n_d}^d` of the descending ramps, after `γ`.
    pub mu_desc: Vec<f64>,
    /// `P_a` at the ascending knots: `mu0`, then `mu0 + Σ_{l<=i} μ_l^a (n_l - n_{l-1})`.
    pub border_asc: Vec<f64>,
    /// `P_d` at the descending knots, likewise.
    pub border_desc: Vec<f64>,
    /// Over-parameterised bold `B` (`n × m`) in the ramp basis, before the split.
    pub b_over: DMatrix<f64>,
    /// Over-parameterised bold `D` (`1 × m`) in the ramp basis, before the split.
    pub d_over: DMatrix<f64>,
    /// Eigenvalues of `A` as `(re, im)`, by decreasing real then imaginary part.
    pub poles: Vec<(f64, f64)>,
    /// Ascending knots used.
    pub knots_asc: Vec<f64>,
    /// Descending knots used.
    pub knots_desc: Vec<f64>,
    /// Number of Hankel columns `j`.
    pub j: usize,
}

impl RefModel {
    /// Model order `n`.
    pub fn order(&self) -> usize {
        self.a.nrows()
    }

    /// Markov parameter of the linear part: `h_0 = D`, `h_k = C A^{k-1} B`.
    pub fn markov(&self, k: usize) -> f64 {
        if k == 0 {
            return self.d;
        }
        (&self.c * self.a.pow((k - 1) as u32) * &self.b)[(0, 0)]
    }

    /// Markov parameter of the over-parameterised model (`1 × m`): bold `D` for `k = 0`,
    /// `C A^{k-1}` bold `B` otherwise.
    pub fn markov_over(&self, k: usize) -> Vec<f64> {
        if k == 0 {
            return self.d_over.iter().copied().collect();
        }
        (&self.c * self.a.pow((k - 1) as u32) * &self.b_over)
            .iter()
            .copied()
            .collect()
    }

    /// The identified ascending path at `u` (piecewise linear between the knots, constant
    /// outside `[u_min, u_max]`): `mu0 + Σ μ_i^a P_i^a(u)`.
    pub fn border_asc_at(&self, u: f64) -> f64 {
        self.mu0
            + ramps(u, &self.knots_asc)
                .iter()
                .zip(&self.mu_asc)
                .map(|(r, m)| r * m)
                .sum::<f64>()
    }

    /// The identified descending path at `u`: `mu0 + Σ μ_i^d P_i^d(u)`.
    pub fn border_desc_at(&self, u: f64) -> f64 {
        self.mu0
            + ramps(u, &self.knots_desc)
                .iter()
                .zip(&self.mu_desc)
                .map(|(r, m)| r * m)
                .sum::<f64>()
    }

    /// Static gain `G(1) = C (I - A)^{-1} B + D` of the identified linear part (1 by
    /// construction, NaN if `I - A` is singular).
    pub fn static_gain(&self) -> f64 {
        let n = self.order();
        let i_a = DMatrix::identity(n, n) - &self.a;
        match i_a.lu().solve(&self.b) {
            Some(x) => (&self.c * x)[(0, 0)] + self.d,
            None => f64::NAN,
        }
    }

    /// Frequency response of the identified linear part at `z = e^{jw}`, as `(re, im)`:
    /// `C (zI - A)^{-1} B + D` (NaN if `zI - A` is singular).
    pub fn freq_response(&self, w: f64) -> (f64, f64) {
        let n = self.order();
        // Solve (zI - A) x = B in real arithmetic: [[cI - A, -sI], [sI, cI - A]] [xr; xi] = [B; 0].
        let (c, s) = (w.cos(), w.sin());
        let mut m = DMatrix::zeros(2 * n, 2 * n);
        let mut rhs = DVector::zeros(2 * n);
        for r in 0..n {
            for col in 0..n {
                let v = if r == col { c } else { 0.0 } - self.a[(r, col)];
                m[(r, col)] = v;
                m[(n + r, n + col)] = v;
            }
            m[(r, n + r)] = -s;
            m[(n + r, r)] = s;
            rhs[r] = self.b[r];
        }
        match m.lu().solve(&rhs) {
            Some(x) => {
                let re = (0..n).map(|i| self.c[i] * x[i]).sum::<f64>() + self.d;
                let im = (0..n).map(|i| self.c[i] * x[n + i]).sum::<f64>();
                (re, im)
            }
            None => (f64::NAN, f64::NAN),
        }
    }

    /// The model's nonlinearity output `mu0 + μ z(t)` along an input sequence (direction
    /// started with `u(-1) = u_min`, `δ(-1) = 0`, as in [`identify`]).
    pub fn nonlinearity_output(&self, u: &[f64]) -> Vec<f64> {
        let u_min = self.knots_asc.first().copied().unwrap_or(0.0);
        direction(u, u_min)
            .iter()
            .zip(u)
            .map(|(&asc, &ut)| {
                if asc {
                    self.border_asc_at(ut)
                } else {
                    self.border_desc_at(ut)
                }
            })
            .collect()
    }

    /// Simulated model output `ŷ(t) = mu0 + G(q) μ z(t)` from zero state (i.e. from the rest
    /// point of the hold at `u_min`).
    pub fn simulate(&self, u: &[f64]) -> Vec<f64> {
        let h = self.nonlinearity_output(u);
        let mut x = DVector::zeros(self.order());
        h.iter()
            .map(|&ht| {
                let hb = ht - self.mu0;
                let y = (&self.c * &x)[(0, 0)] + self.d * hb + self.mu0;
                x = &self.a * &x + &self.b * hb;
                y
            })
            .collect()
    }
}

/// Cholesky factorisation of a symmetric positive definite Gram matrix, rejecting numerically
/// singular ones (squared ratio of smallest to largest pivot below `1e-13`).
pub(crate) fn spd_factor(
    g: DMatrix<f64>,
    which: &'static str,
) -> Result<nalgebra::Cholesky<f64, nalgebra::Dyn>, RefError> {
    let chol = g.cholesky().ok_or(RefError::SingularGram(which))?;
    let l = chol.l_dirty();
    let diag = l.diagonal();
    let (lo, hi) = diag.iter().fold((f64::INFINITY, 0.0_f64), |(lo, hi), &v| {
        (lo.min(v), hi.max(v))
    });
    if !(lo > 0.0 && (lo / hi).powi(2) > 1e-13) {
        return Err(RefError::SingularGram(which));
    }
    Ok(chol)
}

/// Least-squares solution of `M X = R` through the SVD of `M`.
pub(crate) fn least_squares(
    m: DMatrix<f64>,
    r: &DMatrix<f64>,
    which: &'static str,
) -> Result<DMatrix<f64>, RefError> {
    let svd = nalgebra::SVD::try_new(m, true, true, f64::EPSILON, 10_000)
        .ok_or(RefError::SvdFailed(which))?;
    let tol = svd.singular_values.max() * 1e-14;
    svd.solve(r, tol).map_err(|_| RefError::SvdFailed(which))
}

/// Identifies the Hammerstein model from the excitation `u`, the output `y` (same length, no
/// hold) and `mu0` (see [`mu0_from_hold`]), following the paper's Section III (PI-MOESP).
pub fn identify(u: &[f64], y: &[f64], mu0: f64, cfg: &RefConfig) -> Result<RefModel, RefError> {
    identify_weighted(u, y, mu0, cfg, RefMethod::PiMoesp)
}

/// The subspace weightings of Remark 4, written with explicit matrices.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RefMethod {
    /// Eq. (11): `O_f = Ȳ_f Φᵀ(ΦΦᵀ)⁻¹Φ Π⊥_{Z_f}`, `Φ = [Z_p; Z_f]`; `Γ_f = U₁S₁^½`.
    PiMoesp,
    /// Eq. (11) with `Φ = [Z_p; Ȳ_p; Z_f]`; `Γ_f = U₁S₁^½`.
    PoMoesp,
    /// The oblique projection `O_f = (Ȳ_f Π⊥ W_pᵀ)(W_p Π⊥ W_pᵀ)⁻¹ W_p`, `W_p = [Z_p; Ȳ_p]`;
    /// `Γ_f = U₁S₁^½`.
    N4sid,
    /// `(Ȳ_f Π⊥ Ȳ_fᵀ)^{-1/2}` times PO-MOESP's `O_f`: SVD `U S Vᵀ` of `L⁻¹ O_f` with
    /// `L Lᵀ = Ȳ_f Π⊥ Ȳ_fᵀ`; `Γ_f = L U₁ S₁^½`; the singular values are canonical
    /// correlations (not divided by `√j`).
    Cva,
}

/// [`identify`] with a choice of weighting.
pub fn identify_weighted(
    u: &[f64],
    y: &[f64],
    mu0: f64,
    cfg: &RefConfig,
    method: RefMethod,
) -> Result<RefModel, RefError> {
    cfg.validate()?;
    if u.len() != y.len() {
        return Err(RefError::LengthMismatch {
            u: u.len(),
            y: y.len(),
        });
    }
    if !mu0.is_finite() || u.iter().chain(y).any(|v| !v.is_finite()) {
        return Err(RefError::NonFinite);
    }
    let needed = cfg.min_samples();
    if u.len() < needed {
        return Err(RefError::TooFewSamples {
            needed,
            got: u.len(),
        });
    }
    let (f, p, n, m) = (cfg.f, cfg.p, cfg.order, cfg.m());
    let k = f + p;
    let j = u.len() - k + 1;

    // Data matrices.
    let z = regressors(u, cfg);
    let ybar = DMatrix::from_row_slice(1, y.len(), y).add_scalar(-mu0);
    let zp = block_hankel(&z, 0, p, j);
    let zf = block_hankel(&z, p, f, j);
    let yf = block_hankel(&ybar, p, f, j);
    // Instruments W_p: past inputs, and past outputs for all but PI-MOESP.
    let wp = if method == RefMethod::PiMoesp {
        zp.clone()
    } else {
        let yp = block_hankel(&ybar, 0, p, j);
        let mut w = DMatrix::zeros(p * m + p, j);
        w.view_mut((0, 0), (p * m, j)).copy_from(&zp);
        w.view_mut((p * m, 0), (p, j)).copy_from(&yp);
        w
    };
    let nw = wp.nrows();
    let mut phi = DMatrix::zeros(nw + f * m, j);
    phi.view_mut((0, 0), (nw, j)).copy_from(&wp);
    phi.view_mut((nw, 0), (f * m, j)).copy_from(&zf);

    let gram_zf = &zf * zf.transpose();
    let chol_zf = spd_factor(gram_zf, "Z_f Z_f^T")?;
    // X Π⊥_{Z_f} = X - (X Z_fᵀ)(Z_f Z_fᵀ)^{-1} Z_f.
    let perp = |x: &DMatrix<f64>| -> DMatrix<f64> {
        let xzt = x * zf.transpose();
        x - chol_zf.solve(&xzt.transpose()).transpose() * &zf
    };
    // Eq. (11): O_f = Ȳ_f Φᵀ (Φ Φᵀ)^{-1} Φ Π⊥_{Z_f} (PI- and PO-MOESP, and CVA's core).
    let moesp = || -> Result<DMatrix<f64>, RefError> {
        let chol_phi = spd_factor(&phi * phi.transpose(), "Phi Phi^T")?;
        let l_hat = chol_phi.solve(&(&phi * yf.transpose())).transpose();
        Ok(perp(&(&l_hat * &phi)))
    };
    let sqrt_j = (j as f64).sqrt();
    let (o_f, left) = match method {
        RefMethod::PiMoesp | RefMethod::PoMoesp => (moesp()?, None),
        RefMethod::N4sid => {
            let wperp = perp(&wp);
            let yperp = perp(&yf);
            let chol_w = spd_factor(&wperp * wp.transpose(), "W_p Pi W_p^T")?;
            let coef = chol_w.solve(&(&wperp * yperp.transpose())).transpose();
            (&coef * &wp, None)
        }
        RefMethod::Cva => {
            let yperp = perp(&yf);
            let lyy = (&yperp * yf.transpose())
                .cholesky()
                .ok_or(RefError::SingularGram("Y_f Pi Y_f^T"))?
                .l();
            let o = moesp()?;
            let w = lyy
                .solve_lower_triangular(&o)
                .ok_or(RefError::SingularGram("Y_f Pi Y_f^T"))?;
            (w, Some(lyy))
        }
    };

    // Eqs. (12)-(13).
    let svd = nalgebra::SVD::try_new(o_f, true, false, f64::EPSILON, 10_000)
        .ok_or(RefError::SvdFailed("O_f"))?;
    let u_full = svd.u.ok_or(RefError::SvdFailed("O_f"))?;
    let s = svd.singular_values;
    let singular_values: Vec<f64> = match method {
        RefMethod::Cva => s.iter().copied().collect(),
        _ => s.iter().map(|v| v / sqrt_j).collect(),
    };
    let u1 = u_full.columns(0, n).into_owned();
    let sqrt_s = DMatrix::from_diagonal(&s.rows(0, n).map(f64::sqrt));
    let gamma_f = match &left {
        Some(l) => l * &u1 * sqrt_s,
        None => &u1 * sqrt_s,
    };
    // U₂: the orthogonal complement of range(Γ_f).
    let q_full = gamma_f.clone().qr().q();
    let mut basis = DMatrix::<f64>::identity(f, f);
    basis.view_mut((0, 0), (f, n)).copy_from(&q_full);
    let full_q = basis.qr().q();
    let u2t = full_q.columns(n, f - n).transpose();

    // Step 1: C and A.
    let c: RowDVector<f64> = gamma_f.row(0).into_owned();
    let a = least_squares(
        gamma_f.rows(0, f - 1).into_owned(),
        &gamma_f.rows(1, f - 1).into_owned(),
        "Gamma_f",
    )?;

    // Step 2: bold B and D (MOESP, [26]): U_2ᵀ Ξ_f = U_2ᵀ Ȳ_f Z_fᵀ (Z_f Z_fᵀ)^{-1}.
    let rhs_all = &u2t * chol_zf.solve(&(&zf * yf.transpose())).transpose(); // (f-n) × f m
    let x_db = bold_bd(&u2t, &c, &a, &rhs_all, m)?;
    // Step 3: rank-1 split (eq. 14) and γ for G(1) = 1.
    split_model(x_db, a, c, singular_values, mu0, cfg, j)
}

/// Bold `[D; B]` (`(n + 1) × m`, MOESP step 2) from `U₂ᵀ` (`(f − n) × f`), `C`, `A` and the
/// right-hand side `U₂ᵀ Ȳ_f Z_fᵀ (Z_f Z_fᵀ)⁻¹` (`(f − n) × f·m`), by least squares.
pub(crate) fn bold_bd(
    u2t: &DMatrix<f64>,
    c: &RowDVector<f64>,
    a: &DMatrix<f64>,
    rhs_all: &DMatrix<f64>,
    m: usize,
) -> Result<DMatrix<f64>, RefError> {
    let (q, f, n) = (u2t.nrows(), u2t.ncols(), a.nrows());
    // C A^l for l = 0..f-1.
    let mut ca = Vec::with_capacity(f);
    let mut cur = c.clone();
    for _ in 0..f {
        ca.push(cur.clone());
        cur = &cur * a;
    }
    let mut coef = DMatrix::zeros(f * q, n + 1);
    let mut rhs = DMatrix::zeros(f * q, m);
    for jj in 0..f {
        coef.view_mut((jj * q, 0), (q, 1))
            .copy_from(&u2t.column(jj));
        let mut acc = DMatrix::zeros(q, n);
        for i in (jj + 1)..f {
            acc += u2t.column(i) * &ca[i - jj - 1];
        }
        coef.view_mut((jj * q, 1), (q, n)).copy_from(&acc);
        rhs.view_mut((jj * q, 0), (q, m))
            .copy_from(&rhs_all.view((0, jj * m), (q, m)));
    }
    least_squares(coef, &rhs, "Xi_f system") // (n+1) × m = [bold D; bold B]
}

/// The model from bold `[D; B]`, `A` and `C`: the rank-1 split (eq. 14), `γ` for `G(1) = 1`,
/// the slopes `μ` and the borders from `μ0`.
pub(crate) fn split_model(
    x_db: DMatrix<f64>,
    a: DMatrix<f64>,
    c: RowDVector<f64>,
    singular_values: Vec<f64>,
    mu0: f64,
    cfg: &RefConfig,
    j: usize,
) -> Result<RefModel, RefError> {
    let (n, n_a) = (a.nrows(), cfg.n_asc());
    let d_over = x_db.rows(0, 1).into_owned();
    let b_over = x_db.rows(1, n).into_owned();
    let svd2 = nalgebra::SVD::try_new(x_db, true, true, f64::EPSILON, 10_000)
        .ok_or(RefError::SvdFailed("[bold D; bold B]"))?;
    let uu = svd2.u.ok_or(RefError::SvdFailed("[bold D; bold B]"))?;
    let vt = svd2.v_t.ok_or(RefError::SvdFailed("[bold D; bold B]"))?;
    let s1 = svd2.singular_values[0];
    let u_d = uu[(0, 0)];
    let u_b: DVector<f64> = uu.column(0).rows(1, n).into_owned();
    let i_a = DMatrix::identity(n, n) - &a;
    let x_static = i_a.lu().solve(&u_b).ok_or(RefError::PoleAtOne)?;
    let g_dir = (&c * x_static)[(0, 0)] + u_d;
    let denom = s1 * g_dir;
    if !(denom.is_finite() && denom.abs() > f64::MIN_POSITIVE.sqrt()) {
        return Err(RefError::ZeroStaticGain);
    }
    let gamma = 1.0 / denom;
    let d = gamma * s1 * u_d;
    let b = &u_b * (gamma * s1);
    let mu: Vec<f64> = vt.row(0).iter().map(|v| v / gamma).collect();
    let mu_asc = mu[..n_a].to_vec();
    let mu_desc = mu[n_a..].to_vec();
    let borders = |knots: &[f64], mus: &[f64]| {
        let mut acc = mu0;
        let mut out = vec![mu0];
        for (w, mi) in knots.windows(2).zip(mus) {
            acc += mi * (w[1] - w[0]);
            out.push(acc);
        }
        out
    };
    let border_asc = borders(&cfg.knots_asc, &mu_asc);
    let border_desc = borders(&cfg.knots_desc, &mu_desc);

    let poles = eigenvalues(a.clone()).ok_or(RefError::EigenFailed)?;

    Ok(RefModel {
        singular_values,
        a,
        b,
        c,
        d,
        mu0,
        mu_asc,
        mu_desc,
        border_asc,
        border_desc,
        b_over,
        d_over,
        poles,
        knots_asc: cfg.knots_asc.clone(),
        knots_desc: cfg.knots_desc.clone(),
        j,
    })
}
