//! Every method on the paper's Monte Carlo (same seeds for all): the table of the README,
//! the `methods` object of `summary.json` (the figures with uncertainty bands are in
//! [`method_figures`](super::method_figures)).
//!
//! Methods:
//!
//! * `pi-moesp`: the paper's weighting (eq. 11), the core as it is;
//! * `po-moesp`, `n4sid`, `cva`: the other weightings of Remark 4, from the core
//!   ([`hsid::Method`]);
//! * `pi-moesp-als`: PI-MOESP's `A`, `C`, then `B`, `D` and the borders by alternating least
//!   squares ([`bilinear`](crate::refine::bilinear), Remark 5) instead of the rank-1 split;
//! * `pem`: PI-MOESP refined by the prediction-error method ([`pem`](crate::refine::pem)) with the
//!   noise model order chosen by BIC.
//!
//! Per method the summary has the fields of the foundation's
//! [`CaseSummary`] plus `pole_std_over_crb`
//! (`‖(σ_re, σ_im)‖ / ‖(σ_re, σ_im)_CRB‖` of the upper pole), the time per identification and,
//! for `pem`, the check of its reported standard deviations against the empirical spread.

use std::time::Instant;

use serde::Serialize;

use super::case::{Case, PaperConfig, experiment, options};
use super::crb::{Crb, paper_crb};
use super::monte_carlo::{CaseResult, CaseSummary, monte_carlo, summarize};
use crate::identify::{HostModel, IdentifyOptions, identify};
use crate::refine::RefineError;
use crate::refine::bilinear::split;
use crate::refine::pem::{PemFit, PemOptions, refine};
use crate::refine::uncertainty::{bode_db_std, border_std, upper_pole};

/// An identification method of the table.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Method {
    /// PI-MOESP (the paper).
    PiMoesp,
    /// PO-MOESP.
    PoMoesp,
    /// N4SID.
    N4sid,
    /// CVA.
    Cva,
    /// PI-MOESP's `A`, `C` with `B`, `D`, borders by alternating least squares (Remark 5).
    PiMoespAls,
    /// PI-MOESP refined by the prediction-error method.
    Pem,
}

impl Method {
    /// Every method, in table order.
    pub const ALL: [Method; 6] = [
        Method::PiMoesp,
        Method::PoMoesp,
        Method::N4sid,
        Method::Cva,
        Method::PiMoespAls,
        Method::Pem,
    ];

    /// The name used on the command line and in `summary.json`.
    pub fn name(self) -> &'static str {
        match self {
            Method::PiMoesp => "pi-moesp",
            Method::PoMoesp => "po-moesp",
            Method::N4sid => "n4sid",
            Method::Cva => "cva",
            Method::PiMoespAls => "pi-moesp-als",
            Method::Pem => "pem",
        }
    }

    /// The method of a name.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|m| m.name() == name)
    }

    /// Whether this build can run the method (the weightings come from the core; all four
    /// are there).
    pub fn available(self) -> bool {
        true
    }

    /// The core's subspace weighting of a subspace method (`None` for the refinements, which
    /// start from PI-MOESP).
    pub fn weighting(self) -> Option<hsid::Method> {
        match self {
            Method::PiMoesp => Some(hsid::Method::PiMoesp),
            Method::PoMoesp => Some(hsid::Method::PoMoesp),
            Method::N4sid => Some(hsid::Method::N4sid),
            Method::Cva => Some(hsid::Method::Cva),
            Method::PiMoespAls | Method::Pem => None,
        }
    }
}

/// One identification by a method.
#[derive(Clone, Debug)]
pub(crate) struct MethodRun {
    /// The model.
    pub model: HostModel,
    /// Wall-clock seconds (subspace step included for the refinements).
    pub seconds: f64,
    /// The refinement, for `pem`.
    pub pem: Option<PemFit>,
}

/// Identifies `(u, y)` with `method`.
pub(crate) fn identify_method(
    method: Method,
    u: &[f64],
    y: &[f64],
    opts: &IdentifyOptions,
) -> Result<MethodRun, RefineError> {
    let clock = Instant::now();
    // The refinements start from PI-MOESP, consistent whatever the noise.
    let pi = IdentifyOptions {
        method: hsid::Method::PiMoesp,
        ..opts.clone()
    };
    match method {
        Method::PiMoesp | Method::PoMoesp | Method::N4sid | Method::Cva => {
            let sub = IdentifyOptions {
                method: method.weighting().unwrap_or_default(),
                ..opts.clone()
            };
            let model = identify(u, y, &sub)?;
            Ok(MethodRun {
                model,
                seconds: clock.elapsed().as_secs_f64(),
                pem: None,
            })
        }
        Method::PiMoespAls => {
            let init = identify(u, y, &pi)?;
            let fit = split(&init, u, y, opts.hold, 100, opts.static_nonlinearity)?;
            Ok(MethodRun {
                model: fit.model,
                seconds: clock.elapsed().as_secs_f64(),
                pem: None,
            })
        }
        Method::Pem => {
            let init = identify(u, y, &pi)?;
            let fit = refine(u, y, &init, &PemOptions::for_identify(opts))?;
            Ok(MethodRun {
                model: fit.model.clone(),
                seconds: clock.elapsed().as_secs_f64(),
                pem: Some(fit),
            })
        }
    }
}

/// Reported standard deviations against the Monte Carlo spread (`reported / empirical`,
/// 1 is perfect; the issue asks for 0.7 … 1.3).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct UncertaintyCheck {
    /// Runs used.
    pub runs: usize,
    /// Upper pole: mean reported std over the empirical std, `[re, im]`.
    pub pole: [f64; 2],
    /// Bode magnitude on 40 frequencies: `[min, median, max]` of the ratio.
    pub bode_db: [f64; 3],
    /// Border values at the knots (μ0 included): `[min, median, max]` of the ratio.
    pub borders: [f64; 3],
}

/// One method's summary in `summary.json`.
#[derive(Clone, Debug, Serialize)]
pub struct MethodSummary {
    /// The foundation's fields.
    #[serde(flatten)]
    pub base: CaseSummary,
    /// The method's name.
    pub method: String,
    /// `‖pole_std‖ / ‖crb_pole_std‖` of the upper pole.
    pub pole_std_over_crb: f64,
    /// The Cramér–Rao bound on the upper pole's `[re, im]` standard deviations.
    pub crb_pole_std: [f64; 2],
    /// Mean wall-clock seconds per identification (simulation excluded).
    pub seconds_per_identification: f64,
    /// RMS error of μ0 over the runs.
    pub mu0_rms_error: f64,
    /// For `pem`: reported standard deviations against the spread.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub uncertainty: Option<UncertaintyCheck>,
    /// For `pem`: how many runs chose each noise model order (index = order).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub noise_order_counts: Option<Vec<usize>>,
    /// For `pem`: runs in which the feed-through `D` was dropped as insignificant.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub feedthrough_dropped: Option<usize>,
}

/// One method's Monte Carlo.
#[derive(Clone, Debug)]
pub struct MethodResult {
    /// The method.
    pub method: Method,
    /// Its summary.
    pub summary: MethodSummary,
    /// The statistics and figure data, as for the foundation's table.
    pub case: CaseResult,
    /// The refinements of every successful run (`pem` only).
    pub fits: Vec<PemFit>,
}

/// Every method on one case, with the bound.
#[derive(Clone, Debug)]
pub struct CaseMethods {
    /// The case.
    pub case: Case,
    /// The Cramér–Rao bound.
    pub crb: Crb,
    /// The methods, in the order asked.
    pub methods: Vec<MethodResult>,
}

fn sample_std(v: &[f64]) -> f64 {
    let n = v.len() as f64;
    if n < 2.0 {
        return f64::NAN;
    }
    let m = v.iter().sum::<f64>() / n;
    (v.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / (n - 1.0)).sqrt()
}

fn min_med_max(mut v: Vec<f64>) -> [f64; 3] {
    v.retain(|x| x.is_finite());
    if v.is_empty() {
        return [f64::NAN; 3];
    }
    v.sort_by(|a, b| a.total_cmp(b));
    let n = v.len();
    let med = if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    };
    [v[0], med, v[n - 1]]
}

/// 40 log-spaced frequencies for the Bode check.
pub(crate) fn check_frequencies() -> Vec<f64> {
    (0..40)
        .map(|i| 10f64.powf(-2.5 + (std::f64::consts::PI.log10() + 2.5) * i as f64 / 39.0))
        .collect()
}

/// Compares the reported standard deviations of the refinements with their spread.
pub(crate) fn uncertainty_check(fits: &[PemFit]) -> Option<UncertaintyCheck> {
    let fits: Vec<&PemFit> = fits.iter().filter(|f| f.model.order == 2).collect();
    if fits.len() < 3 {
        return None;
    }
    let n = fits.len() as f64;
    let poles: Vec<_> = fits.iter().filter_map(|f| upper_pole(f)).collect();
    let emp_re = sample_std(&poles.iter().map(|p| p.pole.0).collect::<Vec<_>>());
    let emp_im = sample_std(&poles.iter().map(|p| p.pole.1).collect::<Vec<_>>());
    let rep_re = poles.iter().map(|p| p.std.0).sum::<f64>() / poles.len() as f64;
    let rep_im = poles.iter().map(|p| p.std.1).sum::<f64>() / poles.len() as f64;
    let w = check_frequencies();
    let bode: Vec<Vec<(f64, f64)>> = fits.iter().map(|f| bode_db_std(f, &w)).collect();
    let bode_ratio: Vec<f64> = (0..w.len())
        .map(|k| {
            let vals: Vec<f64> = bode.iter().map(|b| b[k].0).collect();
            let rep = bode.iter().map(|b| b[k].1).sum::<f64>() / n;
            rep / sample_std(&vals)
        })
        .collect();
    let stds: Vec<(Vec<f64>, Vec<f64>)> = fits.iter().map(|f| border_std(f)).collect();
    let mut border_ratio = Vec::new();
    let na = fits[0].model.border_asc.len();
    let nd = fits[0].model.border_desc.len();
    for i in 0..na {
        let vals: Vec<f64> = fits.iter().map(|f| f.model.border_asc[i]).collect();
        let rep = stds.iter().map(|s| s.0[i]).sum::<f64>() / n;
        border_ratio.push(rep / sample_std(&vals));
    }
    for i in 1..nd {
        let vals: Vec<f64> = fits.iter().map(|f| f.model.border_desc[i]).collect();
        let rep = stds.iter().map(|s| s.1[i]).sum::<f64>() / n;
        border_ratio.push(rep / sample_std(&vals));
    }
    Some(UncertaintyCheck {
        runs: fits.len(),
        pole: [rep_re / emp_re, rep_im / emp_im],
        bode_db: min_med_max(bode_ratio),
        borders: min_med_max(border_ratio),
    })
}

/// Runs `method` on every run of `case` (in parallel) and summarises against `crb`.
pub(crate) fn run_method(
    method: Method,
    case: Case,
    cfg: &PaperConfig,
    crb: &Crb,
    tick: &(dyn Fn() + Sync),
) -> MethodResult {
    let opts = options(cfg);
    let results = monte_carlo(
        cfg.runs,
        |r| {
            let e = experiment(case, cfg, r)?;
            Ok(identify_method(method, &e.u, &e.y, &opts)?)
        },
        tick,
    );
    let mut models = Vec::new();
    let mut failures = Vec::new();
    let mut fits = Vec::new();
    let mut seconds = Vec::new();
    for (r, res) in results.into_iter().enumerate() {
        match res {
            Ok(run) => {
                seconds.push(run.seconds);
                models.push(run.model);
                if let Some(f) = run.pem {
                    fits.push(f);
                }
            }
            Err(e) => failures.push(format!("run {r}: {e}")),
        }
    }
    let mu0_sq: Vec<f64> = models.iter().map(|m| m.mu0).collect();
    let case_res = summarize(case, cfg, models, failures);
    let mu0_true = case_res.summary.mu0_true;
    let mu0_rms_error = (mu0_sq
        .iter()
        .map(|v| (v - mu0_true) * (v - mu0_true))
        .sum::<f64>()
        / mu0_sq.len().max(1) as f64)
        .sqrt();
    let s = &case_res.summary;
    let ratio = s.pole_std[0].hypot(s.pole_std[1]) / crb.pole_std_norm();
    let is_pem = method == Method::Pem;
    let noise_order_counts = is_pem.then(|| {
        let mut c = vec![0usize; 1 + fits.iter().map(|f| f.noise.order()).max().unwrap_or(0)];
        for f in &fits {
            c[f.noise.order()] += 1;
        }
        c
    });
    let feedthrough_dropped = is_pem.then(|| fits.iter().filter(|f| !f.layout.feedthrough).count());
    let summary = MethodSummary {
        base: s.clone(),
        method: method.name().to_string(),
        pole_std_over_crb: ratio,
        crb_pole_std: [crb.pole.std.0, crb.pole.std.1],
        seconds_per_identification: seconds.iter().sum::<f64>() / seconds.len().max(1) as f64,
        mu0_rms_error,
        uncertainty: if is_pem {
            uncertainty_check(&fits)
        } else {
            None
        },
        noise_order_counts,
        feedthrough_dropped,
    };
    MethodResult {
        method,
        summary,
        case: case_res,
        fits,
    }
}

/// Experiments over which the bound's information is averaged (it barely varies: ±1 % from 5
/// to 20 experiments).
pub(crate) const CRB_RUNS: usize = 10;

/// Every method in `methods` on `case`, and the bound.
pub fn run_methods(
    case: Case,
    cfg: &PaperConfig,
    methods: &[Method],
    tick: &(dyn Fn() + Sync),
) -> Result<CaseMethods, RefineError> {
    let crb = paper_crb(case, cfg, CRB_RUNS.min(cfg.runs.max(1)), true)?;
    let methods = methods
        .iter()
        .map(|&m| run_method(m, case, cfg, &crb, tick))
        .collect();
    Ok(CaseMethods { case, crb, methods })
}

/// The table of the README (Markdown): one row per method and case, plus the bound.
pub fn methods_table(cfg: &PaperConfig, cases: &[CaseMethods]) -> String {
    use std::fmt::Write;
    let mut s = String::new();
    let _ = writeln!(
        s,
        "Monte Carlo: {} runs per case (same seeds for every method), j = {}, f = p = {}, SNR = {} dB, {} uniform segments per path, seed {}",
        cfg.runs, cfg.j, cfg.f, cfg.snr_db, cfg.segments, cfg.seed
    );
    let _ = writeln!(s);
    let _ = writeln!(
        s,
        "| case | method | pole bias | pole std (re, im) | std/CRB | std vs PI-MOESP | median border RMS | μ0 RMS error | time per identification | failures |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|---|---|---|---|");
    for c in cases {
        let pi = c
            .methods
            .iter()
            .find(|m| m.method == Method::PiMoesp)
            .map(|m| m.summary.base.pole_std[0].hypot(m.summary.base.pole_std[1]));
        for m in &c.methods {
            let b = &m.summary.base;
            let norm = b.pole_std[0].hypot(b.pole_std[1]);
            let vs = pi.map_or("–".to_string(), |p| format!("{:.2}×", norm / p));
            let _ = writeln!(
                s,
                "| {} | {} | {:.5} | ({:.5}, {:.5}) | {:.2} | {} | {:.4} | {:.4} | {:.1} ms | {} |",
                c.case.name(),
                m.method.name(),
                b.pole_bias,
                b.pole_std[0],
                b.pole_std[1],
                m.summary.pole_std_over_crb,
                vs,
                b.border_rms_single_median,
                m.summary.mu0_rms_error,
                1e3 * m.summary.seconds_per_identification,
                b.failures.len()
            );
        }
        let _ = writeln!(
            s,
            "| {} | Cramér–Rao bound | – | ({:.5}, {:.5}) | 1 | – | – | – | – | – |",
            c.case.name(),
            c.crb.pole.std.0,
            c.crb.pole.std.1
        );
    }
    for c in cases {
        for m in &c.methods {
            if let Some(u) = &m.summary.uncertainty {
                let _ = writeln!(
                    s,
                    "\n{} / {}: reported std ÷ Monte Carlo std over {} runs — pole ({:.2}, {:.2}), Bode magnitude {:.2}…{:.2} (median {:.2}), border values {:.2}…{:.2} (median {:.2}); noise orders chosen {:?}, D dropped in {} runs",
                    c.case.name(),
                    m.method.name(),
                    u.runs,
                    u.pole[0],
                    u.pole[1],
                    u.bode_db[0],
                    u.bode_db[2],
                    u.bode_db[1],
                    u.borders[0],
                    u.borders[2],
                    u.borders[1],
                    m.summary.noise_order_counts.clone().unwrap_or_default(),
                    m.summary.feedthrough_dropped.unwrap_or(0)
                );
            }
        }
    }
    s
}

/// The `methods` object of a case in `summary.json`: method name → summary.
pub fn methods_json(c: &CaseMethods) -> serde_json::Value {
    let mut map = serde_json::Map::new();
    for m in &c.methods {
        map.insert(
            m.method.name().to_string(),
            serde_json::to_value(&m.summary).unwrap_or_default(),
        );
    }
    serde_json::Value::Object(map)
}
