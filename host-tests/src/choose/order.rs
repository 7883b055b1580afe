//! The final order of the refined model, by an information criterion on the estimation data.
//!
//! The subspace step's order choice reads a gap in the singular values; a weak but real state
//! (a slow pole with little gain) can sit below that gap, and at low SNR a noise direction can
//! sit above it. So the neighbours of the subspace order are refined too, each from its own
//! subspace model, and the order whose refined model has the smallest BIC
//! (`N ln(Σε²/N) + d ln N` on the prediction errors) is kept: a state is kept only when it
//! lowers the prediction error by more than its parameters cost. A refined model the data do
//! not determine ([`determined`]) is kept only when no candidate order is determined.

use super::ModelStage;
use super::start::subspace_start;
use super::{Choices, ChooseError};
use crate::identify::{HostModel, IdentifyError, IdentifyOptions};
use crate::numerics::select::{Criterion, best, relative_scores};
use crate::refine::RefineError;
use crate::refine::pem::{PemFit, PemOptions, refine};

/// The order chosen and the score of every candidate.
#[derive(Clone, Debug)]
pub struct OrderChoice {
    /// The order kept.
    pub order: usize,
    /// The subspace step's own choice.
    pub subspace: usize,
    /// The criterion.
    pub criterion: Criterion,
    /// `(order, score)` of every candidate refined.
    pub scores: Vec<(usize, f64)>,
    /// `(order, reason)` of the candidates that failed.
    pub failures: Vec<(usize, String)>,
    /// The candidates refined to a singular information matrix (not determined by the data).
    pub undetermined: Vec<usize>,
}

impl OrderChoice {
    /// One line for a report.
    pub fn report(&self) -> String {
        format!(
            "order {} chosen by {} of the refined models (the singular values suggested {}; {} relative to the best: {})",
            self.order,
            self.criterion.name(),
            self.subspace,
            self.criterion.name(),
            relative_scores(&self.scores, self.order)
        ) + &match self.undetermined.as_slice() {
            [] => String::new(),
            u => format!(
                "; not determined by the data (a singular JᵀJ or a pole slower than the record), \
                 kept only when no order is: {}",
                u.iter()
                    .map(|n| n.to_string())
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        }
    }
}

/// The refinement's options for `opts` with the noise model of `choices`.
fn pem_options(opts: &IdentifyOptions, choices: &Choices) -> PemOptions {
    PemOptions {
        noise_order: choices.noise,
        ..PemOptions::for_identify(opts)
    }
}

/// A refined order and, when the start it was given did not refine, why.
#[derive(Clone, Debug)]
pub struct Refined {
    /// The fit.
    pub fit: PemFit,
    /// Why the given start did not refine (the fit is then from the subspace model).
    pub restarted: Option<RefineError>,
}

/// Why an order could not be refined: its subspace model, or its refinement.
#[derive(Debug, thiserror::Error)]
enum OrderError {
    #[error(transparent)]
    Start(#[from] IdentifyError),
    #[error(transparent)]
    Refine(#[from] RefineError),
}

/// The subspace model of `(u, y)` with `opts` at order `n`, to start its refinement from.
fn subspace_model(
    u: &[f64],
    y: &[f64],
    opts: &IdentifyOptions,
    n: usize,
) -> Result<HostModel, IdentifyError> {
    let mut o = opts.clone();
    o.order = Some(n);
    Ok(subspace_start(u, y, &mut o, ModelStage::Refined, false)?.model)
}

/// Refines order `n` on `(u, y)` with [`PemOptions::for_identify`] and the noise model of
/// `choices`: from `from` (a fit of the same structure on the record's start) when given, from
/// the subspace model with `opts` at that order when not or when `from` does not refine.
fn refine_order(
    u: &[f64],
    y: &[f64],
    opts: &IdentifyOptions,
    n: usize,
    choices: &Choices,
    from: Option<&HostModel>,
) -> Result<Refined, OrderError> {
    let pem = &pem_options(opts, choices);
    let mut restarted = None;
    if let Some(start) = from {
        match refine(u, y, start, pem) {
            Ok(fit) => return Ok(Refined { fit, restarted }),
            // The start's fit did not refine on the whole record: once more from its own
            // subspace model.
            Err(e) => restarted = Some(e),
        }
    }
    let fit = refine(u, y, &subspace_model(u, y, opts, n)?, pem)?;
    Ok(Refined { fit, restarted })
}

/// The order of `chosen` (a fit on the start of `(u, y)` with `opts`) refined on the whole
/// record: from `chosen`'s model, or from the whole record's subspace model at that order when
/// that does not refine (then with why).
pub fn on_whole_record(
    u: &[f64],
    y: &[f64],
    opts: &IdentifyOptions,
    chosen: &PemFit,
    choices: &Choices,
) -> Result<Refined, ChooseError> {
    let n = chosen.model.order;
    crate::progress::stage(|| format!("refining the chosen order {n} on the whole record"))?;
    refine_order(u, y, opts, n, choices, Some(&chosen.model))
        .map_err(|e| ChooseError::Refine(vec![(n, e.to_string())]))
}

/// Refines the orders `candidates` on `(u, y)` (each identified with `opts` at that order,
/// refined with [`PemOptions::for_identify`] and the noise model of `choices`) and keeps the
/// best by `choices.criterion`; the fit of
/// the kept order is returned with the choice.
pub fn choose_order(
    u: &[f64],
    y: &[f64],
    opts: &IdentifyOptions,
    subspace: usize,
    candidates: &[usize],
    choices: &Choices,
) -> Result<(PemFit, OrderChoice), ChooseError> {
    let criterion = choices.criterion;
    let mut fits = Vec::new();
    let mut scores = Vec::new();
    let mut failures = Vec::new();
    // The subspace models one after the other: each holds the identifier's lagged sums and
    // its solve's workspace, the largest buffers of a run (tens of MB at f = p = 40 and
    // 29 channels, whatever the record's length).
    let mut starts = Vec::with_capacity(candidates.len());
    for &n in candidates {
        crate::progress::stage(|| format!("subspace model at order {n}"))?;
        starts.push(subspace_model(u, y, opts, n).map_err(|e| e.to_string()));
    }
    // Their refinements are independent and need little memory: across the cores, kept in
    // their order.
    let pem = &pem_options(opts, choices);
    let refined = crate::progress::map(&starts, |i, start| {
        let n = candidates[i];
        crate::progress::stage(|| {
            format!("refining order {n} ({} of {})", i + 1, candidates.len())
        })?;
        Ok::<_, crate::progress::Interrupted>(match start {
            Ok(model) => refine(u, y, model, pem).map_err(|e| e.to_string()),
            Err(e) => Err(e.clone()),
        })
    });
    for (&n, refined) in candidates.iter().zip(refined) {
        match refined? {
            Ok(f) => {
                scores.push((
                    n,
                    criterion.score(f.samples as f64, f.mse, f.parameters() as f64),
                ));
                fits.push((n, f));
            }
            Err(e) => failures.push((n, e)),
        }
    }
    // A fit the data do not determine (a singular information matrix, or a pole slower than
    // the record is long, whose gain the record cannot tell from a drift) has a parameter too
    // many: it is kept only when no candidate is determined.
    let undetermined: Vec<usize> = fits
        .iter()
        .filter(|(_, f)| !determined(f))
        .map(|(n, _)| *n)
        .collect();
    let determined: Vec<(usize, f64)> = scores
        .iter()
        .copied()
        .filter(|(n, _)| !undetermined.contains(n))
        .collect();
    let order = match determined.is_empty() {
        true => best(&scores),
        false => best(&determined),
    };
    let kept = order.and_then(|order| fits.into_iter().find(|(n, _)| *n == order));
    let Some((order, fit)) = kept else {
        return Err(match candidates {
            [] => ChooseError::NoCandidate,
            _ => ChooseError::Refine(failures),
        });
    };
    Ok((
        fit,
        OrderChoice {
            order,
            subspace,
            criterion,
            scores,
            failures,
            undetermined,
        },
    ))
}

/// Whether the record determines `fit`: its information matrix is regular and its slowest
/// pole's time constant `−1/ln|p|` is shorter than the samples in its cost (a slower pole's
/// static gain cannot be told from a drift or an offset on that record).
pub fn determined(fit: &PemFit) -> bool {
    let slowest = fit
        .model
        .poles()
        .iter()
        .map(|(a, b)| a.hypot(*b))
        .fold(0.0, f64::max);
    let tau = -1.0 / slowest.ln();
    !fit.singular && tau < fit.samples as f64
}

/// The candidate orders around the subspace order `n`: `n − 1, n, n + 1`, at least 1 and below
/// the future horizon `f`.
pub fn neighbours(n: usize, f: usize) -> Vec<usize> {
    (n.saturating_sub(1).max(1)..=(n + 1).min(f.saturating_sub(1))).collect()
}
