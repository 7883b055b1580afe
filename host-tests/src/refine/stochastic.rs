//! The stochastic part (Remark 6): a noise model `v(t) = C(q)/D(q) e(t)`, the innovation form
//! `x(t+1) = A x(t) + B H[u(t)] + K e(t)`, `y(t) = C x(t) + D H[u(t)] + e(t)` with `σ_e²`, and
//! one-step-ahead prediction.
//!
//! For a subspace model the noise model is fitted to the simulation residual
//! `r(t) = y(t) − ŷ_sim(t)` by the Hannan–Rissanen two-stage least squares (a long AR model
//! gives innovation estimates, then an ARMA regression on past residuals and past
//! innovations), with the order chosen by BIC unless given. The innovation form stacks the
//! plant state and the noise state (observer form of `C/D`): `A = diag(A_p, A_v)`,
//! `B = [B_p; 0]`, `C = [C_p, C_v]`, `K = [0; K_v]`. This is the minimal innovation form of
//! `y = G H + (C/D) e` whenever the noise poles differ from the plant poles — the case of the
//! paper, whose noise pole 0.85 is not a plant pole (an innovation form of the plant's order
//! alone would force the noise to share the plant's poles and bias the predictor).

use std::path::{Path, PathBuf};

use nalgebra::{DMatrix, DVector};
use serde::{Deserialize, Serialize};

use hsid::Direction;

use super::RefineError;
use super::poly::{is_stable, observer_form, stabilise};
use super::signal::filter;
use crate::identify::HostModel;
use crate::numerics::ar::fit_ar;
use crate::numerics::direction::directions;
use crate::numerics::lstsq::{Scaling, normal_by_rows, solve_normal};
use crate::numerics::select::{Criterion, best};
use crate::report::UndefinedFit;

/// The largest noise model file read, in bytes (1 MiB; a noise model of the largest order is
/// a few kilobytes): a larger file is refused before it is read.
pub const MAX_NOISE_FILE_BYTES: u64 = 1 << 20;

/// Why a noise model file could not be written or read.
#[derive(Debug, thiserror::Error)]
pub enum NoiseFileError {
    /// The model could not be put in JSON.
    #[error("{0}")]
    Encode(#[source] serde_json::Error),
    /// The file could not be written.
    #[error("{path}: {source}")]
    Write {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// The file could not be read.
    #[error("{path}: {source}")]
    Read {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// The file is not a noise model's JSON.
    #[error("{path}: {source}")]
    Json {
        /// The file.
        path: PathBuf,
        /// The parser's error.
        source: serde_json::Error,
    },
    /// `c` or `d` not monic or not finite, or `sigma2` not finite and non-negative.
    #[error("{path}: a noise model needs monic finite c and d and a finite sigma2 >= 0")]
    Invalid {
        /// The file.
        path: PathBuf,
    },
    /// The numerator `c` has a root on or outside the unit circle.
    #[error(
        "{path}: the noise numerator c has a root on or outside the unit circle (unstable predictor)"
    )]
    UnstablePredictor {
        /// The file.
        path: PathBuf,
    },
}

/// An ARMA noise model `v(t) = C(q)/D(q) e(t)`, `e` white with variance `sigma2`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct NoiseModel {
    /// Numerator `[1, c₁, …]` (monic, roots inside the unit circle).
    pub c: Vec<f64>,
    /// Denominator `[1, d₁, …]` (monic).
    pub d: Vec<f64>,
    /// Innovation variance `σ_e²`.
    pub sigma2: f64,
}

impl NoiseModel {
    /// White noise of variance `sigma2` (order 0).
    pub fn white(sigma2: f64) -> Self {
        Self {
            c: vec![1.0],
            d: vec![1.0],
            sigma2,
        }
    }

    /// Order (`max(deg C, deg D)`).
    pub fn order(&self) -> usize {
        self.c.len().max(self.d.len()).saturating_sub(1)
    }

    /// The innovations `ε = (D/C) v` from zero initial state.
    pub fn whiten(&self, v: &[f64]) -> Vec<f64> {
        filter(&self.d, &self.c, v)
    }

    /// One-step-ahead prediction of `y` by a model whose simulation is `sim` and whose
    /// residual `v = y − sim` this noise model describes (`v = (C/D) e`): `sim + v − e`, the
    /// residual's own prediction from its past added to the simulation. For a model that is
    /// not `G` alone (an element with memory, friction), where the innovation form does not
    /// apply.
    pub fn predict_around(&self, sim: &[f64], y: &[f64]) -> Vec<f64> {
        let v: Vec<f64> = y.iter().zip(sim).map(|(y, s)| y - s).collect();
        let e = self.whiten(&v);
        sim.iter()
            .zip(v.iter().zip(&e))
            .map(|(s, (v, e))| s + v - e)
            .collect()
    }

    /// The noise part of the innovation form in observer form: `(A_v, K_v, C_v)` with
    /// `C(q)/D(q) = 1 + C_v (qI − A_v)⁻¹ K_v`.
    pub(crate) fn state_space(&self) -> (DMatrix<f64>, Vec<f64>, Vec<f64>) {
        let n = self.order();
        let mut c = self.c.clone();
        c.resize(n + 1, 0.0);
        let mut d = self.d.clone();
        d.resize(n + 1, 0.0);
        let (a, k, cv, _) = observer_form(&c, &d);
        (a, k, cv)
    }

    /// Writes the noise model as JSON (the file `hsid validate --noise` reads).
    pub fn save(&self, path: &Path) -> Result<(), NoiseFileError> {
        let text = serde_json::to_string_pretty(self).map_err(NoiseFileError::Encode)?;
        crate::io::write_atomic(path, text + "\n").map_err(|source| NoiseFileError::Write {
            path: path.to_path_buf(),
            source,
        })
    }

    /// Reads a noise model JSON written by [`save`](Self::save) and checks it.
    pub fn load(path: &Path) -> Result<Self, NoiseFileError> {
        let text = crate::io::read_text_bounded(path, MAX_NOISE_FILE_BYTES).map_err(|source| {
            NoiseFileError::Read {
                path: path.to_path_buf(),
                source,
            }
        })?;
        let m: NoiseModel = serde_json::from_str(&text).map_err(|source| NoiseFileError::Json {
            path: path.to_path_buf(),
            source,
        })?;
        let ok = m.c.first() == Some(&1.0)
            && m.d.first() == Some(&1.0)
            && m.c.iter().chain(&m.d).all(|v| v.is_finite())
            && m.sigma2.is_finite()
            && m.sigma2 >= 0.0;
        if !ok {
            return Err(NoiseFileError::Invalid {
                path: path.to_path_buf(),
            });
        }
        if !is_stable(&m.c, 1.0) {
            return Err(NoiseFileError::UnstablePredictor {
                path: path.to_path_buf(),
            });
        }
        Ok(m)
    }
}

/// How the noise model order is chosen.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NoiseOrder {
    /// ARMA(k, k) with the given `k` (0: white noise).
    Fixed(usize),
    /// ARMA(k, k) for `k = 0 … max`, the one with the smallest BIC.
    Auto {
        /// Largest order tried.
        max: usize,
    },
}

impl Default for NoiseOrder {
    fn default() -> Self {
        NoiseOrder::Auto { max: 2 }
    }
}

/// Mean of the squares.
fn mean_sq(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>() / v.len().max(1) as f64
}

/// Hannan–Rissanen fit of an ARMA(k, k) model to `r` (zero-mean residual).
pub fn hannan_rissanen(r: &[f64], k: usize) -> Result<NoiseModel, RefineError> {
    let n = r.len();
    if r.iter().any(|v| !v.is_finite()) {
        return Err(RefineError::NonFinite);
    }
    if k == 0 {
        return Ok(NoiseModel::white(mean_sq(r)));
    }
    let l = (n / 20).clamp(2 * k + 2, 30);
    if n < 4 * (l + 2 * k) {
        return Err(RefineError::TooFewSamples {
            have: n,
            need: 4 * (l + 2 * k),
        });
    }
    // Stage 1: long AR(l) → innovation estimates.
    let e = fit_ar(r, l)
        .ok_or(RefineError::Singular("long AR model of the residual"))?
        .innovations(r);
    // Stage 2: r(t) = −Σ d_i r(t−i) + Σ c_i ê(t−i) + e(t).
    let s = l + k;
    let rows = n - s;
    let (g, b) = normal_by_rows(rows, 2 * k, |t, x| {
        let tt = t + s;
        for (j, xj) in x.iter_mut().enumerate() {
            *xj = if j < k {
                -r[tt - 1 - j]
            } else {
                e[tt - 1 - (j - k)]
            };
        }
        r[tt]
    });
    let th = solve_normal(&g, &b, Scaling::None)
        .ok_or(RefineError::Singular("ARMA regression of the residual"))?;
    let mut d = vec![1.0];
    d.extend(th.iter().take(k));
    let mut c = vec![1.0];
    c.extend(th.iter().skip(k).take(k));
    let c = stabilise(&c, 0.99)?;
    let d = stabilise(&d, 0.999)?;
    let mut m = NoiseModel { c, d, sigma2: 0.0 };
    let eps = m.whiten(r);
    m.sigma2 = mean_sq(&eps[l.min(n)..]);
    Ok(m)
}

/// A fitted noise model with the order chosen and the BIC of every order tried.
#[derive(Clone, Debug, PartialEq)]
pub struct NoiseFit {
    /// The model.
    pub model: NoiseModel,
    /// `(order, BIC)` of every candidate.
    pub bic: Vec<(usize, f64)>,
}

/// Fits the noise model to a residual, choosing the order by BIC when asked.
pub fn fit_noise(r: &[f64], order: NoiseOrder) -> Result<NoiseFit, RefineError> {
    let orders: Vec<usize> = match order {
        NoiseOrder::Fixed(k) => vec![k],
        NoiseOrder::Auto { max } => (0..=max).collect(),
    };
    let n = r.len() as f64;
    let mut models = Vec::new();
    let mut bic = Vec::new();
    for k in orders {
        let m = match hannan_rissanen(r, k) {
            Ok(m) => m,
            Err(e) if matches!(order, NoiseOrder::Fixed(_)) => return Err(e),
            Err(_) => continue,
        };
        bic.push((k, Criterion::Bic.score(n, m.sigma2, (2 * k) as f64)));
        models.push((k, m));
    }
    let chosen = best(&bic).ok_or(RefineError::Singular("every noise model order"))?;
    let model = models
        .into_iter()
        .find_map(|(k, m)| (k == chosen).then_some(m))
        .ok_or(RefineError::Singular("every noise model order"))?;
    Ok(NoiseFit { model, bic })
}

/// Remark 6 for a deterministic model: fits the noise model to the residual of its
/// simulation, `y − ŷ_sim`, over `y[start..]`.
pub fn estimate_noise(
    model: &HostModel,
    u: &[f64],
    y: &[f64],
    start: usize,
    order: NoiseOrder,
) -> Result<NoiseFit, RefineError> {
    if u.len() != y.len() {
        return Err(RefineError::LengthMismatch {
            u: u.len(),
            y: y.len(),
        });
    }
    let sim = model.simulate(u);
    let r: Vec<f64> = y.iter().zip(&sim).skip(start).map(|(a, b)| a - b).collect();
    fit_noise(&r, order)
}

/// The innovation form of a Hammerstein model with a noise model:
/// `x(t+1) = A x(t) + B H[u(t)] + K e(t)`, `y(t) = C x(t) + D H[u(t)] + e(t)`.
#[derive(Clone, Debug, PartialEq)]
pub struct InnovationForm {
    /// The deterministic model (plant, μ0, borders).
    pub plant: HostModel,
    /// The noise model.
    pub noise: NoiseModel,
    /// `A = diag(A_p, A_v)`.
    pub a: DMatrix<f64>,
    /// `B = [B_p; 0]`.
    pub b: Vec<f64>,
    /// `C = [C_p, C_v]`.
    pub c: Vec<f64>,
    /// `D`.
    pub d: f64,
    /// `K = [0; K_v]`.
    pub k: Vec<f64>,
    /// `σ_e²`.
    pub sigma2: f64,
    /// The input before the record, where δ starts: the plant's `u_min` (set it to the
    /// original `u_min` for a plant extended beyond its interval).
    pub u_start: f64,
}

impl InnovationForm {
    /// Stacks the plant and the noise model.
    pub fn new(plant: &HostModel, noise: &NoiseModel) -> Self {
        let n = plant.order;
        let (av, kv, cv) = noise.state_space();
        let nv = av.nrows();
        let mut a = DMatrix::zeros(n + nv, n + nv);
        a.view_mut((0, 0), (n, n)).copy_from(&plant.a);
        a.view_mut((n, n), (nv, nv)).copy_from(&av);
        let mut b = plant.b.clone();
        b.resize(n + nv, 0.0);
        let mut c = plant.c.clone();
        c.extend(&cv);
        let mut k = vec![0.0; n];
        k.extend(&kv);
        Self {
            plant: plant.clone(),
            noise: noise.clone(),
            a,
            b,
            c,
            d: plant.d,
            k,
            sigma2: noise.sigma2,
            u_start: plant.knots_asc.first().copied().unwrap_or(0.0),
        }
    }

    /// State dimension.
    pub fn order(&self) -> usize {
        self.a.nrows()
    }

    /// The nonlinearity output `H[u(t)]` of the model along `u` (δ from `u(−1) = u_start`,
    /// the plant's `u_min`).
    pub fn nonlinearity(&self, u: &[f64]) -> Vec<f64> {
        u.iter()
            .zip(directions(u, self.u_start))
            .map(|(&ut, dir)| match dir {
                Direction::Ascending => self.plant.border_asc_at(ut),
                Direction::Descending => self.plant.border_desc_at(ut),
            })
            .collect()
    }

    /// One-step-ahead predictions `ŷ(t | t−1)` by the Kalman predictor
    /// `x̂(t+1) = A x̂ + B H + K (y − C x̂ − D H)`, started with the plant at rest at μ0 and the
    /// noise state at 0 (as after the identification hold).
    pub fn predict(&self, u: &[f64], y: &[f64]) -> Vec<f64> {
        let n = self.plant.order;
        let nt = self.order();
        let h = self.nonlinearity(u);
        let ia = DMatrix::<f64>::identity(n, n) - &self.plant.a;
        let rest = ia
            .lu()
            .solve(&(DVector::from_column_slice(&self.plant.b) * self.plant.mu0))
            .unwrap_or_else(|| DVector::zeros(n));
        let mut x = DVector::zeros(nt);
        x.rows_mut(0, n).copy_from(&rest);
        let b = DVector::from_column_slice(&self.b);
        let k = DVector::from_column_slice(&self.k);
        let mut out = Vec::with_capacity(u.len());
        for (&ht, &yt) in h.iter().zip(y) {
            let yhat = self.c.iter().zip(x.iter()).map(|(c, x)| c * x).sum::<f64>() + self.d * ht;
            let e = yt - yhat;
            x = &self.a * x + &b * ht + &k * e;
            out.push(yhat);
        }
        out
    }

    /// Noise-free simulation (the deterministic part alone).
    pub fn simulate(&self, u: &[f64]) -> Vec<f64> {
        self.plant.simulate(u)
    }
}

/// One-line report of one-step-ahead predictions against measurements.
pub fn prediction_report(meas: &[f64], pred: &[f64], sigma2: f64) -> Result<String, UndefinedFit> {
    let f = crate::report::fit(meas, pred);
    if !f.nrmse.is_finite() {
        return Err(UndefinedFit {
            samples: meas.len(),
        });
    }
    Ok(format!(
        "one-step prediction fit on {} samples: RMSE {:.6}, NRMSE {:.4}, fit {:.2} % (model innovation std {:.6})",
        meas.len(),
        f.rmse,
        f.nrmse,
        f.fit_percent,
        sigma2.max(0.0).sqrt()
    ))
}

/// One line describing a noise model.
pub(crate) fn noise_text(m: &NoiseModel) -> String {
    let fmt = |v: &[f64]| {
        v.iter()
            .map(|x| format!("{x:.5}"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    format!(
        "noise model (innovation form): ARMA({0}, {0}), C = [{1}], D = [{2}], sigma_e^2 = {3:.6e}",
        m.order(),
        fmt(&m.c),
        fmt(&m.d),
        m.sigma2
    )
}

#[cfg(test)]
mod tests {
    use super::NoiseModel;

    #[test]
    fn the_prediction_around_a_simulation_adds_the_residuals_own_prediction() {
        // AR(1) residual, v(t) = 0.6 v(t − 1) + e(t): C = 1, D = 1 − 0.6 q⁻¹, so the
        // prediction is sim(t) + 0.6 v(t − 1) (and sim(0) from zero initial state).
        let nm = NoiseModel {
            c: vec![1.0],
            d: vec![1.0, -0.6],
            sigma2: 1.0,
        };
        let sim = [1.0, -2.0, 0.5, 3.0];
        let v = [0.2, -0.4, 1.0, 0.3];
        let y: Vec<f64> = sim.iter().zip(&v).map(|(s, v)| s + v).collect();
        let pred = nm.predict_around(&sim, &y);
        for t in 0..4 {
            let expected = sim[t] + if t > 0 { 0.6 * v[t - 1] } else { 0.0 };
            assert!(
                (pred[t] - expected).abs() < 1e-12,
                "t {t}: {} vs {expected}",
                pred[t]
            );
        }
    }
}
