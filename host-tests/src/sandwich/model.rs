//! The two-mass model with play between motor and load, and its simulator.
//!
//! Two first-order parts, the motor's speed `ω_m` and the load's speed `ω_l`, coupled by a
//! shaft that transmits a torque only once the angle between them, `Δ = θ_m − θ_l`, has
//! crossed the play:
//!
//! ```text
//! ω̇_m = g u + b − T − β_m ω_m
//! ω̇_l = T / r − β_l ω_l
//! Δ̇   = ω_m − ω_l
//! T   = k dz(Δ, α) + c (ω_m − ω_l) [|Δ| > α]
//! ```
//!
//! with `dz(Δ, α) = Δ − α sign(Δ)` outside `[−α, α]` and 0 inside (the dead zone of
//! half-width `α`, the gear play's half) and the output `y = ω_m`, the motor's speed as it is
//! measured. Every quantity is per motor inertia (`g = K/J_m`, `k = k_s/J_m`, …), `r` is the
//! load's inertia over the motor's, and time is counted in samples, so the angles are in the
//! output's unit times one sample: `θ_m(t) = Σ ω_m`. The scale is fixed by the output itself
//! (the speed is measured, and the angle is its sum), so `α` is identifiable in those units; a
//! physical play of `α_phys` rad with a speed in rad/s sampled at `T_s` s is `α = α_phys / T_s`
//! here.
//!
//! **Why a dead zone on the difference of two states rather than a play operator between two
//! transfer functions.** The measured motor speed sits *upstream* of the play: the load's
//! reaction torque acts back on the motor whenever the teeth are in contact, and not at all
//! in the gap. A cascade `G1 → play → G2` feeds nothing back, so its output downstream of the
//! play cannot be the motor's speed; and where the motor side is fast the cascade collapses
//! to the input backlash the project already fits. The two parts here are the two LTI blocks
//! of the cascade (each a first-order speed with its integrated angle) with the play placed
//! where the physics puts it, between their angles. Where the shaft is stiff and the load
//! light the play operator is its limit (the load follows `play(θ_m)`).
//!
//! The simulator holds `u` over each sample (zero-order hold) and integrates the three states
//! with [`TwoMassPlay::substeps`] classical Runge–Kutta steps per sample, a step split where
//! the teeth meet or part; `y(t)` is `ω_m` at
//! the start of sample `t`, before `u(t)` acts (strictly proper). It starts as
//! [`TwoMassPlay::start`] says ([`Start`]): at rest with the teeth in the middle of the play
//! (`Δ = 0`), for a record that starts from standstill whatever its first input; or in the
//! steady state of its first input ([`TwoMassPlay::steady_state`]), both parts turning
//! together at the speed that input holds and the shaft twisted by the torque that carries the
//! load, for a record that starts in a hold. The fit chooses it on the record.

/// How a simulation starts.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Start {
    /// At rest, the teeth in the middle of the play.
    Rest,
    /// In the steady state of the first input.
    Steady,
}

/// The model's parameters (see the module's equations).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct TwoMassPlay {
    /// `g`: the input's gain on the motor's acceleration (output units per sample per input
    /// unit).
    pub gain: f64,
    /// `β_m`: the motor's viscous damping, per sample.
    pub motor_damping: f64,
    /// `k`: the shaft's stiffness per motor inertia, per sample².
    pub stiffness: f64,
    /// `c`: the shaft's damping per motor inertia, per sample.
    pub shaft_damping: f64,
    /// `r = J_l / J_m`.
    pub inertia_ratio: f64,
    /// `β_l`: the load's viscous damping, per sample.
    pub load_damping: f64,
    /// `b`: a constant torque on the motor, per motor inertia (output units per sample): the
    /// input's offset from the motor's zero torque, times `g` (a drive whose input is not
    /// zero at rest, or a static element's offset in front of it).
    pub torque_offset: f64,
    /// `α ≥ 0`: the play's half-width, in output units × samples (the motor's angle as the
    /// sum of its measured speed).
    pub half_width: f64,
    /// Runge–Kutta steps per sample.
    pub substeps: usize,
    /// How its simulations start.
    pub start: Start,
}

/// The parameter vector of the fit: `g`, `ln β_m`, `ln k`, `ln c`, `ln r`, `ln β_l`, `b`, `α`.
pub const PARAMETERS: usize = 8;

/// Index of `b` in the parameter vector.
pub const TORQUE_OFFSET: usize = 6;

/// Index of `α` in the parameter vector.
pub const HALF_WIDTH: usize = 7;

/// Where the teeth are: `−1` in contact on the negative side (`Δ < −α`), `0` in the play,
/// `+1` in contact on the positive side.
fn side(d: f64, alpha: f64) -> i8 {
    if d > alpha {
        1
    } else if d < -alpha {
        -1
    } else {
        0
    }
}

/// The shaft's torque (per motor inertia) at angle `d` and relative speed `dv`, the teeth on
/// `side` (held over an integration step, so that the right-hand side is smooth within it).
fn shaft(side: i8, d: f64, dv: f64, alpha: f64, k: f64, c: f64) -> f64 {
    match side {
        0 => 0.0,
        s => k * (d - f64::from(s) * alpha) + c * dv,
    }
}

impl TwoMassPlay {
    /// The play, `2α`, in the model's angle units.
    pub fn gap(&self) -> f64 {
        2.0 * self.half_width
    }

    /// The parameter vector (see [`PARAMETERS`]); positive parameters by their logarithm.
    pub fn theta(&self) -> Vec<f64> {
        vec![
            self.gain,
            self.motor_damping.ln(),
            self.stiffness.ln(),
            self.shaft_damping.ln(),
            self.inertia_ratio.ln(),
            self.load_damping.ln(),
            self.torque_offset,
            self.half_width,
        ]
    }

    /// The model of a parameter vector (see [`PARAMETERS`]); `α` is taken by its magnitude.
    /// `None` unless `theta` has [`PARAMETERS`] entries.
    pub fn from_theta(theta: &[f64], substeps: usize, start: Start) -> Option<Self> {
        match *theta {
            [gain, bm, k, c, r, bl, b, alpha] => Some(Self {
                gain,
                motor_damping: bm.exp(),
                stiffness: k.exp(),
                shaft_damping: c.exp(),
                inertia_ratio: r.exp(),
                load_damping: bl.exp(),
                torque_offset: b,
                half_width: alpha.abs(),
                substeps,
                start,
            }),
            _ => None,
        }
    }

    /// The shaft's resonance with the teeth in contact, `√(k (1 + r)/r)`, in rad per sample.
    pub fn resonance(&self) -> f64 {
        (self.stiffness * (1.0 + self.inertia_ratio) / self.inertia_ratio).sqrt()
    }

    /// The discrete pole of the rigid-body mode with the teeth in contact,
    /// `exp(−(β_m + r β_l)/(1 + r))`: the slowest decay of the motor's speed (the shaft's
    /// resonance decays at least as fast).
    pub fn rigid_body_pole(&self) -> f64 {
        let r = self.inertia_ratio;
        (-(self.motor_damping + r * self.load_damping) / (1.0 + r)).exp()
    }

    /// The steady state `(Δ, ω_m, ω_l)` under a constant input `u`: both parts at
    /// `ω = (g u + b)/(β_m + r β_l)`, the shaft carrying the load's damping torque
    /// `T = r β_l ω` with the twist `Δ = T/k + α sign(T)` (the teeth in contact on the side
    /// that drives the load; `Δ = 0`, the middle of the play, without a torque).
    pub fn steady_state(&self, u: f64) -> [f64; 3] {
        let r = self.inertia_ratio;
        let w = (self.gain * u + self.torque_offset) / (self.motor_damping + r * self.load_damping);
        let t = r * self.load_damping * w;
        let d = if t == 0.0 {
            0.0
        } else {
            t / self.stiffness + self.half_width * t.signum()
        };
        if [w, d].iter().all(|v| v.is_finite()) {
            [d, w, w]
        } else {
            [0.0; 3]
        }
    }

    /// Whether the fixed-step integration is well inside its stability region: the fastest
    /// rate (resonance, shaft and viscous damping) times the step below 1.5 (classical
    /// Runge–Kutta is stable to about 2.8), finite parameters and at least one step.
    pub fn integrable(&self) -> bool {
        let h = 1.0 / self.substeps.max(1) as f64;
        let r = self.inertia_ratio;
        let fastest = self
            .resonance()
            .max(self.shaft_damping * (1.0 + r) / r)
            .max(self.motor_damping)
            .max(self.load_damping);
        self.substeps > 0
            && [
                self.gain,
                self.motor_damping,
                self.stiffness,
                self.shaft_damping,
                r,
                self.load_damping,
                self.torque_offset,
                self.half_width,
            ]
            .iter()
            .all(|v| v.is_finite())
            && fastest * h < 1.5
    }

    /// The derivative of `(Δ, ω_m, ω_l)` under input `u` with the teeth on `side`.
    fn derivative(&self, x: [f64; 3], u: f64, side: i8) -> [f64; 3] {
        let [d, wm, wl] = x;
        let t = shaft(
            side,
            d,
            wm - wl,
            self.half_width,
            self.stiffness,
            self.shaft_damping,
        );
        [
            wm - wl,
            self.gain * u + self.torque_offset - t - self.motor_damping * wm,
            t / self.inertia_ratio - self.load_damping * wl,
        ]
    }

    /// One classical Runge–Kutta step of length `h` with the teeth held on `side`.
    fn rk4(&self, x: [f64; 3], u: f64, side: i8, h: f64) -> [f64; 3] {
        let add =
            |x: [f64; 3], k: [f64; 3], s: f64| [x[0] + s * k[0], x[1] + s * k[1], x[2] + s * k[2]];
        let k1 = self.derivative(x, u, side);
        let k2 = self.derivative(add(x, k1, h / 2.0), u, side);
        let k3 = self.derivative(add(x, k2, h / 2.0), u, side);
        let k4 = self.derivative(add(x, k3, h), u, side);
        let mut out = x;
        for i in 0..3 {
            out[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
        }
        out
    }

    /// One integration step of length `h`. Where the teeth change side within it, the step
    /// is split where `Δ` reaches the border (`±α`, by linear interpolation of `Δ` over the
    /// step), each part integrated with its own side: the simulation then moves smoothly with
    /// the parameters instead of by a step's share of the switch.
    fn step(&self, x: [f64; 3], u: f64, h: f64) -> [f64; 3] {
        let alpha = self.half_width;
        let before = side(x[0], alpha);
        let trial = self.rk4(x, u, before, h);
        let after = side(trial[0], alpha);
        if after == before {
            return trial;
        }
        // The border crossed: leaving a contact its own, entering one the new side's.
        let border = if before != 0 {
            f64::from(before) * alpha
        } else {
            f64::from(after) * alpha
        };
        let span = trial[0] - x[0];
        let frac = if span != 0.0 {
            ((border - x[0]) / span).clamp(0.0, 1.0)
        } else {
            1.0
        };
        let mut mid = self.rk4(x, u, before, frac * h);
        mid[0] = border;
        let next = if after != 0 && before != 0 { 0 } else { after };
        self.rk4(mid, u, next, (1.0 - frac) * h)
    }

    /// The motor's speed for the input record (see the module's sampling convention).
    pub fn simulate(&self, u: &[f64]) -> Vec<f64> {
        let h = 1.0 / self.substeps.max(1) as f64;
        let mut x = match self.start {
            Start::Rest => [0.0; 3],
            Start::Steady => self.steady_state(u.first().copied().unwrap_or(0.0)),
        };
        let mut y = Vec::with_capacity(u.len());
        for &ut in u {
            y.push(x[1]);
            for _ in 0..self.substeps.max(1) {
                x = self.step(x, ut, h);
            }
        }
        y
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn model(alpha: f64) -> TwoMassPlay {
        TwoMassPlay {
            gain: 1e-3,
            motor_damping: 2e-3,
            stiffness: 0.045,
            shaft_damping: 0.03,
            inertia_ratio: 1.0,
            load_damping: 2e-3,
            torque_offset: 0.0,
            half_width: alpha,
            substeps: 10,
            start: Start::Rest,
        }
    }

    /// In steady state both masses turn together: `ω = g u / (β_m + r β_l)`.
    #[test]
    fn steady_speed_is_the_rigid_body_gain() {
        let m = model(5.0);
        // From rest (a first input of 0), then a unit input.
        let mut u = vec![1.0; 20_000];
        u[0] = 0.0;
        let y = m.simulate(&u);
        assert_eq!(y[0], 0.0);
        let want = 1e-3 / (2e-3 + 2e-3);
        let last = y.last().copied().unwrap_or(f64::NAN);
        assert!((last - want).abs() < 1e-3 * want, "{last} vs {want}");
    }

    /// The start for a first input held is that input's equilibrium: the simulation stays at
    /// it (the speed and the twist that the dynamics reach from rest), with the torque offset
    /// and the play.
    #[test]
    fn the_steady_state_of_the_first_input_is_an_equilibrium() {
        let m = TwoMassPlay {
            torque_offset: -2e-4,
            start: Start::Steady,
            ..model(5.0)
        };
        let y = m.simulate(&[0.7; 3000]);
        let want = (0.7e-3 - 2e-4) / (2e-3 + 2e-3);
        assert!((y[0] - want).abs() < 1e-12, "{} vs {want}", y[0]);
        let drift = y.iter().map(|v| (v - want).abs()).fold(0.0, f64::max);
        assert!(drift < 1e-9 * want, "{drift}");
        // From rest the same input settles at the same speed.
        let mut u = vec![0.7; 20_000];
        u[0] = 2e-4 / 1e-3;
        let from_rest = m.simulate(&u);
        assert_eq!(from_rest[0], 0.0);
        let last = from_rest.last().copied().unwrap_or(f64::NAN);
        assert!((last - want).abs() < 1e-3 * want, "{last} vs {want}");
    }

    /// Inside the play the motor accelerates alone (`ω̇_m ≈ g u`); in contact it carries the
    /// load too: `g/(1 + r) e^{−p t}` with the rigid-body rate `p = (β_m + r β_l)/(1 + r)`, once
    /// the shaft's resonance has died out (3.7e-4 at sample 150).
    #[test]
    fn the_motor_runs_free_inside_the_play() {
        // From rest (a first input of 0), the unit input from sample 1 on.
        let step = |n: usize| {
            let mut u = vec![1.0; n + 1];
            u[0] = 0.0;
            u
        };
        let m = model(50.0);
        let y = m.simulate(&step(40));
        let free = y[11] - y[10];
        assert!((free - 1e-3).abs() < 5e-5, "{free}");
        let rigid = model(0.0).simulate(&step(200));
        let carried = rigid[152] - rigid[151];
        let want = 0.5e-3 * (-0.002f64 * 150.0).exp();
        assert!((carried - want).abs() < 0.05 * want, "{carried} vs {want}");
    }

    #[test]
    fn theta_round_trip() {
        let m = model(3.0);
        let back = TwoMassPlay::from_theta(&m.theta(), 10, Start::Rest);
        let ok = back.is_some_and(|b| {
            b.theta()
                .iter()
                .zip(m.theta())
                .all(|(a, b)| (a - b).abs() < 1e-12)
        });
        assert!(ok);
        assert!(TwoMassPlay::from_theta(&[1.0; 3], 10, Start::Rest).is_none());
        assert!(m.integrable());
        assert!(
            !TwoMassPlay {
                substeps: 1,
                stiffness: 10.0,
                ..m
            }
            .integrable()
        );
    }
}
