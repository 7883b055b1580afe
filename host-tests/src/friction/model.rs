//! The friction model's parameters and its simulation.

use serde::{Deserialize, Serialize};

use crate::identify::HostModel;
use crate::numerics::poly::{observer_form, tf_from_ss};

/// The friction force `F(v) = F_c · tanh(v / v_s) + F_0`, in the units of the element's
/// output (the signal `G` is driven by), the velocity in output units per sample.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Friction {
    /// `F_c`: the Coulomb level, the force the drive loses while it moves.
    pub coulomb: f64,
    /// `v_s > 0`: the velocity over which the Coulomb force changes sign.
    pub velocity_scale: f64,
    /// `F_0`: a force that does not depend on the velocity (an incline, a cable, a bias).
    pub offset: f64,
    /// Samples the element's output takes to reach the drive (a computation or amplifier
    /// delay before the force acts): `w(t) = H[u(t − d)] − F(v(t))`; the friction acts
    /// without it.
    #[serde(default)]
    pub delay: usize,
    /// `G`'s output is a speed (a motor's): the friction acts on the sign of the output
    /// itself, not of its change per sample. Always so for an integrating plant, whose `G`
    /// gives the velocity (the position its sum).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub speed: bool,
}

impl Friction {
    /// No friction (the velocity scale `velocity_scale` kept for a fit to start from).
    pub(crate) fn none(velocity_scale: f64) -> Self {
        Self {
            coulomb: 0.0,
            velocity_scale,
            offset: 0.0,
            delay: 0,
            speed: false,
        }
    }

    /// Whether the velocity is `G`'s output itself (a speed, or an integrating plant's
    /// increments) rather than its change.
    pub(crate) fn on_output(&self, integrating: bool) -> bool {
        integrating || self.speed
    }

    /// The force at velocity `v`.
    pub fn force(&self, v: f64) -> f64 {
        self.coulomb * (v / self.velocity_scale).tanh() + self.offset
    }

    /// The same friction for an element output scaled by `k`.
    pub(crate) fn scaled(&self, k: f64) -> Self {
        Self {
            coulomb: self.coulomb * k,
            velocity_scale: self.velocity_scale,
            offset: self.offset * k,
            delay: self.delay,
            speed: self.speed,
        }
    }
}

/// Where a simulation starts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Initial {
    /// At rest: the input before the record at this value (for a plant that does not
    /// integrate, `G` in the steady state of the element's output there less the offset; for
    /// an integrating plant, no velocity and the position 0).
    Rest {
        /// The input before the record.
        u_start: f64,
    },
    /// An integrating plant moving: the position before the first sample and the velocity (in
    /// output units per sample) it holds there, `G` in the steady state of that velocity.
    Moving {
        /// `ŷ(−1)`.
        position: f64,
        /// `ŷ(0) − ŷ(−1)` before the first input acts.
        velocity: f64,
    },
}

/// The linear part as the simulation runs it: `G(q) = B(q)/F(q)`, strictly proper
/// (`b[0] = 0`), `f` monic, both of length `n + 1`.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Polynomials {
    pub b: Vec<f64>,
    pub f: Vec<f64>,
}

impl Polynomials {
    /// `G` of `model` made strictly proper: a feed-through moves to the next sample (the
    /// friction loop needs the velocity before the sample's input acts).
    pub fn strictly_proper(model: &HostModel) -> Self {
        let (mut b, f) = tf_from_ss(&model.a, &model.b, &model.c, model.d);
        b.resize(f.len(), 0.0);
        let d = b[0];
        if let Some(b1) = b.get_mut(1) {
            *b1 += d;
        }
        b[0] = 0.0;
        Self { b, f }
    }

    /// `G(1)`.
    pub fn gain(&self) -> f64 {
        self.b.iter().sum::<f64>() / self.f.iter().sum::<f64>()
    }
}

/// A Hammerstein model with friction on its velocity: the element of `plant` (its borders),
/// then `w = H[u] − F(v)` into `G` (the plant's `(A, B, C)`, `D = 0`, `G(1) = 1`), and for an
/// integrating plant the sum of `G`'s output.
#[derive(Clone, Debug, PartialEq)]
pub struct FrictionModel {
    /// The element and `G` (strictly proper, `G(1) = 1`): for an integrating plant its stable
    /// part, as in [`crate::integrating`].
    pub plant: HostModel,
    /// The plant integrates (the output is the sum of `G`'s).
    pub integrating: bool,
    /// The friction on the velocity.
    pub friction: Friction,
}

impl FrictionModel {
    /// The model of `G = b/f` (any gain, `b[0] = 0`) driven by the element of `element` and the
    /// friction `friction` in the units of that element's output: normalised so that
    /// `G(1) = 1`, the element's borders and μ0 and the friction scaled by the gain.
    pub(crate) fn normalised(
        element: &HostModel,
        g: &Polynomials,
        friction: &Friction,
        integrating: bool,
    ) -> Self {
        let k = g.gain();
        let num: Vec<f64> = g.b.iter().map(|v| v / k).collect();
        let (a, b, c, _) = observer_form(&num, &g.f);
        let mut plant = element.clone();
        plant.order = g.f.len() - 1;
        plant.a = a;
        plant.b = b;
        plant.c = c;
        plant.d = 0.0;
        plant.mu0 *= k;
        plant.border_asc.iter_mut().for_each(|v| *v *= k);
        plant.border_desc.iter_mut().for_each(|v| *v *= k);
        Self {
            plant,
            integrating,
            friction: friction.scaled(k),
        }
    }

    /// The identified model `model` as a friction model without friction (its feed-through
    /// moved a sample later, as [`fit_friction`](super::fit_friction) starts from it).
    pub(crate) fn normalised_plain(model: &HostModel, integrating: bool) -> Self {
        let g = Polynomials::strictly_proper(model);
        Self::normalised(model, &g, &Friction::none(1.0), integrating)
    }

    /// `G` as polynomials (the feed-through, zero in a fitted model, is dropped).
    pub(crate) fn polynomials(&self) -> Polynomials {
        let p = &self.plant;
        let (mut b, f) = tf_from_ss(&p.a, &p.b, &p.c, 0.0);
        b.resize(f.len(), 0.0);
        if let Some(b0) = b.first_mut() {
            *b0 = 0.0;
        }
        Polynomials { b, f }
    }

    /// The simulated output for the input `u` from `initial`.
    pub fn simulate_from(&self, u: &[f64], initial: Initial) -> Vec<f64> {
        let u_start = match initial {
            Initial::Rest { u_start } => u_start,
            Initial::Moving { .. } => u.first().copied().unwrap_or(0.0),
        };
        let h0 = self.plant.element_output_from(&[u_start], u_start)[0];
        let h = delayed(
            &self.plant.element_output_from(u, u_start),
            h0,
            self.friction.delay,
        );
        run(
            &self.polynomials(),
            &self.friction,
            &h,
            self.integrating,
            start_state(initial, h0),
        )
    }

    /// The simulated output from rest at `u_min` (the position 0 for an integrating plant).
    pub fn simulate(&self, u: &[f64]) -> Vec<f64> {
        self.simulate_from(
            u,
            Initial::Rest {
                u_start: self.plant.u_min(),
            },
        )
    }
}

/// `h` delayed by `d` samples, `h0` before the record.
pub(crate) fn delayed(h: &[f64], h0: f64, d: usize) -> Vec<f64> {
    let d = d.min(h.len());
    std::iter::repeat_n(h0, d)
        .chain(h[..h.len() - d].iter().copied())
        .collect()
}

/// The first samples of a record an integrating model's start is read from, when it is fitted
/// (and by default when it is validated: the benchmark protocols of positioning drives allow
/// the first 20).
pub const START_SAMPLES: usize = 20;

/// The position before the first sample and the velocity there of the parabola through
/// `y_first` (least squares: a drive that accelerates in those samples, as one starting from
/// rest under a step of force does, biases a line's velocity); a line for fewer than 4.
pub(crate) fn accelerating_start(y_first: &[f64]) -> Initial {
    let n = y_first.len();
    if n < 4 {
        return moving_start(y_first);
    }
    // y(t) = p + v (t + 1) + a (t + 1)² / 2: p, v at t = −1.
    let x = nalgebra::DMatrix::from_fn(n, 3, |t, j| {
        let s = t as f64 + 1.0;
        [1.0, s, 0.5 * s * s][j]
    });
    let yv = nalgebra::DVector::from_column_slice(y_first);
    match crate::numerics::lstsq::lstsq(&x, &yv, crate::numerics::lstsq::Scaling::UnitDiagonal) {
        Some(c) => Initial::Moving {
            position: c[0],
            velocity: c[1] + 0.5 * c[2],
        },
        None => moving_start(y_first),
    }
}

/// The position before the first sample and the velocity of the line through `y_first`.
pub(crate) fn moving_start(y_first: &[f64]) -> Initial {
    let n = y_first.len();
    if n < 2 {
        return Initial::Moving {
            position: y_first.first().copied().unwrap_or(0.0),
            velocity: 0.0,
        };
    }
    let tm = (n as f64 - 1.0) / 2.0;
    let ym = y_first.iter().sum::<f64>() / n as f64;
    let (mut sxy, mut sxx) = (0.0, 0.0);
    for (t, y) in y_first.iter().enumerate() {
        let dt = t as f64 - tm;
        sxy += dt * (y - ym);
        sxx += dt * dt;
    }
    let velocity = sxy / sxx;
    let at_zero = ym - velocity * tm;
    Initial::Moving {
        position: at_zero - velocity,
        velocity,
    }
}

/// The state a simulation starts in: the output before the first sample, `G`'s past outputs
/// and past inputs (all equal: a steady state).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum StartState {
    /// A plant that does not integrate, resting with `G` driven by `w` (the element's output
    /// at the start less the friction at rest).
    Rest {
        /// The element's output at the start.
        h0: f64,
    },
    /// An integrating plant at `position`, moving at `velocity`.
    Moving { position: f64, velocity: f64 },
}

/// The state a simulation from `initial` starts in, `h0` the element's output at rest.
pub(crate) fn start_state(initial: Initial, h0: f64) -> StartState {
    match initial {
        Initial::Rest { .. } => StartState::Rest { h0 },
        Initial::Moving { position, velocity } => StartState::Moving { position, velocity },
    }
}

/// The velocity of a plant that does not integrate resting with the element's output at `h0`:
/// 0 for a position; for a speed (`on_output`) the root of `s = G(1) (h0 − F(s))`, which lies
/// within `G(1) |F_c|` of `G(1) (h0 − F_0)` (the sign's `tanh` is within ±1), found by
/// bisection on that bracket (the function is continuous and changes sign across it).
fn steady_velocity(g: &Polynomials, friction: &Friction, h0: f64, on_output: bool) -> f64 {
    if !on_output {
        return 0.0;
    }
    let k = g.gain();
    let centre = k * (h0 - friction.offset);
    let reach = (k * friction.coulomb).abs();
    let excess = |s: f64| s - k * (h0 - friction.force(s));
    let (mut lo, mut hi) = (centre - reach, centre + reach);
    if !(lo.is_finite() && hi.is_finite()) || reach == 0.0 {
        return centre;
    }
    for _ in 0..80 {
        let mid = 0.5 * (lo + hi);
        if excess(mid) > 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    0.5 * (lo + hi)
}

/// The simulation: `s(t) = −Σ f_i s(t−i) + Σ b_i w(t−i)`, the velocity `v(t)` (`s(t)` for an
/// integrating plant or a speed, `s(t) − s(t − 1)` otherwise), `w(t) = h(t) − F(v(t))`, and the output
/// `s(t)` or its running sum.
pub(crate) fn run(
    g: &Polynomials,
    friction: &Friction,
    h: &[f64],
    integrating: bool,
    start: StartState,
) -> Vec<f64> {
    let n = g.f.len() - 1;
    let on_output = friction.on_output(integrating);
    let (mut s_past, mut w_past, mut position) = match start {
        StartState::Rest { h0 } => {
            // A plant that integrates, started at rest, holds no velocity: G's state is zero.
            if integrating {
                (vec![0.0; n], vec![0.0; n], 0.0)
            } else {
                let w0 = h0 - friction.force(steady_velocity(g, friction, h0, on_output));
                (vec![g.gain() * w0; n], vec![w0; n], 0.0)
            }
        }
        StartState::Moving { position, velocity } => {
            let w0 = velocity / g.gain();
            let w0 = if w0.is_finite() { w0 } else { 0.0 };
            (vec![velocity; n], vec![w0; n], position)
        }
    };
    let mut out = Vec::with_capacity(h.len());
    for &ht in h {
        let mut s = 0.0;
        for i in 0..n {
            s += g.b[i + 1] * w_past[i] - g.f[i + 1] * s_past[i];
        }
        let v = match on_output {
            true => s,
            false => s - s_past.first().copied().unwrap_or(s),
        };
        let w = ht - friction.force(v);
        if n > 0 {
            s_past.rotate_right(1);
            w_past.rotate_right(1);
            s_past[0] = s;
            w_past[0] = w;
        }
        let y = match integrating {
            true => {
                position += s;
                position
            }
            false => s,
        };
        out.push(y);
    }
    out
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    /// A rigid body `m v̇ = f − F_v v − F_c sign(v)` by forward Euler, written apart.
    #[test]
    fn an_integrating_model_moves_like_a_mass_with_coulomb_friction() {
        let (ts, m, fv, fc) = (1e-3, 2.0, 4.0, 1.5);
        let a = 1.0 - ts * fv / m;
        // Increments per sample: s(t+1) = a s(t) + (ts²/m) f(t).
        let g = Polynomials {
            b: vec![0.0, ts * ts / m],
            f: vec![1.0, -a],
        };
        let fr = Friction {
            coulomb: fc,
            velocity_scale: 1e-9,
            offset: 0.0,
            delay: 0,
            speed: false,
        };
        let force: Vec<f64> = (0..6000)
            .map(|t| if t < 4000 { 5.0 } else { -5.0 })
            .collect();
        let y = run(
            &g,
            &fr,
            &force,
            true,
            StartState::Moving {
                position: 0.0,
                velocity: 0.0,
            },
        );
        // The body's own Euler steps, position then velocity.
        let (mut p, mut v) = (0.0f64, 0.0f64);
        // The force of a sample acts on the velocity after it.
        for (t, f) in force.iter().enumerate() {
            p += v * ts;
            assert!(
                (y[t] - p).abs() < 1e-9 + 1e-6 * p.abs(),
                "t {t}: {} vs {p}",
                y[t]
            );
            let sign = if v > 0.0 {
                1.0
            } else if v < 0.0 {
                -1.0
            } else {
                0.0
            };
            v += ts / m * (f - fv * v - fc * sign);
        }
        // Terminal velocity (5 − 1.5)/4 per second before the reversal.
        let vt = (y[3999] - y[3998]) / ts;
        assert!((vt - 3.5 / 4.0).abs() < 0.02, "{vt}");
    }

    #[test]
    fn a_parabola_through_the_first_samples_gives_the_start_of_an_accelerating_drive() {
        // From rest at 0.3 under a constant acceleration of 0.004 per sample²: the position
        // before the first sample and the increment to the first.
        let y: Vec<f64> = (0..20)
            .map(|t| {
                let s = t as f64 + 1.0;
                0.3 + 0.002 * s * s
            })
            .collect();
        let Initial::Moving { position, velocity } = accelerating_start(&y) else {
            unreachable!()
        };
        assert!((position - 0.3).abs() < 1e-12, "{position}");
        assert!((velocity - (y[0] - 0.3)).abs() < 1e-12, "{velocity}");
        // A line through the same samples reads a mean velocity ten times as large.
        let Initial::Moving { velocity: line, .. } = moving_start(&y) else {
            unreachable!()
        };
        assert!(line > 9.0 * velocity, "{line} {velocity}");
    }

    #[test]
    fn a_line_through_the_first_samples_gives_the_moving_start() {
        let y: Vec<f64> = (0..20).map(|t| 0.5 + 0.01 * t as f64).collect();
        let start = moving_start(&y);
        let Initial::Moving { position, velocity } = start else {
            unreachable!("{start:?}");
        };
        assert!((velocity - 0.01).abs() < 1e-12);
        assert!((position - 0.49).abs() < 1e-12);
    }
}
