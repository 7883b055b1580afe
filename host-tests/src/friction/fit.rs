//! The friction model fitted by simulation error from an identified model.
//!
//! **Start.** The friction enters `G` through its input, so a regression of the output on its
//! own past, the element's past output and the friction regressors `tanh(v(t − 1)/v_s)` and
//! `1` gives `G`, `F_c` and `F_0` at once for a fixed `v_s` (equation error, as an ARX fit
//! starts an output-error one). It is run for `v_s` at 0.3 %, 1 %, 3 %, 10 % and 30 % of the
//! velocity's RMS, with the velocity `v` from the measured output and from the identified
//! model's simulation (where the noise is as large as a sample's motion, the measured
//! velocity's sign is noise near every stop and the regression reads a fraction of the
//! force); each stable result, and the identified model with the friction of that regression
//! (the ratio of the friction's coefficients to `G`'s gain), is simulated and the better of
//! the two kept. Beside them, the identified model with a grid of Coulomb forces (3 %, 10 %,
//! 20 % and 35 % of the element output's RMS) at 0.3 % and 3 %, and the identified model without
//! friction. Every start is minimised for a few iterations and the three with the smallest
//! error then to the end (a start's own error does not tell which valley it lies in: on a
//! mass on a spring at 30 dB the regressions all start in the valley of half the force); the
//! smallest error is kept, so the fit never ends worse than the model it extends.
//!
//! **Element.** The element of the identified model was fitted without friction, and where
//! the output is a speed its borders took up what they could of it (in the steady state
//! Coulomb friction on a speed is a static jump of the force where the speed changes sign):
//! held in the fit, that element leaves the friction a fraction of its force. The fit is run
//! from the identified element and from the straight line that fits the element's output
//! over the record best, and the smaller error kept (on a motor's speed behind an actuator,
//! with a static element of four segments: the hold-out error 24 % under the model's from the
//! identified element, 92 % from the line).
//!
//! **Delay.** The element's output may reach the drive a sample or two late (a computation
//! or amplifier delay; a sampled rigid body whose position lags its velocity by a sample looks
//! the same): each delay `d = 0, 1, 2` is fitted and the smallest error kept.
//!
//! **Fit.** Levenberg–Marquardt ([`crate::numerics::lm`]) on `F`, `B` (strictly proper, any
//! gain), `F_c`, `ln(v_s − 1.01 |b₁ F_c|)` (the scale's excess over the floor, so that no step
//! crosses it) and `F_0`, with forward-difference Jacobians and steps refused
//! when `F` is not stable. The error is the simulation error of the output, for an integrating
//! plant of the position (the sum of the increments the record holds): a drift of the
//! position is what an integrating model gets wrong first, and the benchmark protocols of
//! positioning drives score it. Samples in `skip` are left out of the error but not of the
//! simulation (an inner hold-out).

use nalgebra::{DMatrix, DVector};

use super::evidence::{change_from_rest, per_sample_change};
use super::model::{
    Friction, FrictionModel, Initial, Polynomials, START_SAMPLES, StartState, accelerating_start,
    delayed, run, start_state,
};
use crate::identify::HostModel;
use crate::numerics::lm::{self, Jacobian, LmFailure, Problem, Settings, minimise};
use crate::numerics::lstsq::{Scaling, lstsq};
use crate::numerics::poly::spectral_radius;

/// The velocity scales of the start, as fractions of the velocity's RMS.
const SCALES: [f64; 5] = [0.003, 0.01, 0.03, 0.1, 0.3];

/// The Coulomb forces of the grid of starts, as fractions of the element output's RMS.
const COULOMB_GRID: [f64; 4] = [0.03, 0.1, 0.2, 0.35];

/// The velocity scales of the grid of starts, as fractions of the velocity's RMS.
const GRID_SCALES: [f64; 2] = [0.003, 0.03];

/// Iterations each start is minimised for before the best [`FINISHED`] are minimised to the
/// end.
const BRIEF_ITERATIONS: usize = 8;

/// Starts minimised to the end: those with the smallest error after [`BRIEF_ITERATIONS`].
const FINISHED: usize = 3;

/// Samples the fit needs per parameter at least.
const SAMPLES_PER_PARAMETER: usize = 10;

/// Why [`fit_friction`] gave no model.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FrictionError {
    /// Too few samples for the parameters.
    #[error(
        "the friction fit needs at least {needed} samples for its {parameters} parameters, the record has {samples}"
    )]
    TooShort {
        /// Samples in the record.
        samples: usize,
        /// Samples needed.
        needed: usize,
        /// Parameters of the model.
        parameters: usize,
    },
    /// Input, output and skip lengths differ.
    #[error("the friction fit was given {u} inputs, {y} outputs and {skip} skip flags")]
    Lengths {
        /// Inputs.
        u: usize,
        /// Outputs.
        y: usize,
        /// Skip flags (0: none).
        skip: usize,
    },
    /// The output does not move: no velocity to act on.
    #[error("the output does not change: there is no velocity for friction to act on")]
    NoMotion,
    /// The identified model does not simulate the record.
    #[error("the identified model does not simulate the record (a non-finite output)")]
    StartDoesNotSimulate,
    /// The minimisation failed.
    #[error("the friction fit: {0}")]
    Minimise(#[from] LmFailure),
}

/// What [`fit_friction`] gives.
#[derive(Clone, Debug, PartialEq)]
pub struct FrictionFit {
    /// The fitted model (`G(1) = 1`, borders and friction scaled with it).
    pub model: FrictionModel,
    /// Where its simulation of the record starts: for an integrating plant the position
    /// (relative to the record's first sample) and velocity fitted with it.
    pub initial: Initial,
    /// Sum of squared simulation errors (the samples scored) of the identified model.
    pub sse_identified: f64,
    /// The same of the fitted model.
    pub sse: f64,
    /// Samples scored.
    pub scored: usize,
    /// Iterations of the minimisation.
    pub iterations: usize,
    /// The relative decrease of the last step when the iteration limit ended the fit.
    pub unconverged: Option<f64>,
}

/// Settings of [`fit_friction`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrictionOptions {
    /// Jacobians computed at most.
    pub iterations: usize,
    /// The output of a plant that does not integrate is a speed (a motor's): the friction
    /// acts on its sign, not on the sign of its change ([`Friction::speed`]).
    pub speed: bool,
}

impl Default for FrictionOptions {
    /// 60 iterations, the output a position.
    fn default() -> Self {
        Self {
            iterations: 60,
            speed: false,
        }
    }
}

/// Fits friction on the velocity of `start` (an identified model; its element is kept) to
/// the record `(u, y)` as identified (for an integrating plant, `integrating`, the record of
/// its increments: `y` holds `y(t) − y(t − 1)`), leaving the samples where `skip` is set out
/// of the error (an empty `skip` leaves none out). See the [module](self).
pub fn fit_friction(
    u: &[f64],
    y: &[f64],
    skip: &[bool],
    start: &HostModel,
    integrating: bool,
    opts: &FrictionOptions,
) -> Result<FrictionFit, FrictionError> {
    if u.len() != y.len() || !(skip.is_empty() || skip.len() == y.len()) {
        return Err(FrictionError::Lengths {
            u: u.len(),
            y: y.len(),
            skip: skip.len(),
        });
    }
    let n = start.order.max(1);
    let parameters = 2 * n + 3;
    let needed = SAMPLES_PER_PARAMETER * parameters + n + 2;
    if y.len() < needed {
        return Err(FrictionError::TooShort {
            samples: y.len(),
            needed,
            parameters,
        });
    }
    let given = fit_element(u, y, skip, start, integrating, opts);
    let u_start = start_input(u, start, integrating);
    let Some(line) = straightened(start, u, u_start) else {
        return given;
    };
    let lined = fit_element(u, y, skip, &line, integrating, opts);
    match (given, lined) {
        (Ok(g), Ok(l)) if l.sse < g.sse => Ok(FrictionFit {
            sse_identified: g.sse_identified,
            ..l
        }),
        (Ok(g), _) => Ok(g),
        (Err(_), Ok(l)) => Ok(l),
        (Err(e), Err(_)) => Err(e),
    }
}

/// The input before the record, where the simulation starts (as
/// [`FrictionModel::simulate_from`] starts it): an integrating plant moving at its first input,
/// any other at rest at `u_min`.
fn start_input(u: &[f64], start: &HostModel, integrating: bool) -> f64 {
    match integrating {
        true => u.first().copied().unwrap_or(0.0),
        false => start.u_min(),
    }
}

/// `model` with its element replaced by the straight line that best fits the element's
/// output over the record's input `u` (least squares of `h(t)` on `u(t)` and 1; `u_start`
/// the input before the record): the element a friction fit also starts from. `None` when
/// the element is a line already (within 10⁻⁹ of its spread) or the input does not vary.
fn straightened(model: &HostModel, u: &[f64], u_start: f64) -> Option<HostModel> {
    use crate::validation::stats::{mean, variance};
    let h = model.element_output_from(u, u_start);
    let (um, hm) = (mean(u), mean(&h));
    let sxx: f64 = u.iter().map(|a| (a - um) * (a - um)).sum();
    let sxy: f64 = u.iter().zip(&h).map(|(a, b)| (a - um) * (b - hm)).sum();
    if !(sxx > 0.0 && sxx.is_finite() && sxy.is_finite()) {
        return None;
    }
    let slope = sxy / sxx;
    let at = |k: &f64| slope * k + (hm - slope * um);
    let spread = variance(&h).sqrt();
    let off = |knots: &[f64], borders: &[f64]| {
        knots
            .iter()
            .zip(borders)
            .fold(0.0f64, |m, (k, b)| m.max((at(k) - b).abs()))
    };
    let bent =
        off(&model.knots_asc, &model.border_asc).max(off(&model.knots_desc, &model.border_desc));
    if bent <= 1e-9 * spread.max(f64::MIN_POSITIVE) {
        return None;
    }
    let mut line = model.clone();
    line.border_asc = model.knots_asc.iter().map(at).collect();
    line.border_desc = model.knots_desc.iter().map(at).collect();
    line.mu0 = at(&model.u_min());
    Some(line)
}

/// [`fit_friction`] with the element of `start` held (the record's lengths checked).
fn fit_element(
    u: &[f64],
    y: &[f64],
    skip: &[bool],
    start: &HostModel,
    integrating: bool,
    opts: &FrictionOptions,
) -> Result<FrictionFit, FrictionError> {
    let skipped = |t: usize| skip.get(t).copied().unwrap_or(false);
    let scored = (0..y.len()).filter(|&t| !skipped(t)).count();
    // The target: the output, or the position of an integrating plant (its increments summed).
    let target: Vec<f64> = match integrating {
        true => crate::integrating::integrate(y, 0.0),
        false => y.to_vec(),
    };
    let on_output = integrating || opts.speed;
    let velocity: Vec<f64> = match on_output {
        true => y.to_vec(),
        false => change_from_rest(y),
    };
    let v_rms = crate::numerics::rms(&velocity);
    if !(v_rms > 0.0 && v_rms.is_finite()) {
        return Err(FrictionError::NoMotion);
    }
    let u_start = start_input(u, start, integrating);
    let h_raw = start.element_output_from(u, u_start);
    let h0 = start.element_output_from(&[u_start], u_start)[0];
    // An integrating plant's start is read off the record's first samples (a parabola through
    // them), as a simulation of the model is started ([`FrictionModel::initial_from`], `hsid
    // validate --initial-samples`), and held: fitted with the model over the whole record, the
    // start's position is an offset of every later sample and absorbs the drift the model
    // should explain (on EMPS the fit then read a mass 4 % and a viscous friction 10 % off the
    // valley it finds from the record's start, and simulated the test record at 85 %).
    let start_at = match integrating {
        true => accelerating_start(&target[..target.len().min(START_SAMPLES)]),
        false => Initial::Rest { u_start },
    };
    let initial = start_state(start_at, h0);
    let sse_of = |sim: &[f64]| -> f64 {
        sim.iter()
            .zip(&target)
            .enumerate()
            .filter(|(t, _)| !skipped(*t))
            .map(|(_, (a, b))| (a - b) * (a - b))
            .sum()
    };
    // The identified model as polynomials, no friction.
    let identified = Polynomials::strictly_proper(start);
    let none = Friction {
        speed: opts.speed,
        ..Friction::none(v_rms * 0.01)
    };
    let sse_identified = sse_of(&run(&identified, &none, &h_raw, integrating, initial));
    if !sse_identified.is_finite() {
        return Err(FrictionError::StartDoesNotSimulate);
    }
    let order = identified.f.len() - 1;
    let mut fitted: Option<(f64, Layout, lm::Minimum)> = None;
    let mut last_error = None;
    for delay in 0..=MAX_DELAY {
        let layout = Layout {
            n: order,
            delay,
            margin: SIGN_MARGINS[0],
            speed: opts.speed,
        };
        let h = delayed(&h_raw, h0, delay);
        match fit_layout(
            &layout,
            &identified,
            &h,
            y,
            &target,
            &velocity,
            initial,
            skip,
            opts,
        ) {
            Ok(min) => {
                let sse: f64 = min.residual.iter().map(|r| r * r).sum();
                if fitted.as_ref().is_none_or(|(best, ..)| sse < *best) {
                    fitted = Some((sse, layout, min));
                }
            }
            Err(e) => last_error = Some(e),
        }
    }
    let Some((sse, layout, min)) = fitted else {
        return Err(last_error.unwrap_or(FrictionError::StartDoesNotSimulate));
    };
    let (g, fr) = layout.at(SIGN_MARGIN).parts(&min.theta);
    Ok(FrictionFit {
        model: FrictionModel::normalised(start, &g, &fr, integrating),
        initial: start_at,
        sse_identified,
        sse,
        scored,
        iterations: min.iterations,
        unconverged: min.unconverged,
    })
}

/// The smallest velocity scale over which the Coulomb force of `fr` may change sign with `G`
/// = `g`: `|b₁ F_c|`, the velocity the force gives in one sample. Over a narrower scale the
/// sampled loop overshoots zero velocity every sample (its gain at zero velocity, `−b₁ F_c /
/// v_s`, passes −1 for a slow `G`) and chatters at standstill, which no continuous drive
/// does: the mean friction of the chatter is not the Coulomb force that holds the drive.
fn sign_limit(g: &Polynomials, fr: &Friction) -> f64 {
    (g.b.get(1).copied().unwrap_or(0.0) * fr.coulomb).abs()
}

/// The floors of the velocity scale the minimisation passes through, as multiples of
/// [`sign_limit`]: a continuation from a smooth sign to the sharpest the sampled loop follows.
/// At the floor every stick and slip of the simulation moves with the parameters and the
/// error surface has a valley at each; over a wider sign it is smooth, and its minimum leads
/// into the deepest (on EMPS every start ends in one valley this way; minimised at the floor
/// at once, the starts end in valleys whose errors differ by up to 74 %).
const SIGN_MARGINS: [f64; 4] = [30.0, 10.0, 3.0, 1.01];

/// How far above [`sign_limit`] a fitted velocity scale stays at least: the last of
/// [`SIGN_MARGINS`].
const SIGN_MARGIN: f64 = SIGN_MARGINS[SIGN_MARGINS.len() - 1];

/// The smallest excess of a start's velocity scale over its floor (the stage's margin times
/// [`sign_limit`]), as a share of the scale: a start on or below the floor has a finite
/// logarithm.
const MIN_EXCESS: f64 = 1e-3;

/// `fr` with its velocity scale raised just above [`sign_limit`] where it is below.
fn smoothed(g: &Polynomials, fr: Friction) -> Friction {
    Friction {
        velocity_scale: fr.velocity_scale.max(SIGN_MARGIN * sign_limit(g, &fr)),
        ..fr
    }
}

/// The largest extra delay of the element's output tried.
const MAX_DELAY: usize = 2;

/// The start and the minimisation for one layout (order and delay), `h` the element's
/// output delayed by it.
#[allow(clippy::too_many_arguments)]
fn fit_layout(
    layout: &Layout,
    identified: &Polynomials,
    h: &[f64],
    y: &[f64],
    target: &[f64],
    velocity: &[f64],
    initial: StartState,
    skip: &[bool],
    opts: &FrictionOptions,
) -> Result<lm::Minimum, FrictionError> {
    let integrating = matches!(initial, StartState::Moving { .. });
    let on_output = integrating || layout.speed;
    let skipped = |t: usize| skip.get(t).copied().unwrap_or(false);
    let sse_of = |sim: &[f64]| -> f64 {
        sim.iter()
            .zip(target)
            .enumerate()
            .filter(|(t, _)| !skipped(*t))
            .map(|(_, (a, b))| (a - b) * (a - b))
            .sum()
    };
    let v_rms = crate::numerics::rms(velocity);
    // Beyond half the velocity's RMS the smoothed sign is a line over the record's velocities:
    // viscous friction, which `G` holds, not Coulomb friction.
    let v_max = 0.5 * v_rms;
    let order = layout.n;
    let none = Friction {
        delay: layout.delay,
        speed: layout.speed,
        ..Friction::none(v_rms * 0.01)
    };
    let sse0 = sse_of(&run(identified, &none, h, integrating, initial));
    // One start per velocity scale (the better of the regression's model and the identified
    // one with the regression's friction), and the identified model without friction.
    let mut starts: Vec<(f64, Vec<f64>)> = Vec::new();
    if sse0.is_finite() {
        starts.push((sse0, layout.theta(identified, &none)));
    }
    // The regression's velocity: the measured one, and the identified model's simulated one
    // (noise-free: where measurement noise is as large as a sample's motion, the measured
    // velocity's sign is noise near every stop and the regression reads a fraction of the
    // Coulomb force, as errors in a regressor do).
    let simulated = run(identified, &none, h, integrating, initial);
    // (The position of an integrating plant starts from 0 before its first sample.)
    let before = match integrating {
        true => 0.0,
        false => simulated.first().copied().unwrap_or(0.0),
    };
    let simulated_velocity = match on_output && !integrating {
        // A speed: the simulated output is the velocity.
        true => simulated.clone(),
        false => per_sample_change(&simulated, before),
    };
    let regressions = SCALES.iter().flat_map(|&k| {
        [velocity, &simulated_velocity[..]]
            .into_iter()
            .map(move |v| (k, v))
    });
    for (k, v) in regressions {
        let vs = k * v_rms;
        let Some((arx, fr)) = equation_error(h, y, v, order, vs) else {
            continue;
        };
        let fr = Friction {
            delay: layout.delay,
            speed: layout.speed,
            ..fr
        };
        // The friction is a force in the element's output units whichever `G` it drives.
        let best = [
            (arx.clone(), smoothed(&arx, fr)),
            (identified.clone(), smoothed(identified, fr)),
        ]
        .into_iter()
        .filter(|(g, _)| spectral_radius(&g.f) < 1.0)
        .map(|(g, fr)| {
            (
                sse_of(&run(&g, &fr, h, integrating, initial)),
                layout.theta(&g, &fr),
            )
        })
        .filter(|(sse, _)| sse.is_finite())
        .min_by(|a, b| a.0.total_cmp(&b.0));
        starts.extend(best);
    }
    // A grid of Coulomb forces on the identified `G` beside the regressions: where the
    // output's noise is as large as a sample's motion both regressions read a fraction of the
    // force (errors in a regressor), and the simulation error has a valley at each.
    let h_spread = crate::numerics::rms(h);
    for c in COULOMB_GRID {
        for k in GRID_SCALES {
            let fr = Friction {
                coulomb: c * h_spread,
                velocity_scale: k * v_rms,
                offset: 0.0,
                delay: layout.delay,
                speed: layout.speed,
            };
            let fr = smoothed(identified, fr);
            let sse = sse_of(&run(identified, &fr, h, integrating, initial));
            if sse.is_finite() {
                starts.push((sse, layout.theta(identified, &fr)));
            }
        }
    }
    if starts.is_empty() {
        return Err(FrictionError::StartDoesNotSimulate);
    }
    let h_rms = crate::numerics::rms(h).max(f64::MIN_POSITIVE);
    let b_size = starts[0].1[order..2 * order]
        .iter()
        .fold(0.0f64, |m, v| m.max(v.abs()))
        .max(1e-12);
    let typical: Vec<f64> = (0..layout.len())
        .map(|j| match layout.role(j) {
            Role::Denominator => 1.0,
            Role::Numerator => b_size,
            Role::Force => h_rms,
            Role::LogScale => 1.0,
        })
        .collect();
    // The simulation error of `th` read with the floor at `margin`.
    let residual_at = |margin: f64, th: &[f64]| -> Option<Vec<f64>> {
        let (g, fr) = layout.at(margin).parts(th);
        let mut r = run(&g, &fr, h, integrating, initial);
        for (t, (a, b)) in r.iter_mut().zip(target).enumerate() {
            *a = if skipped(t) { 0.0 } else { *a - b };
        }
        r.iter().all(|v| v.is_finite()).then_some(r)
    };
    let minimise_at = |margin: f64, theta: &[f64], settings: &Settings| {
        let residual = |th: &[f64]| residual_at(margin, th);
        // The scale is above its floor by construction ([`Layout::parts`]).
        let admissible = |th: &[f64]| {
            let (g, fr) = layout.at(margin).parts(th);
            spectral_radius(&g.f) < 1.0 && fr.velocity_scale <= v_max
        };
        let problem = Problem {
            residual: &residual,
            admissible: &admissible,
            jacobian: Jacobian::ForwardDifference { typical: &typical },
        };
        minimise(&problem, theta, settings)
    };
    // Each start minimised briefly over the widest sign, the best few to the end through the
    // narrower ones ([`SIGN_MARGINS`]): the Coulomb term makes the error surface bumpy, and a
    // start's own error does not say which valley it lies in.
    let sse = |m: &lm::Minimum| m.residual.iter().map(|r| r * r).sum::<f64>();
    let widest = SIGN_MARGINS[0];
    let brief = Settings::simulation_fit(BRIEF_ITERATIONS.min(opts.iterations));
    let mut briefly: Vec<lm::Minimum> = Vec::new();
    let mut failure = None;
    for (_, theta) in &starts {
        match minimise_at(widest, theta, &brief) {
            Ok(min) => briefly.push(min),
            Err(e) => failure = Some(e),
        }
    }
    briefly.sort_by(|a, b| sse(a).total_cmp(&sse(b)));
    briefly.truncate(FINISHED);
    let settings = Settings::simulation_fit(opts.iterations);
    let mut best: Option<lm::Minimum> = None;
    for start in briefly {
        let mut iterations = start.iterations;
        let mut theta = match start.unconverged {
            // Stopped on its own: the end of the widest sign.
            None => start.theta,
            Some(_) => match minimise_at(widest, &start.theta, &settings) {
                Ok(min) if sse(&min) <= sse(&start) => {
                    iterations += min.iterations;
                    min.theta
                }
                Ok(_) => start.theta,
                Err(e) => {
                    failure = Some(e);
                    start.theta
                }
            },
        };
        let mut unconverged = None;
        for &margin in &SIGN_MARGINS[1..] {
            match minimise_at(margin, &theta, &settings) {
                Ok(min) => {
                    iterations += min.iterations;
                    unconverged = min.unconverged;
                    theta = min.theta;
                }
                Err(e) => failure = Some(e),
            }
        }
        // Scored at the floor, where a stage that failed left it.
        let Some(residual) = residual_at(SIGN_MARGIN, &theta) else {
            continue;
        };
        let min = lm::Minimum {
            theta,
            residual,
            iterations,
            unconverged,
        };
        if best.as_ref().is_none_or(|b| sse(&min) < sse(b)) {
            best = Some(min);
        }
    }
    match (best, failure) {
        (Some(min), _) => Ok(min),
        (None, Some(e)) => Err(e.into()),
        (None, None) => Err(FrictionError::StartDoesNotSimulate),
    }
}

/// The parameter vector: `f₁ … f_n`, `b₁ … b_n`, `F_c`, `ln(v_s − m |b₁ F_c|)`, `F_0`; the
/// delay, the margin `m` over the sign's floor and the start fixed.
#[derive(Clone, Copy, Debug)]
struct Layout {
    n: usize,
    delay: usize,
    /// The velocity scale's floor as a multiple of [`sign_limit`] (a stage of
    /// [`SIGN_MARGINS`]).
    margin: f64,
    /// The output is a speed ([`Friction::speed`]).
    speed: bool,
}

/// What a parameter is.
enum Role {
    Denominator,
    Numerator,
    Force,
    LogScale,
}

impl Layout {
    fn len(&self) -> usize {
        2 * self.n + 3
    }

    fn role(&self, j: usize) -> Role {
        let n = self.n;
        if j < n {
            Role::Denominator
        } else if j < 2 * n {
            Role::Numerator
        } else if j == 2 * n + 1 {
            Role::LogScale
        } else {
            Role::Force
        }
    }

    /// The same parameters read with the floor at `margin` ([`SIGN_MARGINS`]): the scale's
    /// excess is kept, so the scale falls with the floor.
    fn at(&self, margin: f64) -> Self {
        Self { margin, ..*self }
    }

    fn theta(&self, g: &Polynomials, fr: &Friction) -> Vec<f64> {
        let n = self.n;
        let mut th = Vec::with_capacity(self.len());
        th.extend_from_slice(&g.f[1..=n]);
        th.extend_from_slice(&g.b[1..=n]);
        th.push(fr.coulomb);
        // The scale's excess over the floor the sampled loop needs, logged: a parameter that
        // cannot cross the floor (a floor imposed by refusing steps holds the minimisation on
        // it, every direction that moves `F_c` or `b₁` refused with the one that would cross).
        let floor = self.margin * sign_limit(g, fr);
        let excess = (fr.velocity_scale - floor).max(MIN_EXCESS * fr.velocity_scale);
        th.push(excess.max(f64::MIN_POSITIVE).ln());
        th.push(fr.offset);
        th
    }

    /// The polynomials and the friction.
    fn parts(&self, th: &[f64]) -> (Polynomials, Friction) {
        let n = self.n;
        let f = std::iter::once(1.0)
            .chain(th[..n].iter().copied())
            .collect();
        let b = std::iter::once(0.0)
            .chain(th[n..2 * n].iter().copied())
            .collect();
        let g = Polynomials { b, f };
        let mut fr = Friction {
            coulomb: th[2 * n],
            velocity_scale: 0.0,
            offset: th[2 * n + 2],
            delay: self.delay,
            speed: self.speed,
        };
        fr.velocity_scale = self.margin * sign_limit(&g, &fr) + th[2 * n + 1].exp();
        (g, fr)
    }
}

/// The equation-error fit of `G` and the friction for the velocity scale `vs`: `s(t)` (the
/// increment or the output) on `−s(t − i)`, `h(t − i)` (`i = 1 … n`), `tanh(v(t − 1)/v_s)`
/// and `1`; the friction's coefficients divided by `−Σ bᵢ`. `None` when the regression is
/// singular or its gain vanishes.
fn equation_error(
    h: &[f64],
    s: &[f64],
    velocity: &[f64],
    n: usize,
    vs: f64,
) -> Option<(Polynomials, Friction)> {
    let rows = s.len().checked_sub(n)?;
    let k = 2 * n + 2;
    let x = DMatrix::from_fn(rows, k, |r, j| {
        let t = r + n;
        if j < n {
            -s[t - 1 - j]
        } else if j < 2 * n {
            h[t - 1 - (j - n)]
        } else if j == 2 * n {
            // The velocity before the input at t − 1 acted.
            (velocity[t - 1] / vs).tanh()
        } else {
            1.0
        }
    });
    let yv = DVector::from_fn(rows, |r, _| s[r + n]);
    let th = lstsq(&x, &yv, Scaling::UnitDiagonal)?;
    let f: Vec<f64> = std::iter::once(1.0)
        .chain(th.iter().take(n).copied())
        .collect();
    let b: Vec<f64> = std::iter::once(0.0)
        .chain(th.iter().skip(n).take(n).copied())
        .collect();
    let gain = b.iter().sum::<f64>();
    if gain.abs() < f64::MIN_POSITIVE || !gain.is_finite() {
        return None;
    }
    let fr = Friction {
        coulomb: -th[2 * n] / gain,
        velocity_scale: vs,
        offset: -th[2 * n + 1] / gain,
        delay: 0,
        speed: false,
    };
    Some((Polynomials { b, f }, fr))
}
