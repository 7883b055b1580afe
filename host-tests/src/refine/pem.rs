//! Prediction-error refinement of the whole structured model (item 4 of the issue).
//!
//! # Model structure
//!
//! `y(t) = μ0 + G(q)[H(t) − μ0] + (I(q)/F(q)) δ_{t0}(t) + (C(q)/D(q)) e(t)` for `t ≥ t0`, with
//!
//! * the plant `G(q) = B(q)/F(q)`, `F = 1 + f₁q⁻¹ + … + f_n q⁻ⁿ`,
//!   `B = b₀ + b₁q⁻¹ + … + b_n q⁻ⁿ`, in which `b₀ = F(1) − b₁ − … − b_n` is not a parameter:
//!   this fixes the scale by `G(1) = 1` (assumption A.2) and, the transfer function being
//!   unique, removes the similarity freedom of a state-space parameterisation (the refined
//!   state space is returned in observer canonical form, `D = b₀`);
//! * `H(t) = Σ_k β_k w_k(t)`, the hat-basis regressors of [`signal`](super::signal) with the
//!   border values `β = (μ0, P_a(n₁ᵃ) …, P_d(n₁ᵈ) …)` as parameters (μ0 is estimated jointly,
//!   with or without a hold);
//! * the noise model `C(q)/D(q)` (ARMA, order from BIC on the starting residual or given);
//! * optionally the initial plant state as the free response `I(q)/F(q)`, `deg I = n − 1`
//!   ([`PemInitialState::Estimate`]); with [`PemInitialState::Rest`] the plant starts at rest at μ0
//!   at `t0` (after a settled hold).
//!
//! The one-step-ahead prediction error is `ε(t) = (D/C)(y − ŷ_det)`; its Jacobian is computed
//! analytically by filtering (`∂ŷ/∂f_i = (1/F)(H − μ0) − q⁻ⁱ(1/F)(ŷ_det − μ0)`, `∂ŷ/∂b_i =
//! ((q⁻ⁱ − 1)/F)(H − μ0)`, `∂ŷ/∂β_k = G w_k`, `∂ε/∂d_i = (q⁻ⁱ/C)(y − ŷ_det)`,
//! `∂ε/∂c_i = −(q⁻ⁱ/C) ε`). The cost `Σ ε²` is minimised by Levenberg–Marquardt with
//! Marquardt's diagonal scaling; a trial step that makes `F` or `C` unstable is rejected like
//! one that increases the cost. The iteration count is bounded; a non-finite cost or exploding
//! parameters give [`RefineError::Diverged`]; at the limit [`refine`] keeps the last iterate
//! and says so ([`PemFit::unconverged`]), [`minimise`] gives [`RefineError::NoConvergence`].
//!
//! At the optimum, `σ̂² = Σε²/(N − d)` and the asymptotic covariance of the parameters is
//! `σ̂² (JᵀJ)⁻¹` ([`PemFit::covariance`]), from which [`uncertainty`](super::uncertainty)
//! derives the standard deviations of the poles, the Bode magnitude and the borders.

use std::cell::RefCell;
use std::time::Instant;

use nalgebra::{DMatrix, DVector};

use super::poly::{observer_form, spectral_radius, tf_from_ss};
use super::signal::{HatRegressors, Stepped, push_lag};
use super::stochastic::{NoiseModel, fit_noise};
use super::{RefineError, Unstable};
use crate::identify::{HostModel, IdentifyOptions, identify};
use crate::numerics::lm::{self, Exhausted, Jacobian, LmFailure, Settings};

pub use super::stochastic::NoiseOrder;

/// How the plant's state at the first sample used is handled.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PemInitialState {
    /// At rest at μ0 (the record starts inside a settled hold at `u_min`).
    Rest,
    /// Estimated: `n` more parameters (any record).
    Estimate,
}

/// Settings of the refinement.
#[derive(Clone, Debug, PartialEq)]
pub struct PemOptions {
    /// Noise model order.
    pub noise_order: NoiseOrder,
    /// Initial plant state.
    pub initial: PemInitialState,
    /// First sample used (e.g. the end of the settling part of the hold).
    pub start: usize,
    /// Iteration limit.
    pub max_iter: usize,
    /// Convergence: relative cost decrease below this.
    pub tol: f64,
    /// Direct feed-through of the plant.
    pub feedthrough: Feedthrough,
    /// A static (memoryless) nonlinearity: one border for both directions.
    pub static_nonlinearity: bool,
}

/// Whether the plant has a direct feed-through `D`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Feedthrough {
    /// `D` is estimated (the subspace model's structure).
    Free,
    /// `D = 0`: the plant is strictly proper (a sampled plant without direct feed-through,
    /// as the paper's `G(q) = q⁻¹(…)`).
    Zero,
    /// `D` is estimated, then dropped when the estimate is within two standard deviations of
    /// zero (and the model refitted without it).
    Auto,
}

impl Default for PemOptions {
    fn default() -> Self {
        Self {
            noise_order: NoiseOrder::default(),
            initial: PemInitialState::Rest,
            start: 0,
            max_iter: 100,
            tol: 1e-10,
            feedthrough: Feedthrough::Auto,
            static_nonlinearity: false,
        }
    }
}

impl PemOptions {
    /// The options matching a subspace identification's: start after the settling part of
    /// the hold with the plant at rest, or, without a hold, at the first sample with the
    /// initial state estimated.
    pub fn for_identify(opts: &IdentifyOptions) -> Self {
        let base = Self {
            static_nonlinearity: opts.static_nonlinearity,
            ..Self::default()
        };
        if opts.hold > 0 {
            Self {
                start: opts.settle.min(opts.hold),
                initial: PemInitialState::Rest,
                ..base
            }
        } else {
            Self {
                start: 0,
                initial: PemInitialState::Estimate,
                ..base
            }
        }
    }
}

/// Where each parameter group sits in `θ`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ParamLayout {
    /// Plant order `n`.
    pub n: usize,
    /// Border channels `1 + n_a + n_d` (μ0 first).
    pub channels: usize,
    /// Noise order.
    pub nv: usize,
    /// Whether the initial state is estimated.
    pub init: bool,
    /// Whether `G` has a direct feed-through `b₀ = D` (else `b₀ = 0`, the plant is strictly
    /// proper, and `b_n` is the coefficient fixed by `G(1) = 1`).
    pub feedthrough: bool,
    /// Whether both directions share one border (a static nonlinearity).
    pub shared: bool,
}

impl ParamLayout {
    /// `f₁ … f_n`.
    pub fn f(&self) -> std::ops::Range<usize> {
        0..self.n
    }
    /// The free numerator coefficients: `b₁ … b_n` with a feed-through, `b₁ … b_{n−1}`
    /// without.
    pub fn b(&self) -> std::ops::Range<usize> {
        self.n..self.n + self.nb()
    }
    /// Number of free numerator coefficients.
    pub(crate) fn nb(&self) -> usize {
        if self.feedthrough { self.n } else { self.n - 1 }
    }
    /// Power of `q⁻¹` of the numerator coefficient fixed by `G(1) = 1` (0 or `n`).
    pub fn eliminated(&self) -> usize {
        if self.feedthrough { 0 } else { self.n }
    }
    /// `β` (μ0 then the border values).
    pub fn beta(&self) -> std::ops::Range<usize> {
        let s = self.b().end;
        s..s + self.channels
    }
    /// Noise denominator `d₁ …`.
    pub fn nd(&self) -> std::ops::Range<usize> {
        let s = self.beta().end;
        s..s + self.nv
    }
    /// Noise numerator `c₁ …`.
    pub fn nc(&self) -> std::ops::Range<usize> {
        let s = self.nd().end;
        s..s + self.nv
    }
    /// Initial-state coefficients `ι₀ … ι_{n−1}` (empty unless estimated).
    pub fn iota(&self) -> std::ops::Range<usize> {
        let s = self.nc().end;
        s..s + if self.init { self.n } else { 0 }
    }
    /// Number of parameters.
    pub fn len(&self) -> usize {
        self.iota().end
    }
    /// Whether there are no parameters (never: the plant has at least order 1).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// The polynomials of a parameter vector.
#[derive(Clone, Debug, PartialEq)]
pub struct Polynomials {
    /// `F = [1, f₁ …]`.
    pub f: Vec<f64>,
    /// `B = [b₀, b₁ …, b_n]`, the eliminated coefficient set so that `B(1) = F(1)`.
    pub b: Vec<f64>,
    /// Noise numerator `[1, c₁ …]`.
    pub c: Vec<f64>,
    /// Noise denominator `[1, d₁ …]`.
    pub d: Vec<f64>,
}

impl ParamLayout {
    /// Splits `θ` into its polynomials.
    pub fn polynomials(&self, th: &[f64]) -> Polynomials {
        let mut f = vec![1.0];
        f.extend(&th[self.f()]);
        let bs = &th[self.b()];
        let rest = f.iter().sum::<f64>() - bs.iter().sum::<f64>();
        let b = if self.feedthrough {
            std::iter::once(rest).chain(bs.iter().copied()).collect()
        } else {
            std::iter::once(0.0)
                .chain(bs.iter().copied())
                .chain(std::iter::once(rest))
                .collect()
        };
        let mut c = vec![1.0];
        c.extend(&th[self.nc()]);
        let mut d = vec![1.0];
        d.extend(&th[self.nd()]);
        Polynomials { f, b, c, d }
    }
}

/// The model structure of a [`PemProblem`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PemStructure {
    /// Plant order `n`.
    pub n: usize,
    /// Noise model order (ARMA(nv, nv)).
    pub nv: usize,
    /// Initial plant state.
    pub initial: PemInitialState,
    /// First sample in the cost.
    pub start: usize,
    /// Direct feed-through `D` estimated (else `D = 0`).
    pub feedthrough: bool,
    /// A static nonlinearity: one border for both directions.
    pub shared: bool,
    /// Leading prediction errors left out of the cost (see [`BURN_IN`]).
    pub burn: usize,
}

/// Default number of leading prediction errors left out of the cost. The predictor starts
/// from a zero noise state, so its first errors are not innovations: they carry the
/// stationary noise variance (`|G_v|²` times `σ_e²`, 7.6 times on the paper's example) while
/// the filtered regressors of the constant channels are largest there (the step response of
/// `D/C` from zero). Kept in the cost, they inflate the spread of μ0 and the borders well
/// beyond `σ² (JᵀJ)⁻¹`; 50 samples let a noise numerator with roots up to 0.87 in modulus
/// forget its initial state to 10⁻³.
pub const BURN_IN: usize = 50;

/// The leading prediction errors left out of the cost: [`BURN_IN`] for a plant at rest at the
/// start, none when the initial state is estimated. The first samples are the ones that
/// determine the initial state: its free response may have decayed by the end of a burn-in,
/// leaving the state's parameters undetermined (a singular information matrix, parameters
/// that run away); the predictor's own transient is then part of the cost, as in a toolbox's
/// prediction-error fit with the initial state estimated.
pub fn burn_in(initial: PemInitialState) -> usize {
    match initial {
        PemInitialState::Estimate => 0,
        PemInitialState::Rest => BURN_IN,
    }
}

/// A prediction-error problem: the data and the structure, without the parameters.
#[derive(Clone, Debug)]
pub struct PemProblem<'a> {
    layout: ParamLayout,
    hat: HatRegressors,
    /// `y[start..]`, borrowed: a long record is not held twice.
    y: &'a [f64],
    start: usize,
    burn: usize,
}

/// Rows of the Jacobian gathered before their products are added to the normal equations.
const ROW_BLOCK: usize = 256;

/// Prediction errors and the normal equations of their Jacobian at one parameter vector,
/// accumulated sample by sample: no `N × d` matrix is formed ([`PemProblem::jacobian`] gives
/// it for checks).
#[derive(Clone, Debug)]
pub struct PemEvaluation {
    /// `ε(t)`, `t = start + burn …`.
    pub eps: Vec<f64>,
    /// `JᵀJ` with `J = ∂ε/∂θ` (`d × d`), the information matrix up to `σ²`.
    pub jtj: DMatrix<f64>,
    /// `Jᵀr` with `r` the residual the evaluation was asked for (`ε` itself by default).
    pub jtr: DVector<f64>,
    /// `Σ ε²`.
    pub cost: f64,
}

impl<'a> PemProblem<'a> {
    /// Sets up the problem of structure `st` on `u`, `y` with the given knots.
    pub fn new(
        u: &[f64],
        y: &'a [f64],
        knots_asc: &[f64],
        knots_desc: &[f64],
        st: PemStructure,
    ) -> Result<Self, RefineError> {
        let PemStructure {
            n,
            nv,
            initial,
            start,
            feedthrough,
            shared,
            burn,
        } = st;
        if n == 0 {
            return Err(RefineError::InvalidModel("order 0"));
        }
        if u.len() != y.len() {
            return Err(RefineError::LengthMismatch {
                u: u.len(),
                y: y.len(),
            });
        }
        if y.iter().any(|v| !v.is_finite()) {
            return Err(RefineError::NonFinite);
        }
        let hat = HatRegressors::build(u, knots_asc, knots_desc, shared)?;
        let layout = ParamLayout {
            n,
            channels: hat.channels(),
            nv,
            init: initial == PemInitialState::Estimate,
            feedthrough,
            shared,
        };
        let have = u.len().saturating_sub(start);
        let need = 4 * layout.len() + 50 + burn;
        if have < need {
            return Err(RefineError::TooFewSamples { have, need });
        }
        Ok(Self {
            layout,
            hat,
            y: &y[start..],
            start,
            burn,
        })
    }

    /// The parameter layout.
    pub fn layout(&self) -> ParamLayout {
        self.layout
    }

    /// The hat regressors of the whole record.
    pub fn regressors(&self) -> &HatRegressors {
        &self.hat
    }

    /// Samples in the cost (after the burn-in).
    pub fn samples(&self) -> usize {
        self.y.len().saturating_sub(self.burn)
    }

    /// First sample used.
    pub fn start(&self) -> usize {
        self.start
    }

    /// Whether the predictor of `θ` is stable (`F` and `C` inside the unit circle).
    pub(crate) fn check_stable(&self, th: &[f64]) -> Result<(), RefineError> {
        let p = self.layout.polynomials(th);
        let rf = spectral_radius(&p.f);
        if rf >= 1.0 {
            return Err(RefineError::UnstablePredictor {
                which: Unstable::Plant,
                radius: rf,
            });
        }
        let rc = spectral_radius(&p.c);
        if rc >= 1.0 {
            return Err(RefineError::UnstablePredictor {
                which: Unstable::Noise,
                radius: rc,
            });
        }
        Ok(())
    }

    /// The deterministic output `ŷ_det(t)` over `start..` (no noise model).
    pub fn simulate(&self, th: &[f64]) -> Vec<f64> {
        let l = self.layout;
        let p = l.polynomials(th);
        let beta = &th[l.beta()];
        let mu0 = beta[0];
        let mut plant = Stepped::new(&p.b, &p.f);
        let mut free = Stepped::new(&th[l.iota()], &p.f);
        let mut w = vec![0.0; l.channels];
        (0..self.y.len())
            .map(|t| {
                let hd = self.hat_at(t, beta, &mut w);
                let mut xr = plant.step(hd);
                if l.init {
                    xr += free.step(if t == 0 { 1.0 } else { 0.0 });
                }
                xr + mu0
            })
            .collect()
    }

    /// `H(t) − μ0` at sample `t` of the problem (`start + t` of the record), its channels
    /// left in `w`.
    fn hat_at(&self, t: usize, beta: &[f64], w: &mut [f64]) -> f64 {
        self.hat.sample_into(self.start + t, w);
        let mut h = 0.0;
        for (b, wk) in beta.iter().zip(w.iter()) {
            h += b * wk;
        }
        h - beta.first().copied().unwrap_or(0.0)
    }

    /// Prediction errors in the cost (`t ≥ start + burn`), the predictor run sample by sample
    /// (the values [`evaluate`](Self::evaluate) gives, without the Jacobian).
    pub fn errors(&self, th: &[f64]) -> Vec<f64> {
        let l = self.layout;
        let p = l.polynomials(th);
        let beta = &th[l.beta()];
        let mu0 = beta[0];
        let mut plant = Stepped::new(&p.b, &p.f);
        let mut free = Stepped::new(&th[l.iota()], &p.f);
        let mut noise = Stepped::new(&p.d, &p.c);
        let mut w = vec![0.0; l.channels];
        let mut e = Vec::with_capacity(self.samples());
        for (t, y) in self.y.iter().enumerate() {
            let hd = self.hat_at(t, beta, &mut w);
            let mut xr = plant.step(hd);
            if l.init {
                xr += free.step(if t == 0 { 1.0 } else { 0.0 });
            }
            let eps = noise.step(y - (xr + mu0));
            if t >= self.burn {
                e.push(eps);
            }
        }
        e
    }

    /// Prediction errors and the normal equations of the analytic Jacobian at `θ`
    /// (`Jᵀε`).
    pub fn evaluate(&self, th: &[f64]) -> PemEvaluation {
        self.evaluate_against(th, None)
    }

    /// [`evaluate`](Self::evaluate) with `Jᵀr` for the residual `r` (one value per sample in
    /// the cost; `ε` itself when `None` or of another length).
    pub fn evaluate_against(&self, th: &[f64], r: Option<&[f64]>) -> PemEvaluation {
        let d = self.layout.len();
        let r = r.filter(|r| r.len() == self.samples());
        let mut jtj = DMatrix::<f64>::zeros(d, d);
        let mut jtr = DVector::<f64>::zeros(d);
        let mut eps = Vec::with_capacity(self.samples());
        // Rows gathered in blocks, each block's `BᵀB` and `Bᵀr` added by a matrix product.
        let mut block = DMatrix::<f64>::zeros(ROW_BLOCK, d);
        let mut rb = DVector::<f64>::zeros(ROW_BLOCK);
        let mut filled = 0;
        let mut add = |block: &DMatrix<f64>, rb: &DVector<f64>, rows: usize| {
            let (b, r) = (block.rows(0, rows), rb.rows(0, rows));
            jtj.gemm_tr(1.0, &b, &b, 1.0);
            jtr.gemv_tr(1.0, &b, &r, 1.0);
        };
        self.rows(th, |e, j| {
            rb[filled] = r.map_or(e, |r| r.get(eps.len()).copied().unwrap_or(e));
            block.row_mut(filled).copy_from_slice(j);
            filled += 1;
            if filled == ROW_BLOCK {
                add(&block, &rb, filled);
                filled = 0;
            }
            eps.push(e);
        });
        add(&block, &rb, filled);
        let cost = eps.iter().map(|e| e * e).sum();
        PemEvaluation {
            eps,
            jtj,
            jtr,
            cost,
        }
    }

    /// The analytic Jacobian `∂ε/∂θ` at `θ` as a matrix (`N × d`, a row per sample in the
    /// cost): for checks and short records; the refinement uses
    /// [`evaluate`](Self::evaluate).
    pub fn jacobian(&self, th: &[f64]) -> DMatrix<f64> {
        let d = self.layout.len();
        let mut values = Vec::with_capacity(self.samples() * d);
        self.rows(th, |_, j| values.extend_from_slice(j));
        DMatrix::from_row_slice(values.len() / d.max(1), d, &values)
    }

    /// Runs the predictor at `θ` sample by sample and calls `row(ε(t), ∂ε(t)/∂θ)` for every
    /// sample in the cost, in order. Every signal is a filter of the one before it, so each
    /// is carried as a filter state (the lags of the Jacobian's columns as short histories):
    /// nothing the record's length is kept.
    ///
    /// With `e` the eliminated power, `∂B/∂f_i = q⁻ᵉ` and `∂B/∂b_i = q⁻ⁱ − q⁻ᵉ`: the columns
    /// of `f_i` are `q⁻ᵉ g − q⁻ⁱ k` and of `b_i` `q⁻ⁱ g − q⁻ᵉ g`, with `g = (H − μ0)/F` and
    /// `k = (x + r)/F`; the border columns `G w_k` (μ0's `G (w_0 − 1) + 1`); the
    /// initial-state columns `q⁻ᵏ δ/F`; each deterministic column through `−D/C`. The noise
    /// columns are `q⁻ⁱ (y − ŷ_det)/C` and `−q⁻ⁱ ε/C`.
    fn rows(&self, th: &[f64], mut row: impl FnMut(f64, &[f64])) {
        let l = self.layout;
        let p = l.polynomials(th);
        let beta = &th[l.beta()];
        let mu0 = beta[0];
        let one = [1.0];
        let (n, nb, e, nv) = (l.n, l.nb(), l.eliminated(), l.nv);
        let mut plant = Stepped::new(&p.b, &p.f);
        let mut free = Stepped::new(&th[l.iota()], &p.f);
        let mut noise = Stepped::new(&p.d, &p.c);
        let mut g_f = Stepped::new(&one, &p.f);
        let mut k_f = Stepped::new(&one, &p.f);
        let mut i_f = Stepped::new(&one, &p.f);
        let mut r_c = Stepped::new(&one, &p.c);
        let mut e_c = Stepped::new(&one, &p.c);
        let mut borders: Vec<Stepped> = (0..l.channels).map(|_| Stepped::new(&p.b, &p.f)).collect();
        // One `D/C` per deterministic column: f, b, β, ι in the layout's order.
        let det_columns = l.f().chain(l.b()).chain(l.beta()).chain(l.iota());
        let mut det: Vec<(usize, Stepped)> =
            det_columns.map(|c| (c, Stepped::new(&p.d, &p.c))).collect();
        let lags = n.max(nb).max(e) + 1;
        let (mut g, mut k) = (vec![0.0; lags], vec![0.0; lags]);
        let mut gf = vec![0.0; n.max(1)];
        let (mut rc, mut ec) = (vec![0.0; nv + 1], vec![0.0; nv + 1]);
        let mut w = vec![0.0; l.channels];
        let mut raw_columns = vec![0.0; det.len()];
        let mut j = vec![0.0; l.len()];
        for t in 0..self.y.len() {
            let hd = self.hat_at(t, beta, &mut w);
            let imp = if t == 0 { 1.0 } else { 0.0 };
            let mut xr = plant.step(hd);
            if l.init {
                xr += free.step(imp);
            }
            let raw = self.y[t] - (xr + mu0);
            let eps = noise.step(raw);
            push_lag(&mut g, g_f.step(hd));
            push_lag(&mut k, k_f.step(xr));
            push_lag(&mut gf, i_f.step(imp));
            push_lag(&mut rc, r_c.step(raw));
            push_lag(&mut ec, e_c.step(eps));
            let mut c = raw_columns.iter_mut();
            for ki in k.iter().skip(1).take(n) {
                c.next().into_iter().for_each(|v| *v = g[e] - ki);
            }
            for i in 1..=nb {
                c.next().into_iter().for_each(|v| *v = g[i] - g[e]);
            }
            for (kk, (wk, f)) in w.iter().zip(borders.iter_mut()).enumerate() {
                let v = match kk {
                    0 => f.step(wk - 1.0) + 1.0,
                    _ => f.step(*wk),
                };
                c.next().into_iter().for_each(|x| *x = v);
            }
            if l.init {
                for gk in gf.iter().take(n) {
                    c.next().into_iter().for_each(|v| *v = *gk);
                }
            }
            for ((col, f), v) in det.iter_mut().zip(&raw_columns) {
                j[*col] = -f.step(*v);
            }
            for i in 1..=nv {
                j[l.nd().start + i - 1] = rc[i];
                j[l.nc().start + i - 1] = -ec[i];
            }
            if t >= self.burn {
                row(eps, &j);
            }
        }
    }

    /// `θ` of a deterministic model and a noise model (initial-state coefficients 0).
    pub fn theta_from(
        &self,
        model: &HostModel,
        noise: &NoiseModel,
    ) -> Result<Vec<f64>, RefineError> {
        let l = self.layout;
        if model.order != l.n || model.a.nrows() != l.n || model.b.len() != l.n {
            return Err(RefineError::InvalidModel(
                "order differs from the problem's",
            ));
        }
        let (num, den) = tf_from_ss(&model.a, &model.b, &model.c, model.d);
        let mut th = vec![0.0; l.len()];
        th[l.f()].copy_from_slice(&den[1..]);
        th[l.b()].copy_from_slice(&num[1..=l.nb()]);
        let beta = self
            .hat
            .beta_of(model.mu0, &model.border_asc, &model.border_desc);
        if beta.len() != l.channels {
            return Err(RefineError::InvalidModel(
                "border count differs from the knots'",
            ));
        }
        th[l.beta()].copy_from_slice(&beta);
        for (i, r) in l.nd().enumerate() {
            th[r] = noise.d.get(i + 1).copied().unwrap_or(0.0);
        }
        for (i, r) in l.nc().enumerate() {
            th[r] = noise.c.get(i + 1).copied().unwrap_or(0.0);
        }
        if th.iter().any(|v| !v.is_finite()) {
            return Err(RefineError::NonFinite);
        }
        Ok(th)
    }

    /// The deterministic model of `θ` in observer canonical form, with the knots, singular
    /// values and horizons of `template`.
    pub(crate) fn model_of(&self, th: &[f64], template: &HostModel, samples: usize) -> HostModel {
        let l = self.layout;
        let p = l.polynomials(th);
        let (a, b, c, d) = observer_form(&p.b, &p.f);
        let (border_asc, border_desc) = self.hat.borders_from_beta(&th[l.beta()]);
        HostModel {
            order: l.n,
            a,
            b,
            c,
            d,
            mu0: th[l.beta().start],
            knots_asc: template.knots_asc.clone(),
            knots_desc: template.knots_desc.clone(),
            border_asc,
            border_desc,
            singular_values: template.singular_values.clone(),
            whitened_singular_values: template.whitened_singular_values.clone(),
            f: template.f,
            p: template.p,
            samples,
        }
    }

    /// The noise model of `θ` with variance `sigma2`.
    pub(crate) fn noise_of(&self, th: &[f64], sigma2: f64) -> NoiseModel {
        let p = self.layout.polynomials(th);
        NoiseModel {
            c: p.c,
            d: p.d,
            sigma2,
        }
    }
}

/// The outcome of a refinement.
#[derive(Clone, Debug)]
pub struct PemFit {
    /// The refined deterministic model (observer canonical form, `G(1) = 1`).
    pub model: HostModel,
    /// The refined noise model, `σ_e²` included.
    pub noise: NoiseModel,
    /// The parameter vector.
    pub theta: Vec<f64>,
    /// Where the parameter groups sit in `θ`.
    pub layout: ParamLayout,
    /// Asymptotic covariance `σ̂² (JᵀJ)⁻¹` of `θ` (zero when [`singular`](Self::singular)).
    pub covariance: DMatrix<f64>,
    /// The information matrix `JᵀJ` at the optimum is singular: the data do not determine
    /// every parameter, the estimate stands but has no covariance (no standard deviations are
    /// reported from it).
    pub singular: bool,
    /// Iterations done.
    pub iterations: usize,
    /// The relative cost decrease of the last step when the iteration limit stopped the
    /// refinement before it converged (the model is the last iterate); `None` when converged.
    pub unconverged: Option<f64>,
    /// Mean squared prediction error `Σε²/N`.
    pub mse: f64,
    /// Samples in the cost.
    pub samples: usize,
    /// First sample used.
    pub start: usize,
    /// `(noise order, BIC)` of the Hannan–Rissanen candidates (the smallest BIC was kept).
    pub noise_bic: Vec<(usize, f64)>,
    /// Cost `Σε²` of the starting point (subspace model + fitted noise model).
    pub initial_cost: f64,
    /// Cost at the optimum.
    pub cost: f64,
    /// Wall-clock seconds of the refinement.
    pub seconds: f64,
}

impl PemFit {
    /// The innovation form `(A, B, C, D, K, σ_e²)` of the refined model.
    pub fn innovation_form(&self) -> super::InnovationForm {
        super::InnovationForm::new(&self.model, &self.noise)
    }

    /// Number of estimated parameters.
    pub fn parameters(&self) -> usize {
        self.layout.len()
    }
}

/// Minimises the prediction-error cost of `problem` from `theta0` by
/// [`numerics::lm`](crate::numerics::lm) with the analytic Jacobian and
/// [`Settings::prediction_error`]; the iteration limit is an error
/// ([`RefineError::NoConvergence`]).
///
/// Returns `(θ, evaluation at θ, iterations)`.
pub fn minimise(
    problem: &PemProblem,
    theta0: Vec<f64>,
    max_iter: usize,
    tol: f64,
) -> Result<(Vec<f64>, PemEvaluation, usize), RefineError> {
    let m = minimise_to_limit(problem, theta0, max_iter, tol)?;
    match m.unconverged {
        Some(last_decrease) => Err(RefineError::NoConvergence {
            iterations: m.iterations,
            last_decrease,
        }),
        None => Ok((m.theta, m.evaluation, m.iterations)),
    }
}

/// What [`minimise_to_limit`] gives.
#[derive(Clone, Debug)]
pub struct PemMinimum {
    /// The parameters of the smallest cost reached.
    pub theta: Vec<f64>,
    /// The evaluation at `theta`.
    pub evaluation: PemEvaluation,
    /// Iterations done.
    pub iterations: usize,
    /// The relative cost decrease of the last accepted step when the iteration limit ended
    /// the minimisation before the convergence test passed; `None` when it converged.
    pub unconverged: Option<f64>,
}

/// [`minimise`] that keeps the last iterate at the iteration limit, as a prediction-error
/// estimator in a toolbox does (the cost only decreased on the way): the limit is reported in
/// [`PemMinimum::unconverged`], not as an error.
pub fn minimise_to_limit(
    problem: &PemProblem,
    theta0: Vec<f64>,
    max_iter: usize,
    tol: f64,
) -> Result<PemMinimum, RefineError> {
    problem.check_stable(&theta0)?;
    // The last evaluation, kept for the result when it is at the optimum.
    let last: RefCell<Option<(Vec<f64>, PemEvaluation)>> = RefCell::new(None);
    let residual = |th: &[f64]| Some(problem.errors(th));
    let admissible = |th: &[f64]| problem.check_stable(th).is_ok();
    // The normal equations, not the Jacobian, go to the iteration, and the previous
    // evaluation is dropped before the next is made: one Jacobian (a row per sample) is held
    // at a time.
    let normal = |th: &[f64], r: &[f64]| {
        *last.borrow_mut() = None;
        let ev = problem.evaluate_against(th, Some(r));
        let normal = (ev.jtj.clone(), ev.jtr.clone());
        *last.borrow_mut() = Some((th.to_vec(), ev));
        normal
    };
    let lm = lm::Problem {
        residual: &residual,
        admissible: &admissible,
        jacobian: Jacobian::Normal(&normal),
    };
    let cost0 = problem.errors(&theta0).iter().map(|e| e * e).sum::<f64>();
    if !cost0.is_finite() {
        return Err(RefineError::Diverged { iteration: 0 });
    }
    let settings = Settings {
        exhausted: Exhausted::ReturnBest,
        ..Settings::prediction_error(max_iter, tol)
    };
    let min = match lm::minimise(&lm, &theta0, &settings) {
        Ok(min) => min,
        Err(LmFailure::Diverged { iteration }) => return Err(RefineError::Diverged { iteration }),
        // Every prediction error is computed, the Jacobian is analytic, and the budget's end
        // returns the last iterate.
        Err(
            LmFailure::StartDoesNotSimulate
            | LmFailure::DifferenceStepFailed { .. }
            | LmFailure::NoConvergence { .. },
        ) => {
            return Err(RefineError::Diverged { iteration: 0 });
        }
    };
    let evaluation = match last.into_inner() {
        Some((th, ev)) if th == min.theta => ev,
        _ => problem.evaluate(&min.theta),
    };
    Ok(PemMinimum {
        theta: min.theta,
        evaluation,
        iterations: min.iterations,
        unconverged: min.unconverged,
    })
}

/// `σ̂² (JᵀJ)⁻¹` at an evaluation.
pub fn covariance(ev: &PemEvaluation) -> Result<(DMatrix<f64>, f64), RefineError> {
    let (n, d) = (ev.eps.len(), ev.jtj.nrows());
    let sigma2 = ev.cost / (n.saturating_sub(d)).max(1) as f64;
    let h = &ev.jtj;
    // Scale to unit diagonal for the inversion.
    let s: Vec<f64> = (0..d).map(|i| 1.0 / h[(i, i)].max(1e-300).sqrt()).collect();
    let hs = DMatrix::from_fn(d, d, |i, j| h[(i, j)] * s[i] * s[j]);
    let inv = hs
        .cholesky()
        .ok_or(RefineError::Singular("information matrix JᵀJ"))?
        .inverse();
    Ok((
        DMatrix::from_fn(d, d, |i, j| sigma2 * inv[(i, j)] * s[i] * s[j]),
        sigma2,
    ))
}

/// Refines a subspace model `init` (with knots, μ0 and borders) on the record `(u, y)`.
///
/// With [`NoiseOrder::Fixed`] the noise model starts from the Hannan–Rissanen fit of the
/// simulation residual and every parameter is refined jointly. With [`NoiseOrder::Auto`] the
/// plant and borders are first refined with a white noise model (output error), the noise
/// order is chosen by BIC on that residual (which is then nearly the noise alone), and
/// everything is refined jointly from there. With [`Feedthrough::Auto`] a feed-through `D`
/// within two standard deviations of zero is dropped and the model refitted.
pub fn refine(
    u: &[f64],
    y: &[f64],
    init: &HostModel,
    opts: &PemOptions,
) -> Result<PemFit, RefineError> {
    let clock = Instant::now();
    if u.len() != y.len() {
        return Err(RefineError::LengthMismatch {
            u: u.len(),
            y: y.len(),
        });
    }
    if init.order == 0 {
        return Err(RefineError::InvalidModel("order 0"));
    }
    let (_, den) = tf_from_ss(&init.a, &init.b, &init.c, init.d);
    let radius = spectral_radius(&den);
    if radius >= 1.0 {
        return Err(RefineError::UnstablePredictor {
            which: Unstable::Plant,
            radius,
        });
    }
    let start = opts.start.min(u.len());
    // The simulation's residual, in the simulation's own buffer.
    let mut resid = init.simulate(u);
    resid.iter_mut().zip(y).for_each(|(s, y)| *s = y - *s);
    resid.drain(..start);
    let free = opts.feedthrough != Feedthrough::Zero;
    let mut fit = refine_structure(u, y, init, opts, start, &resid, free)?;
    if opts.feedthrough == Feedthrough::Auto {
        let (d, sd) = feedthrough_std(&fit);
        if d.abs() < 2.0 * sd
            && let Ok((mut strict, _)) =
                refine_from(u, y, &fit.model, &fit.noise, opts, start, false)
        {
            strict.noise_bic = std::mem::take(&mut fit.noise_bic);
            strict.initial_cost = fit.initial_cost;
            fit = strict;
        }
    }
    fit.seconds = clock.elapsed().as_secs_f64();
    Ok(fit)
}

/// `D = b₀` of a fit with a feed-through and its standard deviation (`(0, 0)` without one).
pub fn feedthrough_std(fit: &PemFit) -> (f64, f64) {
    let l = fit.layout;
    if !l.feedthrough {
        return (0.0, 0.0);
    }
    // b₀ = 1 + Σ f_i − Σ b_i: gradient +1 on f, −1 on b.
    let idx: Vec<(usize, f64)> = l
        .f()
        .map(|i| (i, 1.0))
        .chain(l.b().map(|i| (i, -1.0)))
        .collect();
    let mut var = 0.0;
    for &(i, gi) in &idx {
        for &(j, gj) in &idx {
            var += gi * gj * fit.covariance[(i, j)];
        }
    }
    (fit.model.d, var.max(0.0).sqrt())
}

/// The noise-order logic of [`refine`] for one feed-through structure.
fn refine_structure(
    u: &[f64],
    y: &[f64],
    init: &HostModel,
    opts: &PemOptions,
    start: usize,
    resid: &[f64],
    free: bool,
) -> Result<PemFit, RefineError> {
    match opts.noise_order {
        NoiseOrder::Fixed(k) => {
            let nfit = fit_noise(resid, NoiseOrder::Fixed(k))?;
            let (mut fit, _) = refine_from(u, y, init, &nfit.model, opts, start, free)?;
            fit.noise_bic = nfit.bic;
            Ok(fit)
        }
        NoiseOrder::Auto { max } => {
            // 1. Output error (white noise model): the plant and borders, nearly efficient.
            let white = fit_noise(resid, NoiseOrder::Fixed(0))?;
            let (oe, oe_resid) = refine_from(u, y, init, &white.model, opts, start, free)?;
            // 2. The noise order by BIC on the output-error residual (≈ v(t) alone).
            let nfit = fit_noise(&oe_resid, NoiseOrder::Auto { max })?;
            if nfit.model.order() == 0 {
                let mut fit = oe;
                fit.noise_bic = nfit.bic;
                return Ok(fit);
            }
            // 3. Everything jointly, from the output-error estimate and the fitted noise.
            let (mut fit, _) = refine_from(u, y, &oe.model, &nfit.model, opts, start, free)?;
            fit.noise_bic = nfit.bic;
            fit.initial_cost = oe.initial_cost;
            Ok(fit)
        }
    }
}

/// One refinement from `init` and the starting noise model `noise`; also returns the
/// deterministic residual `y − ŷ_det` over `start..` at the optimum.
fn refine_from(
    u: &[f64],
    y: &[f64],
    init: &HostModel,
    noise: &NoiseModel,
    opts: &PemOptions,
    start: usize,
    feedthrough: bool,
) -> Result<(PemFit, Vec<f64>), RefineError> {
    let problem = PemProblem::new(
        u,
        y,
        &init.knots_asc,
        &init.knots_desc,
        PemStructure {
            n: init.order,
            nv: noise.order(),
            initial: opts.initial,
            start,
            feedthrough,
            shared: opts.static_nonlinearity,
            burn: burn_in(opts.initial),
        },
    )?;
    let th0 = problem.theta_from(init, noise)?;
    let initial_cost = problem.errors(&th0).iter().map(|e| e * e).sum::<f64>();
    let PemMinimum {
        theta: th,
        evaluation: ev,
        iterations,
        unconverged,
    } = minimise_to_limit(&problem, th0, opts.max_iter, opts.tol)?;
    let (cov, sigma2, singular) = match covariance(&ev) {
        Ok((cov, sigma2)) => (cov, sigma2, false),
        // The data do not determine every parameter (a pole cancelled by a zero, an initial
        // state the record hardly excites): the estimate stands, its covariance does not.
        Err(RefineError::Singular(_)) => {
            let (n, d) = (ev.eps.len(), ev.jtj.nrows());
            let sigma2 = ev.cost / (n.saturating_sub(d)).max(1) as f64;
            (DMatrix::zeros(d, d), sigma2, true)
        }
        Err(e) => return Err(e),
    };
    let model = problem.model_of(&th, init, u.len());
    let noise = problem.noise_of(&th, sigma2);
    let cost = ev.cost;
    // The prediction errors are not needed past here: freed before the simulation.
    drop(ev);
    let mut raw = problem.simulate(&th);
    raw.iter_mut()
        .zip(&y[start..])
        .for_each(|(s, y)| *s = y - *s);
    let fit = PemFit {
        model,
        noise,
        layout: problem.layout(),
        covariance: cov,
        iterations,
        unconverged,
        singular,
        mse: cost / problem.samples() as f64,
        samples: problem.samples(),
        start,
        noise_bic: Vec::new(),
        initial_cost,
        cost,
        theta: th,
        seconds: 0.0,
    };
    Ok((fit, raw))
}

/// The deterministic output `ŷ_det` of `fit` on the record `(u, y)` over `fit.start..`, its
/// initial state (when estimated) and borders as fitted: the fit's simulation carried on past
/// the samples it was fitted on (`u` may be longer than those).
pub fn simulate_fit(u: &[f64], y: &[f64], fit: &PemFit) -> Result<Vec<f64>, RefineError> {
    let l = fit.layout;
    let problem = PemProblem::new(
        u,
        y,
        &fit.model.knots_asc,
        &fit.model.knots_desc,
        PemStructure {
            n: l.n,
            nv: l.nv,
            initial: match l.init {
                true => PemInitialState::Estimate,
                false => PemInitialState::Rest,
            },
            start: fit.start,
            feedthrough: l.feedthrough,
            shared: l.shared,
            burn: BURN_IN,
        },
    )?;
    Ok(problem.simulate(&fit.theta))
}

/// Subspace identification (the method in `opts`) followed by [`refine`] with
/// [`PemOptions::for_identify`] and the given noise order.
pub fn identify_pem(
    u: &[f64],
    y: &[f64],
    opts: &IdentifyOptions,
    noise_order: NoiseOrder,
) -> Result<PemFit, RefineError> {
    let init = identify(u, y, opts)?;
    let pem = PemOptions {
        noise_order,
        ..PemOptions::for_identify(opts)
    };
    refine(u, y, &init, &pem)
}
