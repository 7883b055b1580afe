//! Whether a run's true effect is resolvable on its estimation record, decided apart from the
//! diagnosis: the record after its hold is split 75 % / 25 %; on the first part (with the
//! hold) the linear output-error baseline ([`linear_model`]: static element with one segment,
//! refined by output error at the declared order) and the true effect's model are fitted by
//! the library's public fits; both simulate the whole record's command, and their squared
//! errors on the last 25 % are compared by the one-sided paired Diebold–Mariano test
//! ([`diebold_mariano`]) at 5 %, with the relative MSE gain beside it.
//!
//! The true effect's model per class:
//!
//! * friction: [`fit_friction`] from the baseline; on a position (a mass on a spring) as a
//!   plant that does not integrate (the velocity the output's change); on a motor's speed
//!   both that way and as the increments of an integrating plant (the velocity the output
//!   itself, which is where the truth's friction acts; that fit minimises the error of the
//!   speed's sum, and its speed is the simulated position's change), the one with the
//!   smaller error on the first part kept;
//! * play between: [`fit_two_mass_skipping`] from the baseline's poles, the hold left out of
//!   the error (the library's two-mass model starts at rest at zero speed, the record turning
//!   at `u_min`'s speed: scored from the start, the model's start-up transient, the largest
//!   error of the record, pulls the fit away from the truth; it settles within the hold);
//! * input play: [`fit_hysteresis`] of the play operator from the baseline (its two knots:
//!   a play on a straight line, which is the truth's);
//! * end stop: the baseline's simulation clamped at the level that fits the first part best
//!   (the least squares over the upper quantiles of the measured output, 75 % to 100 %);
//!   the linear part is then refitted [`IMPUTATIONS`] times on the first part with the
//!   samples at or above the level, where the simulation goes beyond them, replaced by the
//!   simulation (the pinned samples say only that the output was there or higher), and the
//!   level found again.
//!
//! When the baseline or the effect's fit fails, the diagnosis's own candidate for the
//! expected effect (a step's or a rejected proposal's inner hold-out gain and p-value)
//! decides, if the diagnosis proposed it; else the run is not resolvable and the reason is
//! kept.

use super::class::Class;
use super::design::HOLD;
use super::dm::{diebold_mariano, lags_for};
use super::generate::{Data, quantile};
use super::mass::Output;
use super::servo::Mechanics;
use hsid_host::choose::{Choices, Horizons, linear_model};
use hsid_host::diagnose::Diagnosis;
use hsid_host::friction::{FrictionOptions, Initial, fit_friction};
use hsid_host::hysteresis::{ElementFitOptions, Start, fit_hysteresis};
use hsid_host::identify::HostModel;
use hsid_host::model::MemoryElement;
use hsid_host::sandwich::{TwoMassOptions, fit_two_mass_skipping};

/// The share of the samples after the hold that fit.
pub const FIT_SHARE: f64 = 0.75;
/// The test's level.
pub const LEVEL: f64 = 0.05;
/// Refits of the end stop's linear part on the record with its pinned samples filled in.
pub const IMPUTATIONS: usize = 3;

/// How resolvability was decided.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    /// No effect to resolve (clean).
    NotApplicable,
    /// By the family's own fits and test.
    Fit,
    /// By the diagnosis's candidate of the expected effect (the family's fit failed).
    Candidate,
    /// Neither could decide: not resolvable.
    Undecided,
}

/// The verdict and its numbers.
#[derive(Clone, Debug, PartialEq)]
pub struct Resolvability {
    /// How it was decided.
    pub method: Method,
    /// Resolvable: the effect's model lowers the hold-out MSE significantly (one-sided p <
    /// [`LEVEL`]).
    pub resolvable: bool,
    /// Relative reduction of the hold-out MSE, `1 − MSE_effect / MSE_baseline`.
    pub gain: f64,
    /// The test's one-sided p-value.
    pub p: f64,
    /// What went wrong, or the fitted setting.
    pub note: String,
    /// Wall time of the check, ms.
    pub millis: u128,
}

impl Resolvability {
    fn none(method: Method, note: String) -> Self {
        Self {
            method,
            resolvable: false,
            gain: f64::NAN,
            p: f64::NAN,
            note,
            millis: 0,
        }
    }

    /// `yes (gain 34 %, p 0.002)`, `no (…)`, `-` for clean.
    pub fn describe(&self) -> String {
        match self.method {
            Method::NotApplicable => "-".into(),
            Method::Undecided => format!("no (undecided: {})", self.note),
            m => format!(
                "{} (gain {:.0} %, p {:.3}{}{})",
                if self.resolvable { "yes" } else { "no" },
                100.0 * self.gain,
                self.p,
                if m == Method::Candidate {
                    ", diagnosis's candidate"
                } else {
                    ""
                },
                if self.note.is_empty() {
                    String::new()
                } else {
                    format!("; {}", self.note)
                }
            ),
        }
    }
}

/// The hold-out gain and p-value of `effect` against `base`, both simulated over the whole
/// record, on samples `cut..`.
pub fn compare(y: &[f64], base: &[f64], effect: &[f64], cut: usize) -> (f64, f64) {
    let loss = |sim: &[f64]| -> Vec<f64> {
        y[cut..]
            .iter()
            .zip(&sim[cut..])
            .map(|(a, b)| (a - b) * (a - b))
            .collect()
    };
    let (l0, l1) = (loss(base), loss(effect));
    let mean = |l: &[f64]| l.iter().sum::<f64>() / l.len().max(1) as f64;
    let gain = 1.0 - mean(&l1) / mean(&l0);
    let (_, p) = diebold_mariano(&l0, &l1, lags_for(l0.len()));
    (gain, p)
}

/// The level `L` minimising `Σ (min(ŷ, L) − y)²` over `range`, among the measured output's
/// quantiles 75 % … 100 % (step 0.25 %).
pub fn pinned_level(y: &[f64], sim: &[f64], range: std::ops::Range<usize>) -> f64 {
    let ys = &y[range.clone()];
    (0..=100)
        .map(|i| quantile(ys, 0.75 + 0.0025 * i as f64))
        .map(|l| {
            let sse: f64 = range.clone().map(|t| (sim[t].min(l) - y[t]).powi(2)).sum();
            (sse, l)
        })
        .min_by(|a, b| a.0.partial_cmp(&b.0).unwrap_or(std::cmp::Ordering::Equal))
        .map_or(f64::INFINITY, |(_, l)| l)
}

/// Mean squared error of `sim` against `y` over `range`.
fn mse_on(y: &[f64], sim: &[f64], range: std::ops::Range<usize>) -> f64 {
    let n = range.len().max(1) as f64;
    range.map(|t| (y[t] - sim[t]).powi(2)).sum::<f64>() / n
}

/// The friction model's simulation of the whole record, fitted on `..cut`: on the output's
/// change, or (`increments`) on the output itself as an integrating plant's increments, its
/// speed then the simulated position's change.
fn friction_simulation(
    u: &[f64],
    y: &[f64],
    cut: usize,
    base: &HostModel,
    increments: bool,
) -> Result<(Vec<f64>, String), String> {
    let f = fit_friction(
        &u[..cut],
        &y[..cut],
        &[],
        base,
        increments,
        &FrictionOptions::default(),
    )
    .map_err(|e| format!("friction fit: {e}"))?;
    let note = format!(
        "F_c {:.3} on the output's {}",
        f.model.friction.coulomb,
        if increments { "value" } else { "change" }
    );
    if !increments {
        return Ok((f.model.simulate(u), note));
    }
    let position = f.model.simulate_from(u, f.initial);
    let before = match f.initial {
        Initial::Moving { position, .. } => position,
        Initial::Rest { .. } => 0.0,
    };
    let speeds = std::iter::once(before)
        .chain(position.iter().copied())
        .collect::<Vec<f64>>()
        .windows(2)
        .map(|w| w[1] - w[0])
        .collect();
    Ok((speeds, note))
}

/// The effect's simulation of the whole record, fitted on `..cut`, or why not.
#[allow(clippy::too_many_arguments)]
fn effect_simulation(
    class: Class,
    u: &[f64],
    y: &[f64],
    cut: usize,
    base: &HostModel,
    base_sim: &[f64],
    speed: bool,
    refit: &dyn Fn(&[f64]) -> Result<HostModel, String>,
) -> Result<(Vec<f64>, String), String> {
    let (uf, yf) = (&u[..cut], &y[..cut]);
    match class {
        Class::Clean => Err("no effect".into()),
        Class::Friction => {
            // On a speed, friction on the output itself (the increments of a position) and
            // on its change; the one that simulates the first part better is kept.
            let kinds: &[bool] = if speed { &[true, false] } else { &[false] };
            let mut best: Option<(f64, Vec<f64>, String)> = None;
            let mut why = String::new();
            for &increments in kinds {
                match friction_simulation(u, y, cut, base, increments) {
                    Ok((sim, note)) => {
                        let mse = mse_on(y, &sim, HOLD..cut);
                        if best.as_ref().is_none_or(|(m, ..)| mse < *m) {
                            best = Some((mse, sim, note));
                        }
                    }
                    Err(e) => why = e,
                }
            }
            best.map(|(_, sim, note)| (sim, note)).ok_or(why)
        }
        Class::PlayBetween => {
            // The library's model starts at rest at zero speed, the record turning at
            // `u_min`'s: the hold, where the model settles, is left out of the error.
            let skip: Vec<bool> = (0..cut).map(|t| t < HOLD).collect();
            let f = fit_two_mass_skipping(uf, yf, &skip, &base.poles(), &TwoMassOptions::default())
                .map_err(|e| format!("two-mass fit: {e}"))?;
            Ok((f.simulate(u), format!("gap {:.3}", f.gap())))
        }
        Class::InputPlay => {
            let f = fit_hysteresis(
                uf,
                yf,
                base,
                Start::Static,
                &ElementFitOptions::new(MemoryElement::Play),
            )
            .map_err(|e| format!("play fit: {e}"))?;
            Ok((f.simulate(u), String::new()))
        }
        Class::EndStop => {
            let mut sim = base_sim.to_vec();
            let mut l = pinned_level(y, &sim, HOLD..cut);
            for _ in 0..IMPUTATIONS {
                let filled: Vec<f64> = (0..cut)
                    .map(|t| {
                        if t >= HOLD && y[t] >= l && sim[t] > y[t] {
                            sim[t]
                        } else {
                            y[t]
                        }
                    })
                    .collect();
                sim = refit(&filled)?.simulate(u);
                l = pinned_level(y, &sim, HOLD..cut);
            }
            Ok((
                sim.iter().map(|v| v.min(l)).collect(),
                format!("level {l:.4}"),
            ))
        }
    }
}

/// The diagnosis's own candidate of the class's effect: a step's or a rejected proposal's
/// inner hold-out gain and p-value.
fn candidate(class: Class, d: Option<&Diagnosis>, why: String) -> Resolvability {
    let effect = class.effect();
    let found = d.and_then(|d| {
        let e = effect?;
        d.steps
            .iter()
            .find(|s| s.effect == e)
            .map(|s| (s.inner_gain, s.inner_p))
            .or_else(|| {
                d.rejected
                    .iter()
                    .find(|r| r.effect == e)
                    .map(|r| (r.inner_gain, r.inner_p))
            })
    });
    match found {
        Some((gain, p)) => Resolvability {
            method: Method::Candidate,
            resolvable: p < LEVEL && gain > 0.0,
            gain,
            p,
            note: why,
            millis: 0,
        },
        None => Resolvability::none(
            Method::Undecided,
            format!("{why}; the diagnosis proposed no candidate of it"),
        ),
    }
}

/// Decides whether the run's true effect is resolvable (see the [module](self)).
pub fn resolvability(data: &Data, class: Class, diagnosis: Option<&Diagnosis>) -> Resolvability {
    if class == Class::Clean {
        return Resolvability::none(Method::NotApplicable, String::new());
    }
    let clock = std::time::Instant::now();
    let (u, y) = (&data.record.u, &data.record.y);
    let n = u.len();
    let cut = HOLD + ((n - HOLD) as f64 * FIT_SHARE).round() as usize;
    let choices = Choices {
        horizons: Horizons::Given,
        window: None,
        ..Choices::default()
    };
    let speed = matches!(
        &data.truth.design.servo.mechanics,
        Mechanics::Mass(m) if m.output == Output::Velocity
    );
    let fit = |y_fit: &[f64]| -> Result<HostModel, String> {
        linear_model(&u[..cut], y_fit, &data.options.identify, &choices)
            .map(|b| b.model)
            .map_err(|e| format!("linear baseline: {e}"))
    };
    let mut out = match fit(&y[..cut]) {
        Err(e) => candidate(class, diagnosis, e),
        Ok(base) => {
            let base_sim = base.simulate(u);
            match effect_simulation(class, u, y, cut, &base, &base_sim, speed, &fit) {
                Err(why) => candidate(class, diagnosis, why),
                Ok((sim, note)) => {
                    let (gain, p) = compare(y, &base_sim, &sim, cut);
                    Resolvability {
                        method: Method::Fit,
                        resolvable: p < LEVEL && gain > 0.0,
                        gain,
                        p,
                        note,
                        millis: 0,
                    }
                }
            }
        }
    };
    out.millis = clock.elapsed().as_millis();
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_clamp_level_is_found_where_the_output_is_pinned() {
        let sim: Vec<f64> = (0..3000).map(|t| (t as f64 * 0.05).sin()).collect();
        let y: Vec<f64> = sim.iter().map(|v| v.min(0.7)).collect();
        let l = pinned_level(&y, &sim, 0..1000);
        assert!((l - 0.7).abs() < 1e-12, "{l}");
        let clamped: Vec<f64> = sim.iter().map(|v| v.min(l)).collect();
        let (gain, p) = compare(&y, &sim, &clamped, 1000);
        assert!(gain > 0.99 && p < 0.05, "{gain} {p}");
    }
}
