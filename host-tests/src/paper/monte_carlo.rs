//! The Monte Carlo of Section IV: runs of a case on threads, and its statistics against the
//! true system (pole mean and spread, Bode and border errors) for `summary.json`.

use serde::Serialize;

use super::case::{Case, ExperimentError, PaperConfig, case_system, experiment, options};
use crate::identify::{HostModel, IdentifyError, identify, interpolate};
use crate::numerics::rms_error;
use crate::refine::RefineError;

/// Statistics of one case.
#[derive(Clone, Debug, Serialize)]
pub struct CaseSummary {
    /// Case name.
    pub case: String,
    /// Runs attempted.
    pub runs: usize,
    /// Runs whose identification failed, with the reason.
    pub failures: Vec<String>,
    /// How many runs selected each order (index = order).
    pub order_counts: Vec<usize>,
    /// True poles `[re, im]`.
    pub true_poles: Vec<[f64; 2]>,
    /// Mean of the estimated pole in the upper half plane, `[re, im]` (order-2 runs).
    pub pole_mean: [f64; 2],
    /// Sample standard deviation of that pole, `[re, im]`.
    pub pole_std: [f64; 2],
    /// `|mean − true|` of that pole.
    pub pole_bias: f64,
    /// RMS error of the average border (both paths, 601-point grid) against the true paths.
    pub border_rms_of_average: f64,
    /// Median over runs of the single-run border RMS error.
    pub border_rms_single_median: f64,
    /// RMS error of the best piecewise-linear fit with the same knots (the floor).
    pub border_rms_best_pwl: f64,
    /// Largest Bode magnitude error (dB) of the average model over the frequency grid.
    pub bode_max_db_error_of_average: f64,
    /// Mean μ0 estimate and its true value.
    pub mu0_mean: f64,
    /// True μ0.
    pub mu0_true: f64,
}

/// Everything a case produced, for figures and tests.
#[derive(Clone, Debug)]
pub struct CaseResult {
    /// Which case of Section IV.
    pub case: Case,
    /// The statistics.
    pub summary: CaseSummary,
    /// Every successful model.
    pub models: Vec<HostModel>,
    /// The border grid.
    pub grid: Vec<f64>,
    /// True `P_a`, `P_d` on the grid.
    pub true_asc: Vec<f64>,
    /// True `P_d` on the grid.
    pub true_desc: Vec<f64>,
    /// Average estimated `P_a` on the grid.
    pub avg_asc: Vec<f64>,
    /// Average estimated `P_d` on the grid.
    pub avg_desc: Vec<f64>,
    /// Frequency grid (rad/sample).
    pub w: Vec<f64>,
    /// True `|G|` in dB.
    pub true_db: Vec<f64>,
    /// Average model `|G|` in dB (average of the magnitudes).
    pub avg_db: Vec<f64>,
}

fn median(mut v: Vec<f64>) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(|a, b| a.total_cmp(b));
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

/// Least-squares continuous piecewise-linear fit of `g` on the knots, evaluated on the grid.
pub fn best_pwl(knots: &[f64], grid: &[f64], g: &[f64]) -> Vec<f64> {
    let k = knots.len();
    let hat = |i: usize, u: f64| -> f64 {
        let left = if i > 0 {
            knots[i - 1]
        } else {
            f64::NEG_INFINITY
        };
        let right = if i + 1 < k {
            knots[i + 1]
        } else {
            f64::INFINITY
        };
        let c = knots[i];
        if u <= c && u >= left {
            if left.is_finite() {
                (u - left) / (c - left)
            } else {
                1.0
            }
        } else if u > c && u <= right {
            if right.is_finite() {
                (right - u) / (right - c)
            } else {
                1.0
            }
        } else {
            0.0
        }
    };
    let a = nalgebra::DMatrix::from_fn(grid.len(), k, |r, c| hat(c, grid[r]));
    let b = nalgebra::DVector::from_column_slice(g);
    let sol = a
        .clone()
        .svd(true, true)
        .solve(&b, 1e-12)
        .unwrap_or_else(|_| nalgebra::DVector::zeros(k));
    (a * sol).iter().copied().collect()
}

/// Why one run of the Monte Carlo gave no model.
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    /// The experiment could not be simulated.
    #[error(transparent)]
    Experiment(#[from] ExperimentError),
    /// The subspace identification failed.
    #[error(transparent)]
    Identify(#[from] IdentifyError),
    /// A method of the comparison failed.
    #[error(transparent)]
    Method(#[from] RefineError),
    /// The thread that held the run panicked.
    #[error("run {0}: the identification panicked")]
    Panicked(usize),
}

/// Runs `run(r)` for `r` in `0..runs` on up to 8 threads and returns the results in run
/// order; `tick` is called after every run (for a progress bar). A thread that panics turns
/// each run it held into an error that says so: no run is dropped.
pub fn monte_carlo<R: Send>(
    runs: usize,
    run: impl Fn(usize) -> Result<R, RunError> + Sync,
    tick: &(dyn Fn() + Sync),
) -> Vec<Result<R, RunError>> {
    let all: Vec<usize> = (0..runs).collect();
    let threads = std::thread::available_parallelism()
        .map_or(1, |n| n.get())
        .min(8);
    let chunk = all.len().div_ceil(threads).max(1);
    let run = &run;
    std::thread::scope(|s| {
        let handles: Vec<_> = all
            .chunks(chunk)
            .map(|rs| {
                let handle = s.spawn(move || {
                    rs.iter()
                        .map(|&r| {
                            let out = run(r);
                            tick();
                            out
                        })
                        .collect::<Vec<_>>()
                });
                (rs, handle)
            })
            .collect();
        handles
            .into_iter()
            .flat_map(|(rs, h)| {
                h.join()
                    .unwrap_or_else(|_| rs.iter().map(|&r| Err(RunError::Panicked(r))).collect())
            })
            .collect()
    })
}

/// Runs one case; `tick` is called after every run (for a progress bar).
pub fn run_case(case: Case, cfg: &PaperConfig, tick: &(dyn Fn() + Sync)) -> CaseResult {
    let opts = options(cfg);
    let results = monte_carlo(
        cfg.runs,
        |r| {
            let e = experiment(case, cfg, r)?;
            Ok(identify(&e.u, &e.y, &opts)?)
        },
        tick,
    );
    let mut models = Vec::new();
    let mut failures = Vec::new();
    for (r, res) in results.into_iter().enumerate() {
        match res {
            Ok(m) => models.push(m),
            Err(e) => failures.push(format!("run {r}: {e}")),
        }
    }
    summarize(case, cfg, models, failures)
}

/// The statistics and figure data of a case from its identified models (and the failures, as
/// `run r: reason`): what [`run_case`] reports, reusable for models from any method.
pub fn summarize(
    case: Case,
    cfg: &PaperConfig,
    models: Vec<HostModel>,
    failures: Vec<String>,
) -> CaseResult {
    let opts = options(cfg);
    let (_, paths, plant, _) = case_system(case);
    let mut true_poles: Vec<[f64; 2]> = plant
        .poles()
        .unwrap_or_default()
        .into_iter()
        .map(|(r, i)| [r, i])
        .collect();
    true_poles.sort_by(|a, b| b[1].total_cmp(&a[1]));
    let true_upper = true_poles.first().copied().unwrap_or([f64::NAN; 2]);

    let mut order_counts = vec![0usize; cfg.f + 1];
    let mut upper = Vec::new();
    for m in &models {
        if let Some(c) = order_counts.get_mut(m.order) {
            *c += 1;
        }
        if m.order == 2 {
            let p = m.poles();
            if let Some(&(re, im)) = p.iter().max_by(|a, b| a.1.total_cmp(&b.1)) {
                upper.push((re, im));
            }
        }
    }
    let n = upper.len() as f64;
    let mean = [
        upper.iter().map(|p| p.0).sum::<f64>() / n,
        upper.iter().map(|p| p.1).sum::<f64>() / n,
    ];
    let std = [
        (upper.iter().map(|p| (p.0 - mean[0]).powi(2)).sum::<f64>() / (n - 1.0)).sqrt(),
        (upper.iter().map(|p| (p.1 - mean[1]).powi(2)).sum::<f64>() / (n - 1.0)).sqrt(),
    ];

    let grid: Vec<f64> = (0..=600)
        .map(|i| cfg.u_min + (cfg.u_max - cfg.u_min) * i as f64 / 600.0)
        .collect();
    let true_asc: Vec<f64> = grid.iter().map(|&u| paths.asc(u)).collect();
    let true_desc: Vec<f64> = grid.iter().map(|&u| paths.desc(u)).collect();
    let mut avg_asc = vec![0.0; grid.len()];
    let mut avg_desc = vec![0.0; grid.len()];
    let mut single = Vec::new();
    for m in &models {
        let a: Vec<f64> = grid.iter().map(|&u| m.border_asc_at(u)).collect();
        let d: Vec<f64> = grid.iter().map(|&u| m.border_desc_at(u)).collect();
        for (s, v) in avg_asc.iter_mut().zip(&a) {
            *s += v / models.len() as f64;
        }
        for (s, v) in avg_desc.iter_mut().zip(&d) {
            *s += v / models.len() as f64;
        }
        let both = [a, d].concat();
        single.push(rms_error(
            &both,
            &[true_asc.clone(), true_desc.clone()].concat(),
        ));
    }
    let truth = [true_asc.clone(), true_desc.clone()].concat();
    let border_rms_of_average = rms_error(&[avg_asc.clone(), avg_desc.clone()].concat(), &truth);
    let knots = opts.knots_asc.clone();
    let best = [
        best_pwl(&knots, &grid, &true_asc),
        best_pwl(&opts.knots_desc, &grid, &true_desc),
    ]
    .concat();
    let border_rms_best_pwl = rms_error(&best, &truth);

    let w: Vec<f64> = (0..=400)
        .map(|i| 10f64.powf(-3.0 + (std::f64::consts::PI.log10() + 3.0) * i as f64 / 400.0))
        .collect();
    let true_db: Vec<f64> = w
        .iter()
        .map(|&x| {
            let (re, im) = plant.freq_response(x);
            10.0 * (re * re + im * im).log10()
        })
        .collect();
    let avg_db: Vec<f64> = w
        .iter()
        .map(|&x| {
            let s: f64 = models
                .iter()
                .map(|m| {
                    let (re, im) = m.freq_response(x);
                    (re * re + im * im).sqrt()
                })
                .sum();
            20.0 * (s / models.len() as f64).log10()
        })
        .collect();
    let bode_max = true_db
        .iter()
        .zip(&avg_db)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    let mu0_true = paths.asc(cfg.u_min);
    let mu0_mean = models.iter().map(|m| m.mu0).sum::<f64>() / models.len() as f64;

    CaseResult {
        case,
        summary: CaseSummary {
            case: case.name().to_string(),
            runs: cfg.runs,
            failures,
            order_counts,
            true_poles,
            pole_mean: mean,
            pole_std: std,
            pole_bias: ((mean[0] - true_upper[0]).powi(2) + (mean[1] - true_upper[1]).powi(2))
                .sqrt(),
            border_rms_of_average,
            border_rms_single_median: median(single),
            border_rms_best_pwl,
            bode_max_db_error_of_average: bode_max,
            mu0_mean,
            mu0_true,
        },
        models,
        grid,
        true_asc,
        true_desc,
        avg_asc,
        avg_desc,
        w,
        true_db,
        avg_db,
    }
}

/// Interpolation helper re-exported for tests of the figures' data.
pub fn border_at(knots: &[f64], values: &[f64], u: f64) -> f64 {
    interpolate(knots, values, u)
}
