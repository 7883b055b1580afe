//! Level-dependent stores: state-dependent dynamics with one steady state by construction.
//!
//! An order-2 model with real poles is a cascade of two stores
//! ([`HostModel::cascade_forms_with`](crate::identify::HostModel::cascade_forms_with)).
//! Here each store drains through a monotone power-law outflow instead of a linear one, and
//! the first one may overflow into the second above a level:
//!
//! ```text
//! q_i   = k_i · max(x_i, 0)^α_i                          (outflow of store i)
//! x1   ← x1 + (h + e − q1) / S ,  spill = max(x1 − L, 0),  x1 ← min(x1, L)
//! x2   ← x2 + (q1 − q2) / S + s · spill                  (S sub-steps per sample)
//! y     = g( c1 x1 + c2 x2 + d h + y0 )
//! ```
//!
//! Stores do not go below empty (`x_i ≥ 0`). With `α1 = α2 = 1`, no overflow and one sub-step
//! this is the linear cascade (poles `1 − k_i`), which is where the fit starts. Because every
//! outflow is increasing in its level, a constant inflow has exactly one steady state
//! (`q1(x1) = h + e` below the overflow, then `q2(x2) = q1(x1) + s · spill`): the class cannot
//! produce the spurious equilibria a polynomial state term can (the example `tanks_dynamics`
//! measures one that does).
//! The level `e` where the first store is empty and the output offset `y0` are fitted too:
//! with `α ≠ 1` where a store is empty matters.
//!
//! `k`, `α`, `c`, `d`, `y0`, `e`, `L`, `s`, the initial state and (if asked) the border values
//! are fitted on the simulation error by Levenberg–Marquardt ([`crate::numerics::lm`]), the output
//! map held, from eight starts: both assignments of the linear model's poles to the stores
//! (a complex pair `re ± j·im` taken as the real pair `re ± |im|`), `α` from 1 and from ½,
//! and `L` at 75 % or 90 % of the highest level the first store of the linear start reaches.
//! In [`super::diagnose`] this is the extension of `state_dependent_dynamics`, proposed when
//! the residual tests point at the dynamics (`state_dependence`, `structure_output`,
//! `whiteness`, input or regressor correlation) and kept only if the cross-validation inside
//! the estimation data confirms it against the current model and against
//! [`StoresClass::Linear`], the same stores with linear outflows.

use serde::Serialize;

use super::dynamics::{Cascade, DynamicsError, DynamicsFit};
use crate::identify::HostModel;
use crate::numerics::lm::{Settings, levenberg_marquardt};

/// Sub-steps per sample of the store equations.
pub(crate) const SUBSTEPS: usize = 4;

/// Levenberg–Marquardt iterations per start.
pub(crate) const ITERATIONS: usize = 100;

/// Bounds on the outflow exponents `α`.
pub const EXPONENT_RANGE: (f64, f64) = (0.2, 3.0);

/// A cascade of two stores with power-law outflows, the first overflowing into the second.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Stores {
    /// Outflow coefficients `k_i` (> 0).
    pub k: [f64; 2],
    /// Outflow exponents `α_i` (within [`EXPONENT_RANGE`]).
    pub alpha: [f64; 2],
    /// Output weights `c_i`.
    pub c: [f64; 2],
    /// Direct feed-through `d`.
    pub d: f64,
    /// Output offset `y0`.
    pub offset: f64,
    /// Inflow offset `e`: the first store is empty in steady state at `h = −e`.
    pub inflow_offset: f64,
    /// Level `L` of the first store above which it overflows.
    pub level: f64,
    /// Fraction `s` of the overflow that reaches the second store.
    pub spill: f64,
    /// Initial state `(x1, x2)`.
    pub x0: [f64; 2],
}

const PARAMETERS: usize = 13;

impl Stores {
    fn from_theta(t: &[f64]) -> Self {
        let g = |i: usize| t.get(i).copied().unwrap_or(0.0);
        Stores {
            k: [g(0), g(1)],
            alpha: [g(2), g(3)],
            c: [g(4), g(5)],
            d: g(6),
            offset: g(7),
            inflow_offset: g(8),
            level: g(9),
            spill: g(10),
            x0: [g(11), g(12)],
        }
    }

    fn theta(&self) -> Vec<f64> {
        vec![
            self.k[0],
            self.k[1],
            self.alpha[0],
            self.alpha[1],
            self.c[0],
            self.c[1],
            self.d,
            self.offset,
            self.inflow_offset,
            self.level,
            self.spill,
            self.x0[0],
            self.x0[1],
        ]
    }

    fn admissible(&self) -> bool {
        let (lo, hi) = EXPONENT_RANGE;
        self.k.iter().all(|k| *k > 0.0 && *k < SUBSTEPS as f64)
            && self.alpha.iter().all(|a| (lo..=hi).contains(a))
            && self.level > 0.0
            && (0.0..=2.0).contains(&self.spill)
    }

    /// The states along `h`, from [`Stores::x0`]: `(x1, x2)` before each sample.
    pub fn states(&self, h: &[f64]) -> Option<Vec<[f64; 2]>> {
        let [mut x1, mut x2] = self.x0;
        let dt = 1.0 / SUBSTEPS as f64;
        let mut out = Vec::with_capacity(h.len());
        for &hi in h {
            out.push([x1, x2]);
            for _ in 0..SUBSTEPS {
                let q1 = self.k[0] * x1.max(0.0).powf(self.alpha[0]);
                let q2 = self.k[1] * x2.max(0.0).powf(self.alpha[1]);
                let s1 = x1 + dt * (hi + self.inflow_offset - q1);
                let over = (s1 - self.level).max(0.0);
                x1 = (s1 - over).max(0.0);
                x2 = (x2 + dt * (q1 - q2) + self.spill * over).max(0.0);
            }
            if !(x1.is_finite() && x2.is_finite()) {
                return None;
            }
        }
        Some(out)
    }

    /// The output before the output map, `c1 x1 + c2 x2 + d h + y0`, along `h`; `None` if it
    /// is not finite.
    pub fn simulate(&self, h: &[f64]) -> Option<Vec<f64>> {
        let states = self.states(h)?;
        let out: Vec<f64> = states
            .iter()
            .zip(h)
            .map(|(x, hi)| self.c[0] * x[0] + self.c[1] * x[1] + self.d * hi + self.offset)
            .collect();
        out.iter().all(|v| v.is_finite()).then_some(out)
    }

    /// The steady output (before the output map) for a constant `h`, from the store balance
    /// (unique: every outflow increases with its level).
    #[cfg(test)]
    pub(crate) fn steady_output(&self, h: f64) -> f64 {
        let inflow = (h + self.inflow_offset).max(0.0);
        let level = |q: f64, i: usize| (q / self.k[i]).powf(1.0 / self.alpha[i]);
        let free = level(inflow, 0);
        let (x1, q1, spill) = if free > self.level {
            let q1 = self.k[0] * self.level.powf(self.alpha[0]);
            (self.level, q1, self.spill * (inflow - q1))
        } else {
            (free, inflow, 0.0)
        };
        let x2 = level(q1 + spill, 1);
        self.c[0] * x1 + self.c[1] * x2 + self.d * h + self.offset
    }
}

/// The slowest pole a store starts from.
const SLOWEST_START: f64 = 0.999;

/// Starting overflow levels, as fractions of the highest level the first store of the
/// linear start reaches.
const LEVEL_STARTS: [Option<f64>; 2] = [Some(0.75), Some(0.9)];

/// The overflow level of stores that do not overflow.
const NO_OVERFLOW: f64 = 1e200;

/// Which stores [`fit`] fits.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StoresClass {
    /// Power-law outflows and the overflow: the level-dependent stores.
    LevelDependent,
    /// Linear outflows (`α = 1`), no overflow: the linear cascade refitted the same way
    /// (sub-steps, offsets, borders, simulation error), the reference the level dependence
    /// must beat.
    Linear,
}

impl HostModel {
    /// The cascade forms the fit starts from: the model's poles if real; a complex pair
    /// `re ± j·im` (stores do not oscillate) starts as the real pair `re ± |im|`, and whether the
    /// stores then fit is for the validation to judge.
    pub(crate) fn start_cascades(&self) -> Result<[Cascade; 2], DynamicsError> {
        let poles = self.poles();
        if self.order != 2 || poles.len() != 2 {
            return Err(DynamicsError::NotOrderTwo { order: self.order });
        }
        let (re, im) = poles[0];
        if im == 0.0 {
            return Ok(self.cascade_forms_with(re, poles[1].0));
        }
        Ok(self.cascade_forms_with(re + im.abs(), re - im.abs()))
    }
}

/// Samples the starts are tried on: on a longer record every start is fitted on its first
/// `START_WINDOW` samples with at most [`START_ITERATIONS`] iterations, and the fit continued
/// on the whole record from the best of them (from the next best when it does not simulate
/// there).
pub const START_WINDOW: usize = 30_000;

/// Levenberg–Marquardt iterations per start on the window of a long record: enough to rank
/// the starts; the best one is then given the full iterations on the whole record.
pub const START_ITERATIONS: usize = 25;

/// Fits the level-dependent stores to an order-2 model with real poles (`A`, `B`, `C`, `D`
/// give the start, `x0` its initial state; the borders and the output map are held). Every
/// start in the module documentation is tried (on a record longer than [`START_WINDOW`], on
/// its first samples, the best continued on the whole record); the fit with the least squared
/// simulation error on the samples not skipped is returned.
pub fn fit(
    m: &HostModel,
    x0: &[f64],
    data: &DynamicsFit,
    class: StoresClass,
) -> Result<(Stores, HostModel), DynamicsError> {
    fit_with_window(m, x0, data, class, START_WINDOW)
}

/// [`fit`] with the starts tried on the first `window` samples of a longer record.
fn fit_with_window(
    m: &HostModel,
    x0: &[f64],
    data: &DynamicsFit,
    class: StoresClass,
    window: usize,
) -> Result<(Stores, HostModel), DynamicsError> {
    let windowed = data.h.len() > window;
    let window = DynamicsFit {
        iterations: data.iterations.min(START_ITERATIONS),
        ..data.prefix(window)
    };
    let on = if windowed { &window } else { data };
    let mut fits: Vec<(f64, Vec<f64>)> = starts(m, x0, on, class)?
        .into_iter()
        .filter_map(|theta0| fit_from(m, &theta0, on, class))
        .collect();
    fits.sort_by(|a, b| a.0.total_cmp(&b.0));
    let theta = match windowed {
        false => fits.into_iter().next().map(|(_, t)| t),
        true => fits
            .into_iter()
            .find_map(|(_, t)| fit_from(m, &t, data, class).map(|(_, t)| t)),
    };
    let theta = theta.ok_or(DynamicsError::NotSimulating)?;
    Ok((Stores::from_theta(&theta), with_borders(m, data, &theta)))
}

/// `m` with the border values appended to `θ` after the stores' parameters, when refitted.
fn with_borders(m: &HostModel, data: &DynamicsFit, theta: &[f64]) -> HostModel {
    let mut mm = m.clone();
    if let Some(b) = data.borders {
        b.unpack(&mut theta.iter().skip(PARAMETERS).copied(), &mut mm);
    }
    mm
}

/// The starts `θ0` of the module documentation for `class` on `data` (border values appended
/// when refitted).
fn starts(
    m: &HostModel,
    x0: &[f64],
    data: &DynamicsFit,
    class: StoresClass,
) -> Result<Vec<Vec<f64>>, DynamicsError> {
    let cascades = m.start_cascades()?;
    let y_first = m.d * data.h.first().copied().unwrap_or(0.0)
        + m.c.iter().zip(x0).map(|(c, x)| c * x).sum::<f64>();
    let (h_low, h_high) = data
        .h
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, u), &v| {
            (l.min(v), u.max(v))
        });
    if !(h_low.is_finite() && h_high.is_finite()) {
        return Err(DynamicsError::Empty {
            order: m.order,
            samples: data.h.len(),
        });
    }
    let mut out = Vec::new();
    for cascade in cascades {
        let Some(linear) = linear_start(&cascade, m.d, y_first, h_low, h_high) else {
            continue;
        };
        let Some(states) = linear.states(data.h) else {
            continue;
        };
        let top = states.iter().map(|x| x[0]).fold(0.0, f64::max);
        let mean = |i: usize| states.iter().map(|x| x[i]).sum::<f64>() / states.len() as f64;
        let (alphas, levels): (&[f64], &[Option<f64>]) = match class {
            StoresClass::LevelDependent => (&[1.0, 0.5], &LEVEL_STARTS),
            StoresClass::Linear => (&[1.0], &[None]),
        };
        for &alpha in alphas {
            let mut start = linear.clone();
            for (i, a) in start.alpha.iter_mut().enumerate() {
                // Same outflow at the mean level.
                let x = mean(i).max(1e-9);
                start.k[i] *= x.powf(1.0 - alpha);
                *a = alpha;
            }
            for &level in levels {
                let mut s = start.clone();
                // No overflow: a level no store reaches (its parameter held).
                s.level = level.map_or(NO_OVERFLOW, |f| f * top);
                let mut theta0 = s.theta();
                if let Some(b) = data.borders {
                    b.pack(m, &mut theta0);
                }
                out.push(theta0);
            }
        }
    }
    Ok(out)
}

/// The stores fitted on `data` by Levenberg–Marquardt from `θ0` (what `class` and
/// [`DynamicsFit::fit_x0`] hold kept at `θ0`'s values): the squared simulation error and `θ`;
/// `None` when the fit does not simulate.
fn fit_from(
    m: &HostModel,
    theta0: &[f64],
    data: &DynamicsFit,
    class: StoresClass,
) -> Option<(f64, Vec<f64>)> {
    let residual = |t: &[f64]| -> Option<Vec<f64>> {
        let refitted = data
            .borders
            .and_then(|_| data.refitted_h(&with_borders(m, data, t)));
        data.residual(&Stores::from_theta(t).simulate(refitted.as_deref().unwrap_or(data.h))?)
    };
    let admissible = |t: &[f64]| Stores::from_theta(t).admissible();
    let settings = Settings {
        iterations: data.iterations,
        ..Settings::default()
    };
    let typical: Vec<f64> = theta0.iter().map(|v| v.abs().max(1e-3)).collect();
    let held = |t: &[f64]| {
        let mut t = t.to_vec();
        if !data.fit_x0 {
            t[11..PARAMETERS].copy_from_slice(&theta0[11..PARAMETERS]);
        }
        if class == StoresClass::Linear {
            // α, the level and the spill held.
            for i in [2, 3, 9, 10] {
                t[i] = theta0[i];
            }
        }
        t
    };
    let res = |t: &[f64]| residual(&held(t));
    let (theta, r) = levenberg_marquardt(theta0, &typical, &settings, &res, &admissible).ok()?;
    Some((r.iter().map(|v| v * v).sum(), held(&theta)))
}

/// The linear cascade as stores (`α = 1`, no overflow). Outflow rates `k_i = S (1 − p_i^{1/S})`
/// give the poles over `S` sub-steps; at rest the stores hold `x_i = (h + e) / k_i` where the
/// cascade holds `h / (1 − p1)` and `h / ((1 − p1)(1 − p2))`, which scales the output weights.
/// The inflow offset puts the lowest `h` 5 % of its range above empty, the output offset
/// compensates it, and the stores start at rest at the level that gives the model's first
/// output.
fn linear_start(
    cascade: &Cascade,
    d: f64,
    y_first: f64,
    h_low: f64,
    h_high: f64,
) -> Option<Stores> {
    let Cascade { p1, p2, c1, c2 } = *cascade;
    if !(p1.is_finite() && p2.is_finite()) {
        return None;
    }
    // Stores drain: a pole at or beyond 1 (a drift the linear fit put there) starts as a
    // slow store, one at or below 0 as a fast one.
    let (p1, p2) = (p1.clamp(0.01, SLOWEST_START), p2.clamp(0.01, SLOWEST_START));
    let sub = SUBSTEPS as f64;
    let rate = |p: f64| sub * (1.0 - p.powf(1.0 / sub));
    let k = [rate(p1), rate(p2)];
    let c = [
        c1 * k[0] / (1.0 - p1),
        c2 * k[1] / ((1.0 - p1) * (1.0 - p2)),
    ];
    let e = (0.05 * (h_high - h_low) - h_low).max(0.0);
    // Static gain from h + e to c x.
    let gain = c[0] / k[0] + c[1] / k[1];
    let rest_h = if (gain + d).abs() > 1e-300 {
        y_first / (gain + d)
    } else {
        0.0
    };
    let inflow = (rest_h + e).max(0.0);
    Some(Stores {
        k,
        alpha: [1.0, 1.0],
        c,
        d,
        offset: -gain * e,
        inflow_offset: e,
        level: f64::INFINITY,
        spill: 1.0,
        x0: [inflow / k[0], inflow / k[1]],
    })
}

#[cfg(test)]
mod fixtures;
#[cfg(test)]
mod tests;
