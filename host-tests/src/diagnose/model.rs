//! The extended model: the paper's Hammerstein model plus the catalog's extensions, fitted
//! together on the estimation data by backfitting.
//!
//! ```text
//! y(t) = g( G(q) H[u(t − d)] ) + trend(t) + Σ_k (a_k cos ω_k t + b_k sin ω_k t) + v(t)
//! v(t) = Σ_i c_i v(t − i) + e(t)                      (noise model, for prediction)
//! ```
//!
//! * `d` (`input_delay`) shifts the input before the Hammerstein model,
//! * the order of `G` (`unmodeled_dynamics`) is passed to the subspace identification,
//! * `g` (`output_nonlinearity`) is a monotone piecewise-linear output map on knots at
//!   quantiles of the Hammerstein output (a Hammerstein–Wiener model), fitted by non-negative
//!   least squares on its increments,
//! * `trend` (`offset_drift`) is a polynomial in time, the sinusoids (`periodic_disturbance`)
//!   have fixed frequencies and least-squares amplitudes,
//! * the AR noise model (`colored_noise`) gives one-step-ahead predictions,
//! * `outliers`: samples flagged by the MAD rule are replaced, in the identification target,
//!   by the model's own output (robust re-estimation), and left out of the error.
//!
//! Backfitting: the Hammerstein part is identified on `g⁻¹(y − additive)` (flagged samples and
//! samples on a flat part of `g` imputed from the previous iterate), then `g` is fitted from the
//! simulated Hammerstein output to `y − additive`, then the additive terms to `y − g(·)`, then
//! the outliers are flagged again; three rounds.

use std::ops::Range;

use nalgebra::{DMatrix, DVector};
use serde::Serialize;

use super::dynamics::{Borders, DynamicsFit};
use super::error::DiagnoseError;
use super::noise::{ArNoise, fit_ar};
use super::optimise::{JacobianFailure, Settings, levenberg_marquardt};
use super::output_map::OutputMap;
use super::simulate::{
    delay_input, level_of, linear_response, nonlinearity_output, rest_state, steady_state,
};
use super::stats::{lstsq, mad_sigma, nnls, rms, running_median};
use super::stores::{self, Stores, StoresClass};
use crate::identify::{HostModel, IdentifyOptions, identify};
use crate::report::fit;

/// An input/output record with the time of each sample (sample index in the original file;
/// time-dependent terms are evaluated at it).
#[derive(Clone, Debug, PartialEq)]
pub struct Record {
    /// Input.
    pub u: Vec<f64>,
    /// Output.
    pub y: Vec<f64>,
    /// Time of each sample, in samples.
    pub time: Vec<f64>,
}

impl Record {
    /// A record whose time is the sample index `0, 1, …`.
    pub fn new(u: Vec<f64>, y: Vec<f64>) -> Self {
        let time = (0..u.len()).map(|t| t as f64).collect();
        Self { u, y, time }
    }

    /// Samples.
    pub fn len(&self) -> usize {
        self.u.len()
    }

    /// No samples.
    pub fn is_empty(&self) -> bool {
        self.u.is_empty()
    }

    /// A contiguous part (time kept).
    pub fn slice(&self, r: Range<usize>) -> Record {
        Record {
            u: self.u[r.clone()].to_vec(),
            y: self.y[r.clone()].to_vec(),
            time: self.time[r].to_vec(),
        }
    }

    /// Concatenation of parts of this record (time kept: a junction shows as a jump in time).
    pub fn parts(&self, ranges: &[Range<usize>]) -> Record {
        let mut out = Record {
            u: Vec::new(),
            y: Vec::new(),
            time: Vec::new(),
        };
        for r in ranges {
            out.u.extend_from_slice(&self.u[r.clone()]);
            out.y.extend_from_slice(&self.y[r.clone()]);
            out.time.extend_from_slice(&self.time[r.clone()]);
        }
        out
    }
}

/// How the simulation of a record starts.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum InitialState {
    /// At rest at `u_min` (as after the identification hold).
    Rest,
    /// At rest at a level fitted by least squares on the estimation record (the state
    /// `(I − A)⁻¹ B c`, one parameter `c`); every record simulated starts from it (for records
    /// that do not start at rest at `u_min`, assumed to start alike).
    Estimated,
}

/// Everything the fit needs besides the structure and the data.
#[derive(Clone, Debug, PartialEq)]
pub struct FitOptions {
    /// The base identification options (knots, horizons, hold, μ0, static or not; the order
    /// here is the base order, overridden by [`Structure::order`]).
    pub identify: IdentifyOptions,
    /// Initial state of simulations.
    pub initial: InitialState,
    /// Centre of the time axis for the polynomial trend (samples).
    pub time_center: f64,
    /// Half-width of the time axis for the polynomial trend (samples).
    pub time_scale: f64,
    /// MAD rule threshold for outliers, in robust standard deviations.
    pub outlier_k: f64,
    /// Backfitting rounds when the structure has more than the Hammerstein part.
    pub rounds: usize,
    /// Refit the border values (and μ0, and the initial state when estimated) by least squares
    /// on the output with `A, B, C, D` fixed (the paper's Remark 5), after the subspace step.
    pub refit: bool,
    /// Refine the poles too: the characteristic polynomial of `A` by Levenberg–Marquardt on the
    /// simulation error, the rest (`B`, `D`, borders, μ0, initial level) by least squares for
    /// every candidate (variable projection). With an output map, the poles are refined by a
    /// bounded simplex search with the borders, `B`, `D` and the map refit for every candidate.
    pub refine_poles: bool,
    /// Saturation levels of the output (from the data checks): the output map is clipped there.
    pub saturation: Saturation,
}

/// Levels at which the measured output saturates (found by the data checks).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Saturation {
    /// Upper level.
    pub ceiling: Option<f64>,
    /// Lower level.
    pub floor: Option<f64>,
    /// Samples within this of a level are at it.
    pub tolerance: f64,
}

impl Saturation {
    /// Whether `y` sits at a saturation level.
    pub fn at_limit(&self, y: f64) -> bool {
        self.ceiling.is_some_and(|c| y >= c - self.tolerance)
            || self.floor.is_some_and(|f| y <= f + self.tolerance)
    }

    /// Whether any level is known.
    pub fn any(&self) -> bool {
        self.ceiling.is_some() || self.floor.is_some()
    }
}

/// Which extensions a model has, with their settings.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Structure {
    /// Extra input delay in samples (`input_delay`).
    pub delay: usize,
    /// Model order (`None`: the base option, automatic or fixed); `unmodeled_dynamics`.
    pub order: Option<usize>,
    /// Horizons `f = p` (`None`: the base options); raised with the order.
    pub horizon: Option<usize>,
    /// Degree of the polynomial output trend in time (`offset_drift`).
    pub trend_degree: Option<usize>,
    /// Frequencies of additive sinusoids, radians per sample (`periodic_disturbance`).
    pub frequencies: Vec<f64>,
    /// Segments of the monotone output map (`output_nonlinearity`).
    pub output_map_segments: Option<usize>,
    /// Order of the AR noise model (`colored_noise`).
    pub noise_ar_order: Option<usize>,
    /// Robust re-estimation with outliers flagged by the MAD rule (`outliers`).
    pub robust: bool,
    /// The dynamics between the input nonlinearity and the output map
    /// (`state_dependent_dynamics`).
    pub dynamics: Dynamics,
}

/// The dynamics between the input nonlinearity and the output map.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Dynamics {
    /// The identified linear `G` (the paper's model).
    Linear,
    /// Level-dependent stores ([`super::stores`]) started from `G`, the borders refitted with
    /// them.
    Stores,
    /// The same stores with linear outflows and no overflow: the linear cascade refitted as
    /// the stores are (the reference that `Stores` must beat, not an effect of its own).
    LinearStores,
}

impl Dynamics {
    /// The stores class fitted, if any.
    pub fn stores(self) -> Option<StoresClass> {
        match self {
            Dynamics::Linear => None,
            Dynamics::Stores => Some(StoresClass::LevelDependent),
            Dynamics::LinearStores => Some(StoresClass::Linear),
        }
    }
}

impl Structure {
    /// The paper's model: no extension.
    pub fn base() -> Self {
        Self {
            delay: 0,
            order: None,
            horizon: None,
            trend_degree: None,
            frequencies: Vec::new(),
            output_map_segments: None,
            noise_ar_order: None,
            robust: false,
            dynamics: Dynamics::Linear,
        }
    }

    /// Backfitting rounds: 3 with an output map or outliers (the identification target is
    /// imputed), 2 with additive terms only, 1 otherwise.
    fn rounds(&self) -> usize {
        if self.output_map_segments.is_some() || self.robust {
            3
        } else if self.trend_degree.is_some() || !self.frequencies.is_empty() {
            2
        } else {
            1
        }
    }
}

/// Additive output terms: a polynomial trend in normalised time and sinusoids.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Additive {
    /// Trend coefficients of `τ^k`, `τ = (t − center) / scale` (empty: no trend).
    pub trend: Vec<f64>,
    /// Sinusoid frequencies, radians per sample.
    pub frequencies: Vec<f64>,
    /// `(a, b)` of `a cos ωt + b sin ωt` per frequency.
    pub sin_cos: Vec<(f64, f64)>,
    /// Time centre (samples).
    pub center: f64,
    /// Time scale (samples).
    pub scale: f64,
}

impl Additive {
    fn columns(&self) -> usize {
        self.trend.len() + 2 * self.frequencies.len()
    }

    fn row(&self, t: f64, out: &mut Vec<f64>) {
        out.clear();
        let tau = (t - self.center) / self.scale;
        let mut p = 1.0;
        for _ in 0..self.trend.len() {
            out.push(p);
            p *= tau;
        }
        for &w in &self.frequencies {
            out.push((w * t).cos());
            out.push((w * t).sin());
        }
    }

    /// The additive output at time `t`.
    pub fn eval(&self, t: f64) -> f64 {
        let tau = (t - self.center) / self.scale;
        let mut s = 0.0;
        let mut p = 1.0;
        for c in &self.trend {
            s += c * p;
            p *= tau;
        }
        for (&w, &(a, b)) in self.frequencies.iter().zip(&self.sin_cos) {
            s += a * (w * t).cos() + b * (w * t).sin();
        }
        s
    }

    /// Least squares of the terms on `r` at times `time`, leaving out flagged samples.
    fn fit(&mut self, r: &[f64], time: &[f64], skip: &[bool]) {
        let k = self.columns();
        if k == 0 {
            return;
        }
        let rows: Vec<usize> = (0..r.len()).filter(|&i| !skip[i]).collect();
        let mut x = DMatrix::<f64>::zeros(rows.len(), k);
        let mut buf = Vec::with_capacity(k);
        for (ri, &i) in rows.iter().enumerate() {
            self.row(time[i], &mut buf);
            for (c, v) in buf.iter().enumerate() {
                x[(ri, c)] = *v;
            }
        }
        let y = DVector::from_iterator(rows.len(), rows.iter().map(|&i| r[i]));
        if let Some(beta) = lstsq(&x, &y) {
            let nt = self.trend.len();
            for (c, v) in self.trend.iter_mut().enumerate() {
                *v = beta[c];
            }
            for (j, sc) in self.sin_cos.iter_mut().enumerate() {
                *sc = (beta[nt + 2 * j], beta[nt + 2 * j + 1]);
            }
        }
    }
}

/// The fitted extended model.
#[derive(Clone, Debug, PartialEq)]
pub struct ExtendedModel {
    /// Its structure.
    pub structure: Structure,
    /// The Hammerstein part (identified on the delayed input).
    pub hammerstein: HostModel,
    /// Initial state of simulations.
    pub x0: Vec<f64>,
    /// Output map `g` (Hammerstein–Wiener), if any.
    pub output_map: Option<OutputMap>,
    /// Additive output terms.
    pub additive: Additive,
    /// Noise model, if any.
    pub noise: Option<ArNoise>,
    /// MAD rule threshold (robust standard deviations) for the outliers.
    pub outlier_k: f64,
    /// Samples of the estimation data flagged as outliers.
    pub flagged: usize,
    /// Level-dependent stores replacing `G`'s simulation ([`Dynamics::Stores`]).
    pub stores: Option<Stores>,
}

/// Least-squares initial state at rest at a level `c`: `target(t) − zero-state response =
/// c · C A^t (I − A)⁻¹ B`.
fn estimate_x0(m: &HostModel, h: &[f64], target: &[f64], skip: &[bool]) -> Vec<f64> {
    let n = m.order;
    let zs = linear_response(m, h, &vec![0.0; n]);
    let xs = steady_state(m);
    let free = linear_response(m, &vec![0.0; h.len()], &xs);
    let (mut num, mut den) = (0.0, 0.0);
    for t in 0..target.len() {
        if !skip[t] {
            num += free[t] * (target[t] - zs[t]);
            den += free[t] * free[t];
        }
    }
    let c = if den > 0.0 { num / den } else { m.mu0 };
    xs.iter().map(|v| v * c).collect()
}

/// The output of the Hammerstein part is linear in the border values at the knots (μ0 shared
/// by both paths, A.1) and, for an estimated initial state, in `x0`, once `A, B, C, D` are
/// fixed. This is that linear map: one column per unknown, one row per sample.
pub struct BorderBasis {
    /// Columns: `ψ_c = G0[φ_c]` (zero-state responses of the hat channels; column 0 is μ0's,
    /// already combined with the rest state), then `C A^t` for an estimated initial state.
    cols: Vec<Vec<f64>>,
    /// Border unknowns (μ0, ascending knots 1…, descending knots 1…).
    borders: usize,
    /// Segments of the ascending path.
    na: usize,
    /// Segments of the descending path.
    nd: usize,
    shared: bool,
    initial: InitialState,
}

impl BorderBasis {
    /// The basis of a model for an input record.
    pub fn new(m: &HostModel, u: &[f64], initial: InitialState, shared: bool) -> Option<Self> {
        let n = u.len();
        let na = m.knots_asc.len().checked_sub(1)?;
        let nd = m.knots_desc.len().checked_sub(1)?;
        if na == 0 || nd == 0 {
            return None;
        }
        let borders = 1 + na + if shared { 0 } else { nd };
        let phi = border_channels(m, u, shared)?;
        let order = m.order;
        let zero = vec![0.0; order];
        let mut cols: Vec<Vec<f64>> = phi.iter().map(|p| linear_response(m, p, &zero)).collect();
        match initial {
            InitialState::Rest => {
                // Rest at μ0 before the record: y = μ0 (1 − Σ_{c≥1} ψ_c) + Σ_{c≥1} v_c ψ_c.
                #[allow(clippy::needless_range_loop)]
                for t in 0..n {
                    let s: f64 = (1..borders).map(|c| cols[c][t]).sum();
                    cols[0][t] = 1.0 - s;
                }
            }
            InitialState::Estimated => {
                // Free response from rest at the unit level, C A^t (I − A)⁻¹ B.
                let xs = steady_state(m);
                cols.push(linear_response(m, &vec![0.0; n], &xs));
            }
        }
        Some(Self {
            cols,
            borders,
            na,
            nd,
            shared,
            initial,
        })
    }

    /// The output for the unknowns `beta`.
    pub fn output(&self, beta: &[f64]) -> Vec<f64> {
        let n = self.cols.first().map_or(0, Vec::len);
        (0..n)
            .map(|t| self.cols.iter().zip(beta).map(|(c, b)| c[t] * b).sum())
            .collect()
    }

    /// The unknowns of a model (`x0` for an estimated initial state).
    pub fn unknowns(&self, m: &HostModel, x0: &[f64]) -> Vec<f64> {
        let mut b = vec![m.mu0];
        b.extend(m.border_asc.iter().skip(1));
        if !self.shared {
            b.extend(m.border_desc.iter().skip(1));
        }
        if self.initial == InitialState::Estimated {
            b.push(level_of(m, x0));
        }
        b
    }

    /// Weighted least squares `min Σ_t (w_t (row_t · β) − rhs_t)²` over samples not skipped.
    pub fn solve(&self, rhs: &[f64], weight: Option<&[f64]>, skip: &[bool]) -> Option<Vec<f64>> {
        let rows: Vec<usize> = (0..rhs.len()).filter(|&t| !skip[t]).collect();
        let k = self.cols.len();
        let mut x = DMatrix::<f64>::zeros(rows.len(), k);
        for (r, &t) in rows.iter().enumerate() {
            let w = weight.map_or(1.0, |w| w[t]);
            for c in 0..k {
                x[(r, c)] = w * self.cols[c][t];
            }
        }
        let y = DVector::from_iterator(rows.len(), rows.iter().map(|&t| rhs[t]));
        let beta = lstsq(&x, &y)?;
        beta.iter()
            .all(|v| v.is_finite())
            .then(|| beta.iter().copied().collect())
    }

    /// The model with the border values of `beta`, and its initial state.
    pub fn apply(&self, m: &HostModel, beta: &[f64]) -> (HostModel, Vec<f64>) {
        let mut out = m.clone();
        out.mu0 = beta[0];
        out.border_asc = (0..=self.na)
            .map(|j| if j == 0 { beta[0] } else { beta[j] })
            .collect();
        out.border_desc = if self.shared {
            out.border_asc.clone()
        } else {
            (0..=self.nd)
                .map(|j| if j == 0 { beta[0] } else { beta[self.na + j] })
                .collect()
        };
        let x0 = match self.initial {
            InitialState::Estimated => {
                let c = beta.get(self.borders).copied().unwrap_or(0.0);
                steady_state(&out).iter().map(|v| v * c).collect()
            }
            InitialState::Rest => rest_state(&out),
        };
        (out, x0)
    }
}

/// The border values refit by least squares with `A, B, C, D` fixed (Remark 5 of the paper:
/// `B` and `μ` separately once `A` and `C` are known). Returns the model with the new borders
/// and μ0, and the initial state (fitted too when estimated).
pub fn refit_borders(
    m: &HostModel,
    u: &[f64],
    target: &[f64],
    skip: &[bool],
    initial: InitialState,
    shared: bool,
) -> Option<(HostModel, Vec<f64>)> {
    let basis = BorderBasis::new(m, u, initial, shared)?;
    let beta = basis.solve(target, None, skip)?;
    Some(basis.apply(m, &beta))
}

/// `B` and `D` of the linear part given the borders and `A`, `C`: the output is linear in
/// `[B; D]` (and in `x0` when estimated; at rest the rest state `(I − A)⁻¹ B μ0` is linear in
/// `B` too). After the solve `G(1) = 1` is restored by scaling `B`, `D` down and the borders up.
struct BdBasis {
    cols: Vec<Vec<f64>>,
    order: usize,
    initial: InitialState,
    level: f64,
}

impl BdBasis {
    fn new(m: &HostModel, u: &[f64], x0: &[f64], initial: InitialState) -> Option<Self> {
        let n = m.order;
        // The rest level the record starts from: μ0, or the fitted level.
        let level = match initial {
            InitialState::Rest => m.mu0,
            InitialState::Estimated => level_of(m, x0),
        };
        let h = nonlinearity_output(m, u);
        let len = u.len();
        // Free response rows C A^t.
        let mut ca = vec![vec![0.0; n]; len];
        let mut v = m.c.clone();
        for row in ca.iter_mut() {
            row.copy_from_slice(&v);
            v = (0..n)
                .map(|j| (0..n).map(|i| v[i] * m.a[(i, j)]).sum())
                .collect();
        }
        let ia = DMatrix::<f64>::identity(n, n) - &m.a;
        let ia_inv = ia.try_inverse()?;
        let mut cols = Vec::with_capacity(2 * n + 1);
        for i in 0..n {
            // y_i(t) = C x(t), x(t+1) = A x(t) + e_i h(t).
            let mut x = vec![0.0; n];
            let mut col = Vec::with_capacity(len);
            for (t, &ht) in h.iter().enumerate() {
                // Plus the free response from rest: C A^t (I − A)⁻¹ e_i · level.
                let y: f64 = m.c.iter().zip(&x).map(|(c, x)| c * x).sum::<f64>()
                    + level * (0..n).map(|j| ca[t][j] * ia_inv[(j, i)]).sum::<f64>();
                col.push(y);
                let mut next: Vec<f64> = (0..n)
                    .map(|r| (0..n).map(|c| m.a[(r, c)] * x[c]).sum())
                    .collect();
                next[i] += ht;
                x = next;
            }
            cols.push(col);
        }
        cols.push(h);
        Some(Self {
            cols,
            order: n,
            initial,
            level,
        })
    }

    fn solve(&self, rhs: &[f64], weight: Option<&[f64]>, skip: &[bool]) -> Option<Vec<f64>> {
        let rows: Vec<usize> = (0..rhs.len()).filter(|&t| !skip[t]).collect();
        let k = self.cols.len();
        let x = DMatrix::from_fn(rows.len(), k, |r, c| {
            weight.map_or(1.0, |w| w[rows[r]]) * self.cols[c][rows[r]]
        });
        let y = DVector::from_iterator(rows.len(), rows.iter().map(|&t| rhs[t]));
        let beta = lstsq(&x, &y)?;
        beta.iter()
            .all(|v| v.is_finite())
            .then(|| beta.iter().copied().collect())
    }

    fn unknowns(&self, m: &HostModel) -> Vec<f64> {
        let mut b = m.b.clone();
        b.push(m.d);
        b
    }

    /// The model with `[B; D]` (normalised to `G(1) = 1`, the borders scaled inversely).
    fn apply(&self, m: &HostModel, beta: &[f64]) -> Option<(HostModel, Vec<f64>)> {
        let n = self.order;
        let mut out = m.clone();
        out.b = beta[..n].to_vec();
        out.d = beta[n];
        let ia = DMatrix::<f64>::identity(n, n) - &out.a;
        let xs = ia.lu().solve(&DVector::from_column_slice(&out.b))?;
        // The initial state before normalisation: (I − A)⁻¹ B_raw · level (unchanged by it).
        let x_start: Vec<f64> = xs.iter().map(|v| v * self.level).collect();
        let gain = out.d + out.c.iter().zip(xs.iter()).map(|(c, x)| c * x).sum::<f64>();
        if !(gain.is_finite() && gain.abs() > 1e-9) {
            return None;
        }
        for v in out.b.iter_mut() {
            *v /= gain;
        }
        out.d /= gain;
        out.mu0 *= gain;
        for v in out.border_asc.iter_mut().chain(out.border_desc.iter_mut()) {
            *v *= gain;
        }
        let x0 = match self.initial {
            InitialState::Estimated => x_start,
            InitialState::Rest => rest_state(&out),
        };
        Some((out, x0))
    }
}

/// Least-squares refinement with `A` and `C` fixed (the paper's Remark 5: `B` and `μ`
/// separately once `A` and `C` are known): alternately the border values (with μ0 and an
/// estimated initial state) and `[B; D]`, each a linear least squares; with an output map `g`,
/// alternately the monotone map by non-negative least squares and damped Gauss–Newton steps
/// of the borders and of `[B; D]` through the map (`ŷ = g(ℓ)`, Jacobian `g'(ℓ) ∂ℓ`: samples on a
/// flat part of `g` do not pull the linear part). Every step is kept only if it lowers the
/// squared error over the samples not skipped.
#[allow(clippy::too_many_arguments)]
fn refine_linear(
    m: &HostModel,
    x0: &[f64],
    u: &[f64],
    y: &[f64],
    skip: &[bool],
    map_segments: Option<usize>,
    sat: &Saturation,
    initial: InitialState,
    shared: bool,
) -> (HostModel, Vec<f64>, Option<OutputMap>) {
    let lin_of = |m: &HostModel, x0: &[f64]| linear_response(m, &nonlinearity_output(m, u), x0);
    let fit_map = |lin: &[f64]| map_segments.and_then(|k| fit_output_map(lin, y, skip, k, sat));
    let sse = |lin: &[f64], g: &Option<OutputMap>| -> f64 {
        lin.iter()
            .zip(y)
            .zip(skip)
            .filter(|(_, s)| !**s)
            .map(|((l, y), _)| (y - g.as_ref().map_or(*l, |g| g.eval(*l))).powi(2))
            .sum()
    };
    let mut model = m.clone();
    let mut state = x0.to_vec();
    let mut lin = lin_of(&model, &state);
    let mut g = fit_map(&lin);
    let mut best = sse(&lin, &g);
    if !best.is_finite() {
        return (model, state, g);
    }
    for _ in 0..4 {
        let mut improved = false;
        for part in 0..2 {
            let slope: Vec<f64> = lin
                .iter()
                .map(|&l| g.as_ref().map_or(1.0, |g| g.slope_at(l)))
                .collect();
            let rhs: Vec<f64> = (0..y.len())
                .map(|t| y[t] - g.as_ref().map_or(lin[t], |g| g.eval(lin[t])) + slope[t] * lin[t])
                .collect();
            let w = g.as_ref().map(|_| slope.as_slice());
            // The unknowns now and their least-squares solution.
            let (bb, bd) = if part == 0 {
                (BorderBasis::new(&model, u, initial, shared), None)
            } else {
                (None, BdBasis::new(&model, u, &state, initial))
            };
            let step = match (&bb, &bd) {
                (Some(b), _) => b
                    .solve(&rhs, w, skip)
                    .map(|next| (b.unknowns(&model, &state), next)),
                (_, Some(b)) => b
                    .solve(&rhs, w, skip)
                    .map(|next| (b.unknowns(&model), next)),
                _ => None,
            };
            let Some((now, next)) = step else { continue };
            let mut a = 1.0;
            for _ in 0..5 {
                let trial: Vec<f64> = now
                    .iter()
                    .zip(&next)
                    .map(|(b, n)| b + a * (n - b))
                    .collect();
                let built = match (&bb, &bd) {
                    (Some(b), _) => Some(b.apply(&model, &trial)),
                    (_, Some(b)) => b.apply(&model, &trial),
                    _ => None,
                };
                if let Some((m2, x2)) = built {
                    let l2 = lin_of(&m2, &x2);
                    let g2 = if g.is_some() { fit_map(&l2) } else { None };
                    let e = sse(&l2, &g2);
                    if e < best * (1.0 - 1e-9) {
                        best = e;
                        model = m2;
                        state = x2;
                        lin = l2;
                        g = g2;
                        improved = true;
                        break;
                    }
                }
                a *= 0.5;
            }
        }
        if !improved {
            break;
        }
    }
    (model, state, g)
}

/// Monic polynomial `z^n + a_1 z^{n−1} + … + a_n` with the given roots; returns `a_1 … a_n`.
fn poly_from_roots(roots: &[(f64, f64)]) -> Vec<f64> {
    let mut p = vec![1.0];
    let mut i = 0;
    let mul = |p: &[f64], f: &[f64]| -> Vec<f64> {
        let mut out = vec![0.0; p.len() + f.len() - 1];
        for (i, a) in p.iter().enumerate() {
            for (j, b) in f.iter().enumerate() {
                out[i + j] += a * b;
            }
        }
        out
    };
    while i < roots.len() {
        let (re, im) = roots[i];
        if im.abs() > 1e-12 && i + 1 < roots.len() {
            p = mul(&p, &[1.0, -2.0 * re, re * re + im * im]);
            i += 2;
        } else {
            p = mul(&p, &[1.0, -re]);
            i += 1;
        }
    }
    p[1..].to_vec()
}

/// The observer canonical `A` of `z^n + a_1 z^{n−1} + … + a_n`: first column `−a`, ones on
/// the superdiagonal.
fn observer_a(a: &[f64]) -> DMatrix<f64> {
    let n = a.len();
    DMatrix::from_fn(n, n, |i, j| {
        if j == 0 {
            -a[i]
        } else if j == i + 1 {
            1.0
        } else {
            0.0
        }
    })
}

/// The linear part in observer canonical form (`C = e₁`): the same transfer function.
fn to_observer(m: &HostModel) -> Option<(Vec<f64>, HostModel)> {
    let n = m.order;
    if n == 0 {
        return None;
    }
    let poles = m.poles();
    if poles.len() != n {
        return None;
    }
    let a = poly_from_roots(&poles);
    // Markov parameters h_k = C A^{k−1} B, k = 1…n.
    let mut h = Vec::with_capacity(n);
    let mut v = DVector::from_column_slice(&m.b);
    for _ in 0..n {
        h.push(m.c.iter().zip(v.iter()).map(|(c, x)| c * x).sum::<f64>());
        v = &m.a * v;
    }
    let b: Vec<f64> = (0..n)
        .map(|k| h[k] + (0..k).map(|i| a[i] * h[k - 1 - i]).sum::<f64>())
        .collect();
    let mut out = m.clone();
    out.a = observer_a(&a);
    out.b = b;
    out.c = (0..n).map(|i| if i == 0 { 1.0 } else { 0.0 }).collect();
    Some((a, out))
}

/// Residual of the over-parameterised model with `A` fixed: the output is linear in the
/// products `B_i v_c`, `D v_c` (and `B_i c` for an estimated initial level), which makes the
/// residual a smooth function of `A` (the paper's eq. 7 with `A`, `C` given). `m` is in
/// observer canonical form with characteristic polynomial `a`: the response of `y` to an input
/// into state `i` is `q^{−i} / A(q⁻¹)`, so one filter per channel and shifts give every column.
fn overparameterised_residual(
    m: &HostModel,
    a: &[f64],
    phi: &[Vec<f64>],
    y: &[f64],
    skip: &[bool],
    initial: InitialState,
) -> Option<Vec<f64>> {
    let n = m.order;
    let len = y.len();
    let ia = DMatrix::<f64>::identity(n, n) - &m.a;
    let ia_inv = ia.try_inverse()?;
    // Free responses from rest, ρ_i(t) = C A^t (I − A)⁻¹ e_i.
    let mut rho = vec![vec![0.0; len]; n];
    for (i, r) in rho.iter_mut().enumerate() {
        let mut x: Vec<f64> = (0..n).map(|j| ia_inv[(j, i)]).collect();
        for v in r.iter_mut() {
            *v = x[0];
            x = (0..n)
                .map(|row| (0..n).map(|k| m.a[(row, k)] * x[k]).sum())
                .collect();
        }
    }
    let mut cols: Vec<Vec<f64>> = Vec::with_capacity(phi.len() * (n + 1) + n);
    for (c, ph) in phi.iter().enumerate() {
        // w = φ / A(q⁻¹) from rest.
        let mut w = vec![0.0; len];
        for t in 0..len {
            let mut v = ph[t];
            for (k, ak) in a.iter().enumerate() {
                if t > k {
                    v -= ak * w[t - 1 - k];
                }
            }
            w[t] = v;
        }
        for i in 1..=n {
            let col: Vec<f64> = (0..len)
                .map(|t| {
                    let base = if t >= i { w[t - i] } else { 0.0 };
                    if c == 0 && initial == InitialState::Rest {
                        base + rho[i - 1][t]
                    } else {
                        base
                    }
                })
                .collect();
            cols.push(col);
        }
        cols.push(ph.clone());
    }
    if initial == InitialState::Estimated {
        cols.extend(rho);
    }
    let rows: Vec<usize> = (0..len).filter(|&t| !skip[t]).collect();
    let x = DMatrix::from_fn(rows.len(), cols.len(), |r, c| cols[c][rows[r]]);
    let yy = DVector::from_iterator(rows.len(), rows.iter().map(|&t| y[t]));
    let beta = lstsq(&x, &yy)?;
    let fit = &x * beta;
    Some((0..rows.len()).map(|r| yy[r] - fit[r]).collect())
}

/// The hat channels of the borders (column 0: the knot `u_min`).
fn border_channels(m: &HostModel, u: &[f64], shared: bool) -> Option<Vec<Vec<f64>>> {
    let na = m.knots_asc.len().checked_sub(1)?;
    let nd = m.knots_desc.len().checked_sub(1)?;
    if na == 0 || nd == 0 {
        return None;
    }
    let borders = 1 + na + if shared { 0 } else { nd };
    let mut phi = vec![vec![0.0; u.len()]; borders];
    let mut up = false;
    let mut prev = m.u_min();
    for (t, &ui) in u.iter().enumerate() {
        if ui > prev {
            up = true;
        } else if ui < prev {
            up = false;
        }
        prev = ui;
        let (k, off) = if up || shared {
            (&m.knots_asc, 0)
        } else {
            (&m.knots_desc, na)
        };
        let segs = k.len() - 1;
        let s = k.iter().rposition(|&x| x <= ui).unwrap_or(0).min(segs - 1);
        let th = ((ui - k[s]) / (k[s + 1] - k[s])).clamp(0.0, 1.0);
        let col = |j: usize| if j == 0 { 0 } else { off + j };
        phi[col(s)][t] += 1.0 - th;
        phi[col(s + 1)][t] += th;
    }
    Some(phi)
}

/// Largest root modulus of `z^n + a_1 z^{n−1} + …`.
fn root_radius(a: &[f64]) -> f64 {
    crate::sim::eigenvalues(observer_a(a)).map_or(f64::INFINITY, |ev| {
        ev.iter().map(|(r, i)| r.hypot(*i)).fold(0.0, f64::max)
    })
}

/// Levenberg–Marquardt on the characteristic polynomial of `A` (variable projection: the
/// residual of the over-parameterised least squares for every `A`), kept stable with time
/// constants below twice the record; then `B`, `D`, borders by [`refine_linear`].
#[allow(clippy::too_many_arguments)]
fn refine_poles(
    m: &HostModel,
    x0: &[f64],
    u: &[f64],
    y: &[f64],
    skip: &[bool],
    initial: InitialState,
    shared: bool,
) -> Option<(HostModel, Vec<f64>)> {
    let (mut a, obs) = to_observer(m)?;
    let n = a.len();
    let limit = 1.0 - 0.5 / u.len().max(4) as f64;
    if root_radius(&a) >= limit {
        // Start from the subspace poles pulled inside: |p| ≤ 0.99 · limit.
        let poles: Vec<(f64, f64)> = m
            .poles()
            .into_iter()
            .map(|(re, im)| {
                let r = re.hypot(im);
                let k = if r >= 0.99 * limit {
                    0.99 * limit / r
                } else {
                    1.0
                };
                (re * k, im * k)
            })
            .collect();
        a = poly_from_roots(&poles);
    }
    let phi = border_channels(m, u, shared)?;
    let resid = |a: &[f64]| -> Option<Vec<f64>> {
        let mut mm = obs.clone();
        mm.a = observer_a(a);
        overparameterised_residual(&mm, a, &phi, y, skip, initial)
    };
    let settings = Settings {
        iterations: 12,
        initial_damping: 1e-3,
        tries: 5,
        min_gain: 1e-5,
        jacobian_failure: JacobianFailure::Fail,
    };
    let (a, _) = levenberg_marquardt(&a, &vec![1e-2; n], &settings, &resid, &|trial: &[f64]| {
        root_radius(trial) < limit
    })?;
    let mut mm = obs;
    mm.a = observer_a(&a);
    let x0 = match initial {
        InitialState::Rest => rest_state(&mm),
        InitialState::Estimated => {
            let c = level_of(m, x0);
            steady_state(&mm).iter().map(|v| v * c).collect()
        }
    };
    let (m2, x2, _) = refine_linear(
        &mm,
        &x0,
        u,
        y,
        skip,
        None,
        &Saturation::default(),
        initial,
        shared,
    );
    Some((m2, x2))
}

/// The poles of a model with an output map refined on the simulation error: a bounded
/// Nelder–Mead search over the characteristic polynomial of `A` (stable, time constants below
/// twice the record), with the borders, `B`, `D`, the initial level and the map refit by
/// [`refine_linear`] for every candidate. Returns `None` when nothing improves.
#[allow(clippy::too_many_arguments)]
fn refine_poles_mapped(
    m: &HostModel,
    x0: &[f64],
    u: &[f64],
    y: &[f64],
    skip: &[bool],
    map_segments: Option<usize>,
    sat: &Saturation,
    initial: InitialState,
    shared: bool,
) -> Option<(HostModel, Vec<f64>, Option<OutputMap>)> {
    let (a0, obs) = to_observer(m)?;
    let n = a0.len();
    let limit = 1.0 - 0.5 / u.len().max(4) as f64;
    let level = level_of(m, x0);
    let eval = |a: &[f64]| -> Option<(f64, HostModel, Vec<f64>, Option<OutputMap>)> {
        if root_radius(a) >= limit {
            return None;
        }
        let mut mm = obs.clone();
        mm.a = observer_a(a);
        let xs = match initial {
            InitialState::Rest => rest_state(&mm),
            InitialState::Estimated => steady_state(&mm).iter().map(|v| v * level).collect(),
        };
        let (m2, x2, g) = refine_linear(&mm, &xs, u, y, skip, map_segments, sat, initial, shared);
        let lin = linear_response(&m2, &nonlinearity_output(&m2, u), &x2);
        let sse: f64 = lin
            .iter()
            .zip(y)
            .zip(skip)
            .filter(|(_, s)| !**s)
            .map(|((l, y), _)| (y - g.as_ref().map_or(*l, |g| g.eval(*l))).powi(2))
            .sum();
        sse.is_finite().then_some((sse, m2, x2, g))
    };
    let start = eval(&a0)?;
    let mut simplex: Vec<(Vec<f64>, f64)> = vec![(a0.clone(), start.0)];
    for k in 0..n {
        let mut v = a0.clone();
        v[k] += 2e-3 * a0[k].abs().max(0.1);
        let f = eval(&v).map_or(f64::INFINITY, |e| e.0);
        simplex.push((v, f));
    }
    for _ in 0..40 * n {
        simplex.sort_by(|a, b| a.1.total_cmp(&b.1));
        let (best, worst) = (simplex[0].1, simplex[n].1);
        if worst.is_finite() && worst - best <= 1e-7 * best.max(1e-300) {
            break;
        }
        let centroid: Vec<f64> = (0..n)
            .map(|k| simplex[..n].iter().map(|v| v.0[k]).sum::<f64>() / n as f64)
            .collect();
        let along = |t: f64| -> Vec<f64> {
            (0..n)
                .map(|k| centroid[k] + t * (simplex[n].0[k] - centroid[k]))
                .collect()
        };
        let score = |v: &[f64]| eval(v).map_or(f64::INFINITY, |e| e.0);
        let r = along(-1.0);
        let fr = score(&r);
        if fr < simplex[0].1 {
            let e = along(-2.0);
            let fe = score(&e);
            simplex[n] = if fe < fr { (e, fe) } else { (r, fr) };
        } else if fr < simplex[n - 1].1 {
            simplex[n] = (r, fr);
        } else {
            let c = along(0.5);
            let fc = score(&c);
            if fc < simplex[n].1 {
                simplex[n] = (c, fc);
            } else {
                let b = simplex[0].0.clone();
                for v in simplex.iter_mut().skip(1) {
                    let s: Vec<f64> = v.0.iter().zip(&b).map(|(x, b)| b + 0.5 * (x - b)).collect();
                    let f = score(&s);
                    *v = (s, f);
                }
            }
        }
    }
    simplex.sort_by(|a, b| a.1.total_cmp(&b.1));
    if simplex[0].1.partial_cmp(&start.0) != Some(std::cmp::Ordering::Less) {
        return None;
    }
    let (_, m2, x2, g) = eval(&simplex[0].0)?;
    Some((m2, x2, g))
}

/// Spectral radius of the model's `A`.
pub fn spectral_radius(m: &HostModel) -> f64 {
    m.poles()
        .iter()
        .map(|(r, i)| r.hypot(*i))
        .fold(0.0, f64::max)
}

/// Flags isolated outliers of a residual: the residual minus its running median (window 7) is
/// beyond `k` robust standard deviations (1.4826 MAD), in runs of at most two samples.
pub fn detect_outliers(r: &[f64], k: f64) -> Vec<bool> {
    let n = r.len();
    if n < 8 {
        return vec![false; n];
    }
    let med = running_median(r, 7);
    let s: Vec<f64> = r.iter().zip(&med).map(|(a, b)| a - b).collect();
    let sigma = mad_sigma(&s).max(1e-3 * rms(&s)).max(1e-300);
    let mut flags: Vec<bool> = s.iter().map(|v| v.abs() > k * sigma).collect();
    let mut i = 0;
    while i < n {
        if flags[i] {
            let mut j = i;
            while j < n && flags[j] {
                j += 1;
            }
            if j - i > 2 {
                for f in &mut flags[i..j] {
                    *f = false;
                }
            }
            i = j;
        } else {
            i += 1;
        }
    }
    flags
}

/// Fits the monotone output map with `segments` segments from `x` to `y`, clipped at the
/// saturation levels; samples at a saturation level do not take part in the fit of the
/// piecewise-linear part (their value says only that the unclipped output is beyond it).
fn fit_output_map(
    x: &[f64],
    y: &[f64],
    skip: &[bool],
    segments: usize,
    sat: &Saturation,
) -> Option<OutputMap> {
    let idx: Vec<usize> = (0..x.len())
        .filter(|&i| !skip[i] && !sat.at_limit(y[i]))
        .collect();
    if idx.len() < 4 * (segments + 1) {
        return None;
    }
    let mut sorted: Vec<f64> = idx.iter().map(|&i| x[i]).collect();
    sorted.sort_by(f64::total_cmp);
    let mut knots: Vec<f64> = (0..=segments)
        .map(|k| sorted[((sorted.len() - 1) * k) / segments])
        .collect();
    knots.dedup_by(|a, b| (*a - *b).abs() <= 1e-12 * (1.0 + b.abs()));
    if knots.len() < 2 {
        return None;
    }
    let s = knots.len() - 1;
    let mut design = DMatrix::<f64>::zeros(idx.len(), s + 1);
    for (r, &i) in idx.iter().enumerate() {
        let xi = x[i];
        let j = match knots.iter().rposition(|&k| k <= xi) {
            None => 0,
            Some(j) => j.min(s - 1),
        };
        let t = (xi - knots[j]) / (knots[j + 1] - knots[j]);
        design[(r, 0)] = 1.0;
        for c in 0..j {
            design[(r, 1 + c)] = 1.0;
        }
        design[(r, 1 + j)] = t;
    }
    let target = DVector::from_iterator(idx.len(), idx.iter().map(|&i| y[i]));
    let beta = nnls(&design, &target, 1)?;
    let mut v = Vec::with_capacity(s + 1);
    let mut acc = beta[0];
    v.push(acc);
    for c in 0..s {
        acc += beta[1 + c];
        v.push(acc);
    }
    Some(OutputMap {
        x: knots,
        v,
        ceiling: sat.ceiling,
        floor: sat.floor,
    })
}

impl ExtendedModel {
    /// Output of the Hammerstein part (delay included) for an input record.
    pub fn hammerstein_output(&self, u: &[f64]) -> Vec<f64> {
        let ud = delay_input(u, self.structure.delay);
        let h = nonlinearity_output(&self.hammerstein, &ud);
        match &self.stores {
            Some(st) => st.simulate(&h).unwrap_or_else(|| vec![f64::NAN; h.len()]),
            None => linear_response(&self.hammerstein, &h, &self.x0),
        }
    }

    /// The simulated output (deterministic part, no measured output used).
    pub fn simulate(&self, u: &[f64], time: &[f64]) -> Vec<f64> {
        let lin = self.hammerstein_output(u);
        lin.iter()
            .zip(time)
            .map(|(&l, &t)| {
                let g = self.output_map.as_ref().map_or(l, |m| m.eval(l));
                g + self.additive.eval(t)
            })
            .collect()
    }

    /// One-step-ahead prediction: the simulation plus the noise model's prediction of the
    /// residual from the past residuals (the simulation when there is no noise model).
    /// Residuals of samples flagged as outliers are replaced by their own prediction.
    pub fn predict(&self, u: &[f64], y: &[f64], time: &[f64]) -> Vec<f64> {
        let sim = self.simulate(u, time);
        let Some(ar) = &self.noise else { return sim };
        let flags = if self.structure.robust {
            let r: Vec<f64> = y.iter().zip(&sim).map(|(a, b)| a - b).collect();
            detect_outliers(&r, self.outlier_k)
        } else {
            vec![false; y.len()]
        };
        let mut r = vec![0.0; y.len()];
        let mut out = Vec::with_capacity(y.len());
        for t in 0..y.len() {
            let pr: f64 =
                ar.a.iter()
                    .enumerate()
                    .filter(|(k, _)| t > *k)
                    .map(|(k, a)| a * r[t - 1 - k])
                    .sum();
            out.push(sim[t] + pr);
            r[t] = if flags[t] { pr } else { y[t] - sim[t] };
        }
        out
    }
}

/// Fits a structure on a record.
pub fn fit_structure(
    s: &Structure,
    rec: &Record,
    opts: &FitOptions,
) -> Result<ExtendedModel, DiagnoseError> {
    fit_structure_impl(s, rec, opts, None)
}

/// [`fit_structure`] for a fold of the cross-validation: `fit_part` is `whole` without the
/// samples `block`, joined at the gap. The linear part is fitted on `fit_part`; the
/// level-dependent stores, whose simulation error a join would corrupt, on the simulation of
/// `whole` with the block's samples left out of the error (the input is known throughout).
pub fn fit_structure_fold(
    s: &Structure,
    fit_part: &Record,
    opts: &FitOptions,
    whole: &Record,
    block: Range<usize>,
) -> Result<ExtendedModel, DiagnoseError> {
    fit_structure_impl(s, fit_part, opts, Some((whole, block)))
}

/// Fits level-dependent stores to a fitted model ([`Dynamics::Stores`]): started from its
/// linear part, on the simulation error of `rec` without the `skip` samples, the borders
/// refitted with them, the output map and the additive terms held.
fn fit_stores(
    model: &mut ExtendedModel,
    rec: &Record,
    skip: &[bool],
    opts: &FitOptions,
    class: StoresClass,
) -> Result<(), DiagnoseError> {
    let ud = delay_input(&rec.u, model.structure.delay);
    let h = nonlinearity_output(&model.hammerstein, &ud);
    let target: Vec<f64> = rec
        .y
        .iter()
        .zip(&rec.time)
        .map(|(y, &t)| y - model.additive.eval(t))
        .collect();
    let data = DynamicsFit {
        h: &h,
        y: &target,
        skip,
        map: model.output_map.as_ref(),
        fit_x0: true,
        radius_limit: 1.0,
        iterations: stores::ITERATIONS,
        borders: Some(Borders {
            u: &ud,
            shared: opts.identify.static_nonlinearity,
        }),
    };
    let (st, hm) = stores::fit(&model.hammerstein, &model.x0, &data, class)
        .map_err(DiagnoseError::Dynamics)?;
    model.hammerstein = hm;
    model.stores = Some(st);
    Ok(())
}

fn fit_structure_impl(
    s: &Structure,
    rec: &Record,
    opts: &FitOptions,
    held: Option<(&Record, Range<usize>)>,
) -> Result<ExtendedModel, DiagnoseError> {
    // Stores start from the linear part refined on the simulation error: the subspace
    // estimate of a slow, well-damped plant can put a lightly damped complex pair where the
    // plant has two real poles.
    let refined;
    let opts = if s.dynamics.stores().is_some() && !opts.refine_poles {
        refined = FitOptions {
            refine_poles: true,
            ..opts.clone()
        };
        &refined
    } else {
        opts
    };
    let n = rec.len();
    let ud = delay_input(&rec.u, s.delay);
    let mut idopts = opts.identify.clone();
    // The subspace estimate is only the start: the poles are refined on the simulation error
    // below and a model too slow for the record is refused there, so a slow plant's pole that
    // the subspace step puts just outside the unit circle is taken here.
    idopts.poles = hsid::Poles::Any;
    if s.order.is_some() {
        idopts.order = s.order;
    }
    if let Some(h) = s.horizon {
        idopts.f = h;
        idopts.p = h;
    }
    let mut additive = Additive {
        trend: vec![0.0; s.trend_degree.map_or(0, |d| d + 1)],
        frequencies: s.frequencies.clone(),
        sin_cos: vec![(0.0, 0.0); s.frequencies.len()],
        center: opts.time_center,
        scale: opts.time_scale.max(1.0),
    };
    let mut map: Option<OutputMap> = None;
    let mut flags = vec![false; n];
    let mut lin_prev: Option<Vec<f64>> = None;
    let rounds = s.rounds().min(opts.rounds.max(1));
    let mut last: Option<(HostModel, Vec<f64>)> = None;
    let mut best_round: Option<(f64, HostModel, Vec<f64>, Option<OutputMap>)> = None;
    for _ in 0..rounds {
        let add: Vec<f64> = rec.time.iter().map(|&t| additive.eval(t)).collect();
        let mut target: Vec<f64> = rec.y.iter().zip(&add).map(|(y, a)| y - a).collect();
        // Samples whose target is imputed from the previous iterate: outliers, and outputs on a
        // flat part of the output map. The subspace step needs every sample (imputed); the
        // least-squares refit leaves them out.
        let mut imputed = flags.clone();
        if let Some(lp) = &lin_prev {
            if let Some(g) = &map {
                let min_slope = 0.1 * g.mean_slope().max(0.0);
                for ((tv, &l), im) in target.iter_mut().zip(lp).zip(imputed.iter_mut()) {
                    match g.invert(*tv, min_slope).filter(|x| x.is_finite()) {
                        Some(x) => *tv = x,
                        None => {
                            *tv = l;
                            *im = true;
                        }
                    }
                }
            }
            for (i, &f) in flags.iter().enumerate() {
                if f {
                    target[i] = lp[i];
                }
            }
        }
        let m = identify(&ud, &target, &idopts).map_err(DiagnoseError::Identify)?;
        let refit = if opts.refit {
            refit_borders(
                &m,
                &ud,
                &target,
                &imputed,
                opts.initial,
                idopts.static_nonlinearity,
            )
        } else {
            None
        };
        let (m, x0) = match refit {
            Some(r) => r,
            None => {
                let h = nonlinearity_output(&m, &ud);
                let x0 = match opts.initial {
                    InitialState::Rest => rest_state(&m),
                    InitialState::Estimated => estimate_x0(&m, &h, &target, &imputed),
                };
                (m, x0)
            }
        };
        let minus_add: Vec<f64> = rec.y.iter().zip(&add).map(|(y, a)| y - a).collect();
        let (m, x0) = if opts.refit {
            let (m2, x2, g) = refine_linear(
                &m,
                &x0,
                &ud,
                &minus_add,
                &flags,
                s.output_map_segments,
                &opts.saturation,
                opts.initial,
                idopts.static_nonlinearity,
            );
            if g.is_some() {
                map = g;
            }
            (m2, x2)
        } else {
            (m, x0)
        };
        let (m, x0) = if opts.refine_poles && s.output_map_segments.is_none() {
            refine_poles(
                &m,
                &x0,
                &ud,
                &minus_add,
                &flags,
                opts.initial,
                idopts.static_nonlinearity,
            )
            .unwrap_or((m, x0))
        } else if opts.refine_poles && opts.refit {
            match refine_poles_mapped(
                &m,
                &x0,
                &ud,
                &minus_add,
                &flags,
                s.output_map_segments,
                &opts.saturation,
                opts.initial,
                idopts.static_nonlinearity,
            ) {
                Some((m2, x2, g)) => {
                    if g.is_some() {
                        map = g;
                    }
                    (m2, x2)
                }
                None => (m, x0),
            }
        } else {
            (m, x0)
        };
        let h = nonlinearity_output(&m, &ud);
        let lin = linear_response(&m, &h, &x0);
        let out: Vec<f64> = lin
            .iter()
            .map(|&l| map.as_ref().map_or(l, |g| g.eval(l)))
            .collect();
        let r: Vec<f64> = rec.y.iter().zip(&out).map(|(y, o)| y - o).collect();
        // With an output map, a later round (identified on the inverted output) is kept only if
        // it fits better: the inversion can mislead the subspace step.
        if s.output_map_segments.is_some() && !s.robust {
            let sse: f64 = r
                .iter()
                .zip(&rec.time)
                .map(|(v, &t)| (v - additive.eval(t)).powi(2))
                .sum();
            if let Some((best_sse, bm, bx, bg)) = &best_round
                && sse.partial_cmp(best_sse) != Some(std::cmp::Ordering::Less)
            {
                let h = nonlinearity_output(bm, &ud);
                lin_prev = Some(linear_response(bm, &h, bx));
                last = Some((bm.clone(), bx.clone()));
                map = bg.clone();
                continue;
            }
            best_round = Some((sse, m.clone(), x0.clone(), map.clone()));
        }
        additive.fit(&r, &rec.time, &flags);
        if s.robust {
            let res: Vec<f64> = r
                .iter()
                .zip(&rec.time)
                .map(|(v, &t)| v - additive.eval(t))
                .collect();
            flags = detect_outliers(&res, opts.outlier_k);
        }
        lin_prev = Some(lin);
        last = Some((m, x0));
    }
    let Some((hammerstein, x0)) = last else {
        return Err(DiagnoseError::TooShort {
            samples: n,
            need: 1,
        });
    };
    let mut model = ExtendedModel {
        structure: s.clone(),
        hammerstein,
        x0,
        output_map: map,
        additive,
        noise: None,
        outlier_k: opts.outlier_k,
        flagged: flags.iter().filter(|&&f| f).count(),
        stores: None,
    };
    if let Some(class) = s.dynamics.stores() {
        match held {
            Some((whole, block)) => {
                let skip: Vec<bool> = (0..whole.len()).map(|t| block.contains(&t)).collect();
                fit_stores(&mut model, whole, &skip, opts, class)?;
            }
            None => fit_stores(&mut model, rec, &flags, opts, class)?,
        }
    }
    if let Some(p) = s.noise_ar_order {
        let sim = model.simulate(&rec.u, &rec.time);
        let r: Vec<f64> = rec
            .y
            .iter()
            .zip(&sim)
            .zip(&flags)
            .map(|((y, s), &f)| if f { 0.0 } else { y - s })
            .collect();
        model.noise = fit_ar(&r, p);
    }
    Ok(model)
}

/// Which error a score measures.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Metric {
    /// Simulation error: the model is driven by the input only.
    Simulation,
    /// One-step-ahead prediction error (the noise model uses past measured outputs).
    Prediction,
}

/// A model's error on a scored range of a record.
#[derive(Clone, Debug, PartialEq)]
pub struct Evaluation {
    /// Model output over the whole record (simulation or prediction).
    pub output: Vec<f64>,
    /// Residual `y − output` over the scored range (0 at excluded samples).
    pub residual: Vec<f64>,
    /// Samples of the scored range excluded as outliers (robust models only).
    pub excluded: Vec<bool>,
    /// RMSE over the samples used, output units.
    pub rmse: f64,
    /// RMSE / standard deviation of the measured output over the samples used.
    pub nrmse: f64,
    /// Fit in percent, `100 (1 − NRMSE)`.
    pub fit_percent: f64,
    /// Samples used.
    pub used: usize,
}

impl Evaluation {
    /// Squared errors over the scored range (`None` at excluded samples).
    pub fn losses(&self) -> Vec<Option<f64>> {
        self.residual
            .iter()
            .zip(&self.excluded)
            .map(|(r, &e)| (!e).then_some(r * r))
            .collect()
    }
}

/// Evaluates a model on `range` of `rec`, simulating (or predicting) over the whole record.
pub fn evaluate(
    model: &ExtendedModel,
    rec: &Record,
    range: Range<usize>,
    metric: Metric,
) -> Evaluation {
    let output = match metric {
        Metric::Simulation => model.simulate(&rec.u, &rec.time),
        Metric::Prediction => model.predict(&rec.u, &rec.y, &rec.time),
    };
    let range = range.start.min(rec.len())..range.end.min(rec.len());
    let raw: Vec<f64> = range.clone().map(|t| rec.y[t] - output[t]).collect();
    let excluded = if model.structure.robust {
        detect_outliers(&raw, model.outlier_k)
    } else {
        vec![false; raw.len()]
    };
    let residual: Vec<f64> = raw
        .iter()
        .zip(&excluded)
        .map(|(&r, &e)| if e { 0.0 } else { r })
        .collect();
    let (meas, sim): (Vec<f64>, Vec<f64>) = range
        .clone()
        .zip(&excluded)
        .filter(|(_, e)| !**e)
        .map(|(t, _)| (rec.y[t], output[t]))
        .unzip();
    let f = fit(&meas, &sim);
    Evaluation {
        output,
        residual,
        excluded,
        rmse: f.rmse,
        nrmse: f.nrmse,
        fit_percent: f.fit_percent,
        used: meas.len(),
    }
}
