//! The two-mass model fitted by simulation error from the current model.
//!
//! **Start.** The current model (linear, or with an element at the input) has put the
//! record's dynamics into the poles of its `G`; they are split between the two-mass model's
//! parts. Its slowest real pole `z₀` is the rigid-body mode, both masses turning together:
//! `β_m = β_l = −ln z₀` (the rigid-body rate `(β_m + r β_l)/(1 + r)` is then `−ln z₀`). Each
//! complex pair `z` is a candidate shaft resonance `ω = |ln z|` with damping
//! `ζ = −ln|z|/ω`; and since the current model may have none (a first-order model, or an
//! over-damped fit of a record the play dominates) the resonance is also tried at 0.1, 0.3
//! and 1 rad per sample with `ζ = 0.3`. For each resonance the inertia ratio `r` is tried at
//! 0.5, 1.5 and 4, which gives `k = ω² r/(1 + r)` and `c = 2ζω r/(1 + r)`; the gain `g` and
//! the torque offset `b` are the least-squares ones with the teeth in contact (`α = 0`, where
//! the output is linear in `g` and `b`).
//!
//! **Search.** The error is far from quadratic in the play: a play of the wrong size puts
//! every contact at the wrong sample. So the play is not left to the iteration from a guess.
//! (1) Each start above is fitted with the play held at 0 ([`SCREEN_ITERATIONS`]
//! iterations): the two-mass model in contact, a linear model of the structure. (2) From the
//! starts of the [`LINEAR_KEPT`] best, one per resonance (the best starts of one resonance
//! differ in the inertia ratio alone and lead into one valley; and the fit in contact may
//! have let the shaft go slack, where the play no longer acts, so its own parameters are no
//! start for the play), the play
//! is held at each point of a grid of half-widths from 1 to 1024 times the output's RMS (the
//! angle the motor turns in 1 to 1024 samples at a typical speed), a factor `√2` apart, and
//! the other parameters are fitted ([`PROFILE_ITERATIONS`] iterations): the error's profile
//! in the play. (3) The [`FINALISTS`] best points of the grid and the best fit in contact get
//! the full budget on every parameter, and the smallest error is kept.
//!
//! **Fit.** Levenberg–Marquardt ([`crate::numerics::lm`], [`Settings::simulation_fit`]) on
//! the simulation error of the motor's speed, parameters as in
//! [`TwoMassPlay::theta`](super::model::TwoMassPlay::theta), forward-difference Jacobians
//! (the simulation is continuous in every parameter; the dead zone's kink and the shaft
//! damping's switch at contact are crossed by a difference step only at the few samples
//! within the step of them, as for the element fit in [`crate::hysteresis::fit`]), steps
//! refused where the fixed-step integration is not well inside its stability region. The
//! difference steps are `10⁻⁴` (relative; the element fit's are `10⁻⁶`): the simulator
//! splits a step where the teeth meet or part, but the crossing is located by interpolation,
//! and what is left of the step's share of the shaft damping's switch is a roughness of the
//! error far below the noise that a `10⁻⁶` quotient could read as the slope.

use super::error::SandwichError;
use super::model::{HALF_WIDTH, PARAMETERS, Start, TORQUE_OFFSET, TwoMassPlay};
use super::uncertainty::{Uncertainty, uncertainty};
use crate::identify::HostModel;
use crate::numerics::lm::{self, Jacobian, Minimum, Problem, Settings};
use crate::numerics::poly::eigenvalues;
use crate::numerics::rms;

/// Iterations every start gets with the play held at 0.
pub const SCREEN_ITERATIONS: usize = 15;

/// Fits in contact whose play is searched on the grid.
pub const LINEAR_KEPT: usize = 3;

/// Iterations at each point of the play's grid, the play held.
pub const PROFILE_ITERATIONS: usize = 6;

/// Points of the play's grid that get the full iteration budget.
pub const FINALISTS: usize = 3;

/// Factors `(f, g)` by which the resonance (`k` by `f²`, `c` by `f`) and the damping ratio
/// (`c` by `g`) of the best fit are moved, to look into the valleys beside its own.
const RESONANCE_STEPS: [(f64, f64); 6] = [
    (0.5, 1.0),
    (0.7, 1.0),
    (1.4, 1.0),
    (2.0, 1.0),
    (1.0, 0.5),
    (1.0, 2.0),
];

/// Rounds of moving the resonance (each kept only if the full fit from it is better).
const RESONANCE_ROUNDS: usize = 2;

/// How much smaller the steady start's least `Σe²` in contact must be than the rest start's
/// for the fit to start in the steady state of the first input.
const STEADY_BETTER: f64 = 0.8;

/// The inertia ratios `r` of the start.
const RATIOS: [f64; 3] = [0.5, 1.5, 4.0];

/// The play's grid: half-widths of `√2^i` times the output's RMS, `i < GRID`.
const GRID: i32 = 21;

/// Resonances (rad per sample) tried beside the current model's.
const RESONANCES: [f64; 3] = [0.1, 0.3, 1.0];

/// The difference steps, in multiples of the shared solver's `10⁻⁶` of a parameter's size.
const DIFFERENCE_SCALE: f64 = 100.0;

/// Samples the fit needs per parameter at least.
const SAMPLES_PER_PARAMETER: usize = 20;

/// Settings of the fit.
#[derive(Clone, Debug, PartialEq)]
pub struct TwoMassOptions {
    /// Iteration limit of Levenberg–Marquardt for the finalists.
    pub max_iter: usize,
    /// Runge–Kutta steps per sample of the model's simulator.
    pub substeps: usize,
}

impl Default for TwoMassOptions {
    /// 60 iterations, 10 steps per sample.
    fn default() -> Self {
        Self {
            max_iter: 60,
            substeps: 10,
        }
    }
}

/// The fitted model and how the fit went.
#[derive(Clone, Debug, PartialEq)]
pub struct TwoMassFit {
    /// The model.
    pub model: TwoMassPlay,
    /// `Σe²` of the best start (before any iteration).
    pub initial_cost: f64,
    /// `Σe²` at the optimum.
    pub cost: f64,
    /// Starts tried.
    pub starts: usize,
    /// Iterations of the kept finalist.
    pub iterations: usize,
    /// Standard deviations (`None` when `JᵀJ` is singular at the optimum).
    pub uncertainty: Option<Uncertainty>,
}

impl TwoMassFit {
    /// The play `2α` (the model's angle units).
    pub fn gap(&self) -> f64 {
        self.model.gap()
    }

    /// The play's standard deviation, when known.
    pub fn gap_std(&self) -> Option<f64> {
        self.uncertainty.as_ref().map(|u| u.gap)
    }

    /// The simulated output for an input record.
    pub fn simulate(&self, u: &[f64]) -> Vec<f64> {
        self.model.simulate(u)
    }

    /// The drive in words, in seconds and the output's unit when they are known (the play in
    /// the output's unit × s: rad for a speed in rad/s), else per sample.
    pub fn describe(&self, ts: Option<f64>, output_unit: Option<&str>) -> String {
        let std = self
            .gap_std()
            .map_or(String::new(), |s| format!(" (std {})", Self::per(s, ts)));
        let unit = output_unit.map_or(String::new(), |u| format!(" {u}"));
        let (rate, play_unit) = match ts {
            Some(t) => (
                format!("{:.1} rad/s", self.model.resonance() / t),
                format!("{unit} × s"),
            ),
            None => (
                format!("{:.4} rad/sample", self.model.resonance()),
                format!("{unit} × samples"),
            ),
        };
        format!(
            "play {}{std}{play_unit} between motor and load, load/motor inertia {:.3}, shaft resonance {rate}, rigid-body pole {:.5}",
            Self::per(self.gap(), ts),
            self.model.inertia_ratio,
            self.model.rigid_body_pole(),
        )
    }

    /// An angle in the model's units (output × samples) in output × s when `ts` is known.
    fn per(x: f64, ts: Option<f64>) -> String {
        format!("{:.4e}", ts.map_or(x, |t| x * t))
    }
}

/// Refuses records the fit cannot use.
fn check(u: &[f64], y: &[f64], opts: &TwoMassOptions) -> Result<(), SandwichError> {
    if u.len() != y.len() {
        return Err(SandwichError::LengthMismatch {
            u: u.len(),
            y: y.len(),
        });
    }
    let need = SAMPLES_PER_PARAMETER * PARAMETERS;
    if u.len() < need {
        return Err(SandwichError::TooFewSamples {
            have: u.len(),
            need,
        });
    }
    for (signal, x) in [("u", u), ("y", y)] {
        if let Some(index) = x.iter().position(|v| !v.is_finite()) {
            return Err(SandwichError::NonFinite { signal, index });
        }
        let first = x.first().copied().unwrap_or(0.0);
        if x.iter().all(|&v| v == first) {
            return Err(SandwichError::Constant(if signal == "u" {
                "input"
            } else {
                "output"
            }));
        }
    }
    if opts.substeps == 0 {
        return Err(SandwichError::NoSubsteps);
    }
    Ok(())
}

/// The resonances `(ω, ζ)` and the rigid-body rate of discrete poles `(re, im)`.
pub fn split_poles(poles: &[(f64, f64)]) -> (Vec<(f64, f64)>, f64) {
    let rate = |(re, im): (f64, f64)| -(re.hypot(im).max(1e-12)).ln();
    let rigid = poles
        .iter()
        .filter(|(re, im)| im.abs() < 1e-9 && *re > 0.0 && *re < 1.0)
        .map(|&p| rate(p))
        .fold(f64::INFINITY, f64::min);
    let rigid = if rigid.is_finite() {
        rigid
    } else {
        poles
            .iter()
            .map(|&p| rate(p))
            .filter(|r| *r > 0.0)
            .fold(f64::INFINITY, f64::min)
    };
    let rigid = if rigid.is_finite() { rigid } else { 1e-3 };
    let mut resonances: Vec<(f64, f64)> = poles
        .iter()
        .filter(|(_, im)| *im > 1e-9)
        .map(|&(re, im)| {
            let sigma = rate((re, im));
            let omega = sigma.hypot(im.atan2(re));
            (omega, (sigma / omega).clamp(0.01, 0.9))
        })
        .collect();
    resonances.extend(RESONANCES.iter().map(|&w| (w, 0.3)));
    (resonances, rigid.max(1e-6))
}

/// The shaft's resonance `√(k (1 + r)/r)` of a parameter vector (at least [`HALF_WIDTH`]
/// entries: `ln k` at 2, `ln r` at 4).
fn start_resonance(th: &[f64]) -> f64 {
    let (k, r) = (th[2].exp(), th[4].exp());
    (k * (1.0 + r) / r).sqrt()
}

/// The starting parameter vectors in contact (`α = 0`) from the poles (see the module), each
/// with its `Σe²`, the simulations starting as `start` says.
fn starts(
    u: &[f64],
    y: &[f64],
    kept: &dyn Fn(usize) -> bool,
    poles: &[(f64, f64)],
    substeps: usize,
    start: Start,
) -> Vec<(Vec<f64>, f64)> {
    let (resonances, rigid) = split_poles(poles);
    let mut out = Vec::new();
    for &(omega, zeta) in &resonances {
        for &r in &RATIOS {
            let contact = TwoMassPlay {
                gain: 1.0,
                motor_damping: rigid,
                stiffness: omega * omega * r / (1.0 + r),
                shaft_damping: 2.0 * zeta * omega * r / (1.0 + r),
                inertia_ratio: r,
                load_damping: rigid,
                torque_offset: 0.0,
                half_width: 0.0,
                substeps,
                start,
            };
            if !contact.integrable() {
                continue;
            }
            // In contact the model is linear: its output is `g` times the response to `u`
            // plus `b` times the response to a unit torque.
            let unit = contact.simulate(u);
            let constant = TwoMassPlay {
                gain: 0.0,
                torque_offset: 1.0,
                ..contact.clone()
            }
            .simulate(u);
            let rows = || {
                (0..y.len())
                    .filter(|&t| kept(t))
                    .map(|t| (unit[t], constant[t], y[t]))
            };
            let (mut aa, mut ab, mut bb, mut ay, mut by) = (0.0, 0.0, 0.0, 0.0, 0.0);
            for (a, b, v) in rows() {
                (aa, ab, bb, ay, by) = (aa + a * a, ab + a * b, bb + b * b, ay + a * v, by + b * v);
            }
            let det = aa * bb - ab * ab;
            let (gain, torque_offset) = if det > 1e-12 * aa * bb {
                ((ay * bb - by * ab) / det, (aa * by - ab * ay) / det)
            } else {
                (ay / aa, 0.0)
            };
            let cost: f64 = rows()
                .map(|(a, b, v)| (gain * a + torque_offset * b - v).powi(2))
                .sum();
            if gain.is_finite() && gain != 0.0 && torque_offset.is_finite() && cost.is_finite() {
                out.push((
                    TwoMassPlay {
                        gain,
                        torque_offset,
                        ..contact
                    }
                    .theta(),
                    cost,
                ));
            }
        }
    }
    out
}

/// Fits the two-mass model with play to `(u, y)` (`y` the motor's speed) from the poles of
/// the current model's `G`.
pub fn fit_two_mass(
    u: &[f64],
    y: &[f64],
    current: &HostModel,
    opts: &TwoMassOptions,
) -> Result<TwoMassFit, SandwichError> {
    let poles = eigenvalues(current.a.clone()).unwrap_or_default();
    fit_two_mass_from_poles(u, y, &poles, opts)
}

/// [`fit_two_mass`] from discrete poles `(re, im)` of any current model.
pub fn fit_two_mass_from_poles(
    u: &[f64],
    y: &[f64],
    poles: &[(f64, f64)],
    opts: &TwoMassOptions,
) -> Result<TwoMassFit, SandwichError> {
    fit_two_mass_skipping(u, y, &[], poles, opts)
}

/// [`fit_two_mass_from_poles`] with the samples `t` where `skip[t]` left out of the error
/// (the input drives the simulation through them: a held-out block, outliers); `skip` empty
/// or of the record's length.
pub fn fit_two_mass_skipping(
    u: &[f64],
    y: &[f64],
    skip: &[bool],
    poles: &[(f64, f64)],
    opts: &TwoMassOptions,
) -> Result<TwoMassFit, SandwichError> {
    check(u, y, opts)?;
    if !skip.is_empty() && skip.len() != y.len() {
        return Err(SandwichError::LengthMismatch {
            u: y.len(),
            y: skip.len(),
        });
    }
    let kept = |t: usize| !skip.get(t).copied().unwrap_or(false);
    let substeps = opts.substeps;
    // From rest, unless the steady state of the first input (a record that starts in a hold)
    // explains the record clearly better in contact, by the starts' least squares: with the
    // torque offset free the steady start can mimic rest (`b = −g u(0)`) at the price of a
    // bias everywhere after, so a near tie stays at rest.
    let least = |c: &[(Vec<f64>, f64)]| c.iter().map(|p| p.1).fold(f64::INFINITY, f64::min);
    let (rest, steady) = (
        starts(u, y, &kept, poles, substeps, Start::Rest),
        starts(u, y, &kept, poles, substeps, Start::Steady),
    );
    let (start, candidates) = if least(&steady) < STEADY_BETTER * least(&rest) {
        (Start::Steady, steady)
    } else {
        (Start::Rest, rest)
    };
    let candidates: Vec<Vec<f64>> = candidates.into_iter().map(|p| p.0).collect();
    let residual = |th: &[f64]| -> Option<Vec<f64>> {
        let m = TwoMassPlay::from_theta(th, substeps, start)?;
        let r: Vec<f64> = m
            .simulate(u)
            .iter()
            .zip(y)
            .enumerate()
            .map(|(t, (a, b))| if kept(t) { a - b } else { 0.0 })
            .collect();
        r.iter().all(|v| v.is_finite()).then_some(r)
    };
    let admissible =
        |th: &[f64]| TwoMassPlay::from_theta(th, substeps, start).is_some_and(|m| m.integrable());
    let sse = |r: &[f64]| r.iter().map(|v| v * v).sum::<f64>();
    let gain_size = candidates
        .first()
        .map_or(1.0, |t| t[0].abs())
        .max(f64::MIN_POSITIVE);
    let y_rms = rms(y).max(f64::MIN_POSITIVE);
    // Difference steps of `10⁻⁶ · typical`: 10⁻⁴ of the gain, 10⁻⁴ in the logarithms and
    // 10⁻⁴ of the output's RMS × 100 in the play (see the module on the contact's switch).
    let mut typical = vec![DIFFERENCE_SCALE; PARAMETERS];
    typical[0] = DIFFERENCE_SCALE * gain_size;
    typical[TORQUE_OFFSET] = DIFFERENCE_SCALE * gain_size * rms(u).max(f64::MIN_POSITIVE);
    typical[HALF_WIDTH] = DIFFERENCE_SCALE * y_rms;
    let problem = Problem {
        residual: &residual,
        admissible: &admissible,
        jacobian: Jacobian::ForwardDifference { typical: &typical },
    };
    // (1) In contact: the play held at 0.
    let with_play = |th: &[f64], alpha: f64| {
        let mut t = th.to_vec();
        t.push(alpha);
        t
    };
    // The other parameters fitted from `from` with the play held at `alpha`.
    let fit_held = |alpha: f64, from: &[f64], iterations: usize| -> Option<Minimum> {
        let residual_at = |th: &[f64]| residual(&with_play(th, alpha));
        let admissible_at = |th: &[f64]| admissible(&with_play(th, alpha));
        let held = Problem {
            residual: &residual_at,
            admissible: &admissible_at,
            jacobian: Jacobian::ForwardDifference {
                typical: &typical[..HALF_WIDTH],
            },
        };
        lm::minimise(&held, from, &Settings::simulation_fit(iterations)).ok()
    };
    let residual_contact = |th: &[f64]| residual(&with_play(th, 0.0));
    let admissible_contact = |th: &[f64]| admissible(&with_play(th, 0.0));
    let contact = Problem {
        residual: &residual_contact,
        admissible: &admissible_contact,
        jacobian: Jacobian::ForwardDifference {
            typical: &typical[..HALF_WIDTH],
        },
    };
    let mut initial_cost = f64::INFINITY;
    let mut in_contact: Vec<(Minimum, &[f64])> = Vec::new();
    let mut failure = None;
    for th in &candidates {
        let th = &th[..HALF_WIDTH];
        let Some(r0) = residual_contact(th) else {
            continue;
        };
        initial_cost = initial_cost.min(sse(&r0));
        match lm::minimise(&contact, th, &Settings::simulation_fit(SCREEN_ITERATIONS)) {
            Ok(m) => in_contact.push((m, th)),
            Err(e) => failure = Some(e),
        }
    }
    if in_contact.is_empty() {
        return Err(failure.map_or(SandwichError::NoStart, SandwichError::from));
    }
    in_contact.sort_by(|a, b| sse(&a.0.residual).total_cmp(&sse(&b.0.residual)));
    // (2) The play on its grid, the other parameters refitted at each point, from the best
    // start of each of the LINEAR_KEPT best resonances (the best starts of one resonance
    // differ only in the inertia ratio and lead to one valley).
    let mut kept: Vec<&[f64]> = Vec::new();
    for (_, from) in &in_contact {
        if kept.len() == LINEAR_KEPT {
            break;
        }
        if !kept
            .iter()
            .any(|k| (start_resonance(k) / start_resonance(from) - 1.0).abs() < 1e-6)
        {
            kept.push(from);
        }
    }
    let mut grid: Vec<(f64, Vec<f64>)> = Vec::new();
    for from in kept {
        for i in 0..GRID {
            let alpha = y_rms * std::f64::consts::SQRT_2.powi(i);
            if let Some(m) = fit_held(alpha, from, PROFILE_ITERATIONS) {
                grid.push((sse(&m.residual), with_play(&m.theta, alpha)));
            }
        }
    }
    grid.sort_by(|a, b| a.0.total_cmp(&b.0));
    // (3) Every parameter from the best points and the best fit in contact.
    let finalists = grid
        .into_iter()
        .take(FINALISTS)
        .map(|(_, th)| th)
        .chain(in_contact.first().map(|(m, _)| with_play(&m.theta, 0.0)));
    let mut best: Option<Minimum> = None;
    for start in finalists {
        let m = match lm::minimise(&problem, &start, &Settings::simulation_fit(opts.max_iter)) {
            Ok(m) => m,
            Err(e) => {
                failure = Some(e);
                continue;
            }
        };
        if best
            .as_ref()
            .is_none_or(|b| sse(&m.residual) < sse(&b.residual))
        {
            best = Some(m);
        }
    }
    let mut best = best.ok_or(failure.map_or(SandwichError::NoStart, SandwichError::from))?;
    // (4) The shaft's resonance and damping moved by the factors of RESONANCE_STEPS, the play
    // held, the best of them fitted in full: the error has a valley per resonance, and the
    // grid's starts are a factor √3 or more apart.
    for _ in 0..RESONANCE_ROUNDS {
        let alpha = best.theta[HALF_WIDTH];
        let moved = RESONANCE_STEPS
            .iter()
            .filter_map(|&(f, g): &(f64, f64)| {
                let mut th = best.theta[..HALF_WIDTH].to_vec();
                th[2] += 2.0 * f.ln();
                th[3] += (f * g).ln();
                fit_held(alpha, &th, PROFILE_ITERATIONS)
            })
            .min_by(|a, b| sse(&a.residual).total_cmp(&sse(&b.residual)));
        let Some(moved) = moved else { break };
        let start = with_play(&moved.theta, alpha);
        match lm::minimise(&problem, &start, &Settings::simulation_fit(opts.max_iter)) {
            Ok(m) if sse(&m.residual) < sse(&best.residual) * (1.0 - 1e-9) => best = m,
            _ => break,
        }
    }
    let model =
        TwoMassPlay::from_theta(&best.theta, substeps, start).ok_or(SandwichError::NoStart)?;
    Ok(TwoMassFit {
        uncertainty: uncertainty(&problem, &best.theta, &best.residual, &typical),
        model,
        initial_cost,
        cost: sse(&best.residual),
        starts: candidates.len(),
        iterations: best.iterations,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Records the fit cannot use are refused with the reason, before any simulation.
    #[test]
    fn unusable_records_are_refused() {
        let opts = TwoMassOptions::default();
        let poles = [(0.99, 0.0)];
        let u: Vec<f64> = (0..400).map(|t| (t as f64 * 0.05).sin()).collect();
        let y: Vec<f64> = u.iter().map(|v| 0.5 * v).collect();
        let fit = |u: &[f64], y: &[f64], o: &TwoMassOptions| {
            fit_two_mass_from_poles(u, y, &poles, o).map(|_| ())
        };
        assert_eq!(
            fit(&u, &y[..399], &opts),
            Err(SandwichError::LengthMismatch { u: 400, y: 399 })
        );
        assert_eq!(
            fit(&u[..100], &y[..100], &opts),
            Err(SandwichError::TooFewSamples {
                have: 100,
                need: SAMPLES_PER_PARAMETER * PARAMETERS
            })
        );
        let mut bad = y.clone();
        bad[7] = f64::NAN;
        assert_eq!(
            fit(&u, &bad, &opts),
            Err(SandwichError::NonFinite {
                signal: "y",
                index: 7
            })
        );
        assert_eq!(
            fit(&u, &vec![1.0; 400], &opts),
            Err(SandwichError::Constant("output"))
        );
        let none = TwoMassOptions {
            substeps: 0,
            ..opts
        };
        assert_eq!(fit(&u, &y, &none), Err(SandwichError::NoSubsteps));
    }

    /// The current model's slowest real pole is the rigid-body rate; a complex pair is a
    /// resonance, tried beside the fixed ones.
    #[test]
    fn poles_are_split_into_rigid_body_and_resonance() {
        let z = (-0.05f64).exp();
        let (re, im) = (z * 0.2f64.cos(), z * 0.2f64.sin());
        let (res, rigid) = split_poles(&[(0.998, 0.0), (0.5, 0.0), (re, im), (re, -im)]);
        assert!((rigid - -(0.998f64.ln())).abs() < 1e-12, "{rigid}");
        let omega = 0.05f64.hypot(0.2);
        assert!((res[0].0 - omega).abs() < 1e-9, "{res:?}");
        assert!((res[0].1 - 0.05 / omega).abs() < 1e-9, "{res:?}");
        assert_eq!(res.len(), 1 + RESONANCES.len());
    }
}
