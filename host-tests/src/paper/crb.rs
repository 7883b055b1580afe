//! The Cramér–Rao bound for the pole estimates on the paper's example (item 8 of the issue).
//!
//! For Gaussian innovations the bound of an unbiased estimator of `θ` in the model structure of
//! the refinement ([`pem`](crate::refine::pem): plant `B/F` of order 2 with `G(1) = 1`, μ0 and the
//! border values on the knots, noise ARMA(1, 1), plant at rest after the hold) is
//! `σ_e² E[JᵀJ]⁻¹`, `J = ∂ε/∂θ` evaluated at the *true* system and the *true* noise model
//! `G_v(q) = (1 + 0.5q⁻¹)/(1 − 0.85q⁻¹)`. It is also the asymptotic covariance of the
//! prediction-error estimate, which is therefore efficient. `E[JᵀJ]` is the average over the
//! Monte Carlo's own experiments (same seeds), and the bound is mapped onto the poles like the
//! estimate's covariance ([`uncertainty::pole_std`](crate::refine::uncertainty::pole_std)).
//!
//! Without a hold (`cfg.hold == 0`) the structure estimates the initial state, whose true
//! value (the simulator starts the plant from zero) is included in the true parameters.
//!
//! The true borders are not piecewise linear; the bound is taken at their values on the knots
//! (the gradients with respect to the plant use the model's `H`, which differs from the true
//! `H` by the best-fit error, a few hundredths, a negligible change of the information).

use nalgebra::DMatrix;

use super::case::{Case, PaperConfig, case_system, experiment, options};
use crate::refine::RefineError;
use crate::refine::pem::{BURN_IN, PemInitialState, PemProblem, PemStructure};
use crate::refine::uncertainty::{PoleStd, pole_std};
use crate::sim::{paper_noise_model, paper_plant, variance};

/// The bound on the paper's example.
#[derive(Clone, Debug, PartialEq)]
pub struct Crb {
    /// The true upper pole with the bound on the standard deviations of its real and
    /// imaginary parts.
    pub pole: PoleStd,
    /// Bound on the standard deviation of μ0 and the border values (`β` order: μ0, the
    /// ascending values, the descending values).
    pub border_std: Vec<f64>,
    /// Innovation variance `σ_e²` of the experiments.
    pub sigma2: f64,
    /// Experiments averaged.
    pub runs: usize,
    /// Parameters in the structure.
    pub parameters: usize,
}

impl Crb {
    /// `√(σ_re² + σ_im²)` of the bound.
    pub fn pole_std_norm(&self) -> f64 {
        self.pole.std.0.hypot(self.pole.std.1)
    }
}

/// The bound of the paper's example for `case` with the Monte Carlo settings `cfg`, averaging
/// the information over runs `0 … runs − 1`.
pub fn paper_crb(
    case: Case,
    cfg: &PaperConfig,
    runs: usize,
    feedthrough: bool,
) -> Result<Crb, RefineError> {
    let opts = options(cfg);
    let (_, paths, _, _) = case_system(case);
    let plant = paper_plant();
    let noise = paper_noise_model();
    let den = plant.den().to_vec();
    let num = plant.num().to_vec();
    let n = den.len() - 1;
    let energy = noise.impulse_energy();
    let mut info: Option<DMatrix<f64>> = None;
    let mut sigma2_sum = 0.0;
    let mut used = 0usize;
    let mut params = 0usize;
    let mut b0 = 0usize;
    for r in 0..runs.max(1) {
        let e = experiment(case, cfg, r).map_err(|e| RefineError::Identify(e.to_string()))?;
        let problem = PemProblem::new(
            &e.u,
            &e.y,
            &opts.knots_asc,
            &opts.knots_desc,
            PemStructure {
                n,
                nv: 1,
                initial: if cfg.hold > 0 {
                    PemInitialState::Rest
                } else {
                    PemInitialState::Estimate
                },
                start: cfg.settle.min(cfg.hold),
                feedthrough,
                shared: false,
                burn: BURN_IN,
            },
        )?;
        let l = problem.layout();
        params = l.len();
        b0 = l.beta().start;
        let mut th = vec![0.0; l.len()];
        th[l.f()].copy_from_slice(&den[1..]);
        for (k, i) in l.b().enumerate() {
            th[i] = num.get(k + 1).copied().unwrap_or(0.0);
        }
        let mut beta = vec![paths.asc(cfg.u_min)];
        beta.extend(opts.knots_asc.iter().skip(1).map(|&u| paths.asc(u)));
        beta.extend(opts.knots_desc.iter().skip(1).map(|&u| paths.desc(u)));
        th[l.beta()].copy_from_slice(&beta);
        th[l.nd().start] = noise.den()[1];
        th[l.nc().start] = noise.num()[1];
        if l.init {
            // The simulated plant starts from zero state, not at rest at μ0: the free response
            // is −μ0 (1 − G) 1(t) = −μ0 (F − B)/((1 − q⁻¹) F) δ(t), so I = −μ0 (F − B)/(1 − q⁻¹).
            let p = l.polynomials(&th);
            let mut q = 0.0;
            for (k, i) in l.iota().enumerate() {
                q += p.f[k] - p.b[k];
                th[i] = -beta[0] * q;
            }
        }
        let ev = problem.evaluate(&th);
        let jtj = ev.jtj;
        info = Some(match info {
            Some(acc) => acc + jtj,
            None => jtj,
        });
        let end = (cfg.hold + cfg.j + cfg.f + cfg.p - 1).min(e.y_clean.len());
        let var_y = variance(&e.y_clean[cfg.hold.min(end)..end]);
        sigma2_sum += var_y / (10f64.powf(cfg.snr_db / 10.0) * energy);
        used += 1;
    }
    let info = info.ok_or(RefineError::Singular("no experiment"))? / used as f64;
    let sigma2 = sigma2_sum / used as f64;
    let d = info.nrows();
    let s: Vec<f64> = (0..d)
        .map(|i| 1.0 / info[(i, i)].max(1e-300).sqrt())
        .collect();
    let scaled = DMatrix::from_fn(d, d, |i, j| info[(i, j)] * s[i] * s[j]);
    let inv = scaled
        .cholesky()
        .ok_or(RefineError::Singular("Fisher information"))?
        .inverse();
    let cov = DMatrix::from_fn(d, d, |i, j| sigma2 * inv[(i, j)] * s[i] * s[j]);
    let cov_f = cov.view((0, 0), (n, n)).into_owned();
    let pole = pole_std(&den, &cov_f)
        .into_iter()
        .max_by(|a, b| a.pole.1.total_cmp(&b.pole.1))
        .ok_or(RefineError::Singular("true poles"))?;
    let channels = opts.knots_asc.len() + opts.knots_desc.len() - 1;
    let border_std = (0..channels)
        .map(|k| cov[(b0 + k, b0 + k)].max(0.0).sqrt())
        .collect();
    Ok(Crb {
        pole,
        border_std,
        sigma2,
        runs: used,
        parameters: params,
    })
}
