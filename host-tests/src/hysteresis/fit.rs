//! The simulation-error fit: `min Σ (y(t) − ŷ(t; θ))²` over the whole record by the shared
//! Levenberg–Marquardt, from the starting model of [`start`](super::start). On an output
//! pinned at a level (a saturating sensor), `ŷ` is the simulation clamped there
//! ([`ElementFitOptions::floor`]).
//!
//! # Jacobian
//!
//! Forward differences (the shared solver's, step `10⁻⁶ max(|θ_j|, typical_j)`). The play
//! operator's output is a continuous, piecewise-linear function of the border values and of
//! `w(−1)` (a composition of `max`, `min` and the linear interpolation), and the relay's is
//! linear in them; `G` is smooth in `(F, B)`. The simulation error is therefore Lipschitz and
//! differentiable except where a sample sits exactly on a switch between a border and the
//! held value; a difference step crosses such a switch only at the few samples within
//! `10⁻⁶` of it, where the two one-sided slopes differ by a bounded amount. The difference
//! quotient is thus the exact derivative up to `O(step)` on all other samples, which is what
//! Gauss–Newton needs. An analytic derivative would have to carry the same case analysis
//! (which border is active at each sample) and gives the same matrix; the differences cost
//! one simulation (`O(N n)`) per parameter, well within the bounded iteration budget.

use super::error::HysteresisError;
use super::params::{HysteresisModel, Layout};
use super::simulate::simulate;
use super::start::{Start, start_model};
use super::uncertainty::{Uncertainty, uncertainty};
use crate::identify::HostModel;
use crate::model::MemoryElement;
use crate::numerics::lm::{self, Divergence, Exhausted, Jacobian, Problem, Settings};
use crate::numerics::poly::spectral_radius;

/// Settings of the fit.
#[derive(Clone, Debug, PartialEq)]
pub struct ElementFitOptions {
    /// Backlash or switch.
    pub kind: MemoryElement,
    /// Iteration limit of Levenberg–Marquardt.
    pub max_iter: usize,
    /// Whether `G` has a direct feed-through (usually not for a sampled plant).
    pub feedthrough: bool,
    /// The fit admits only `G` whose poles lie strictly inside this radius: 1 admits every
    /// stable `G`; below 1 keeps out modes slower than the record can validate (a pole at
    /// 0.99997 on 2400 samples acts as a drift), so the fit finds the best model among those
    /// instead of one that must then be refused.
    pub max_pole_radius: f64,
    /// Levels the measured output cannot go below and above (a saturating sensor, an end
    /// stop): the simulation is clamped to them before the error is taken, so a sample pinned
    /// at a level pulls the fit only where the model's output would not reach it. `None`: no
    /// clamp.
    pub floor: Option<f64>,
    /// The upper level (see [`floor`](Self::floor)).
    pub ceiling: Option<f64>,
}

impl ElementFitOptions {
    /// A fit of `kind` with 60 iterations and a strictly proper, stable `G`, no clamp.
    pub fn new(kind: MemoryElement) -> Self {
        Self {
            kind,
            max_iter: 60,
            feedthrough: false,
            max_pole_radius: 1.0,
            floor: None,
            ceiling: None,
        }
    }

    /// `v` clamped to [`floor`](Self::floor) and [`ceiling`](Self::ceiling).
    pub fn clamp(&self, v: f64) -> f64 {
        let v = self.ceiling.map_or(v, |c| v.min(c));
        self.floor.map_or(v, |f| v.max(f))
    }
}

/// The fitted model and how the fit went.
#[derive(Clone, Debug)]
pub struct HysteresisFit {
    /// The model.
    pub model: HysteresisModel,
    /// The estimate that started the fit.
    pub start: Start,
    /// `Σe²` at the start and at the end.
    pub initial_cost: f64,
    /// `Σe²` at the optimum.
    pub cost: f64,
    /// Iterations done.
    pub iterations: usize,
    /// Whether the iteration budget ended the fit (the last step still gained).
    pub budget_reached: bool,
    /// Standard deviations (`None` when `JᵀJ` is singular at the optimum).
    pub uncertainty: Option<Uncertainty>,
}

impl HysteresisFit {
    /// The simulated output for an input record.
    pub fn simulate(&self, u: &[f64]) -> Vec<f64> {
        simulate(&self.model, u)
    }
}

/// Refuses records the fit cannot use.
fn check(u: &[f64], y: &[f64], params: usize) -> Result<(), HysteresisError> {
    if u.len() != y.len() {
        return Err(HysteresisError::LengthMismatch {
            u: u.len(),
            y: y.len(),
        });
    }
    let need = 10 * params;
    if u.len() < need {
        return Err(HysteresisError::TooFewSamples {
            have: u.len(),
            need,
        });
    }
    for (signal, x) in [("u", u), ("y", y)] {
        if let Some(index) = x.iter().position(|v| !v.is_finite()) {
            return Err(HysteresisError::NonFinite { signal, index });
        }
    }
    Ok(())
}

/// Fits a hysteresis model of `opts.kind` to `(u, y)` from the subspace estimate `init`
/// (the two-path or the static one, named by `start`).
pub fn fit_hysteresis(
    u: &[f64],
    y: &[f64],
    init: &HostModel,
    start: Start,
    opts: &ElementFitOptions,
) -> Result<HysteresisFit, HysteresisError> {
    fit_hysteresis_skipping(u, y, &[], init, start, opts)
}

/// [`fit_hysteresis`] with the samples where `skip` is set left out of the error (an empty
/// `skip` leaves none out). The whole input still drives the simulation, so the element's
/// state and the plant's run through the skipped samples (a held-out block, outliers); the
/// start is chosen with the measured output there replaced by `init`'s simulation, so the
/// skipped outputs choose nothing.
pub fn fit_hysteresis_skipping(
    u: &[f64],
    y: &[f64],
    skip: &[bool],
    init: &HostModel,
    start: Start,
    opts: &ElementFitOptions,
) -> Result<HysteresisFit, HysteresisError> {
    let layout = Layout {
        kind: opts.kind,
        n: init.order,
        knots: init.knots_asc.len(),
        feedthrough: opts.feedthrough,
    };
    check(u, y, layout.len())?;
    if !(f64::MIN_POSITIVE..=1.0).contains(&opts.max_pole_radius) {
        return Err(HysteresisError::PoleRadius(opts.max_pole_radius));
    }
    if !skip.is_empty() && skip.len() != y.len() {
        return Err(HysteresisError::SkipMismatch {
            samples: y.len(),
            skip: skip.len(),
        });
    }
    let skipped = |t: usize| skip.get(t).copied().unwrap_or(false);
    let used = y.len() - skip.iter().filter(|&&s| s).count();
    let y_start: Vec<f64> = if skip.iter().any(|&s| s) {
        let sim = init.simulate(u);
        (0..y.len())
            .map(|t| if skipped(t) { sim[t] } else { y[t] })
            .collect()
    } else {
        y.to_vec()
    };
    let m0 = start_model(init, opts.kind, opts.feedthrough, u, &y_start)?;
    let knots = m0.knots.clone();
    let th0 = m0.theta(&layout);
    let residual = |th: &[f64]| -> Option<Vec<f64>> {
        let m = HysteresisModel::from_theta(&layout, &knots, th);
        let r: Vec<f64> = simulate(&m, u)
            .iter()
            .zip(y)
            .enumerate()
            .map(
                |(t, (a, b))| {
                    if skipped(t) { 0.0 } else { opts.clamp(*a) - b }
                },
            )
            .collect();
        r.iter().all(|v| v.is_finite()).then_some(r)
    };
    let admissible = |th: &[f64]| admissible(&layout, th, opts.max_pole_radius);
    let scale = y.iter().fold(0.0f64, |m, v| m.max(v.abs())).max(1e-9);
    let typical: Vec<f64> = (0..layout.len())
        .map(|j| {
            if layout.plant().contains(&j) {
                1.0
            } else {
                scale
            }
        })
        .collect();
    let problem = Problem {
        residual: &residual,
        admissible: &admissible,
        jacobian: Jacobian::ForwardDifference { typical: &typical },
    };
    let settings = Settings {
        divergence: Divergence::Fail { growth: 1e6 },
        exhausted: Exhausted::ReturnBest,
        ..Settings::simulation_fit(opts.max_iter)
    };
    let radius = spectral_radius(&layout.linear().polynomials(&th0[layout.plant()]).f);
    if radius < 1.0 && radius >= opts.max_pole_radius {
        return Err(HysteresisError::StartTooSlow {
            radius,
            limit: opts.max_pole_radius,
        });
    }
    if !admissible(&th0) {
        return Err(HysteresisError::StartDoesNotSimulate);
    }
    let initial_cost = residual(&th0)
        .ok_or(HysteresisError::StartDoesNotSimulate)?
        .iter()
        .map(|v| v * v)
        .sum();
    let min = lm::minimise(&problem, &th0, &settings)?;
    let cost = min.residual.iter().map(|v| v * v).sum::<f64>();
    let model = HysteresisModel::from_theta(&layout, &knots, &min.theta);
    let uncertainty = uncertainty(&problem, &layout, &min.theta, &min.residual, used, &typical)
        .map(|s| match opts.kind {
            MemoryElement::Play => s.with_gap(&layout, &model),
            MemoryElement::Relay => s,
        });
    Ok(HysteresisFit {
        uncertainty,
        model,
        start,
        initial_cost,
        cost,
        iterations: min.iterations,
        budget_reached: min.iterations >= opts.max_iter,
    })
}

/// `F(q)`'s roots inside `max_radius` (1: stable), and for a backlash `H_a ≤ H_d` at every
/// knot (the play operator's condition).
fn admissible(layout: &Layout, th: &[f64], max_radius: f64) -> bool {
    let p = layout.linear().polynomials(&th[layout.plant()]);
    let ordered = layout.kind == MemoryElement::Relay
        || th[layout.asc()]
            .iter()
            .zip(&th[layout.desc()])
            .all(|(a, d)| a <= d);
    ordered && spectral_radius(&p.f) < max_radius
}
