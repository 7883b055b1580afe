//! A rigid servo axis in continuous time: an optional first-order actuator (amplifier,
//! current loop) from the command to the force, a mass with viscous damping, an optional
//! spring to the frame, optional Coulomb friction with sticking, and an optional upper end
//! stop on the position (inelastic: the mass stays at the stop while the force pushes it
//! there).
//!
//! ```text
//! τ_a ḟ = K u − f          (f = K u without actuator)
//! ẋ = v
//! m v̇ = f − c v − k x − F_c sign(v)
//! ```
//!
//! The command is held over each sample (zero-order hold); each sample is integrated by
//! [`SUBSTEPS`] classical Runge–Kutta steps with the friction's sign held over a step. The
//! events that change the right-hand side — the velocity reaching zero (the mass sticks when
//! the force is within `F_c`, or moves on the other way), the position reaching the stop —
//! are located inside a step by bisection and the step is continued from there in the new
//! mode, so the sampled response converges to the continuous one as the steps shrink.

/// Runge–Kutta steps per sample.
pub const SUBSTEPS: usize = 20;

/// What is measured.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Output {
    /// The position `x` (needs a spring for a stable plant).
    Position,
    /// The velocity `v` (a motor's speed).
    Velocity,
}

/// The axis's parameters (SI units: N, kg, s).
#[derive(Clone, Debug, PartialEq)]
pub struct Mass {
    /// `K`: force per command unit.
    pub gain: f64,
    /// `τ_a`: the actuator's time constant, when it has one.
    pub actuator: Option<f64>,
    /// `m`.
    pub mass: f64,
    /// `c`: viscous friction.
    pub damping: f64,
    /// `k`: the spring to the frame (0: none).
    pub stiffness: f64,
    /// `F_c`: the Coulomb force, also the force that breaks a stuck mass loose (0: none).
    pub coulomb: f64,
    /// The upper end stop of the position, when there is one.
    pub stop: Option<f64>,
    /// What is measured.
    pub output: Output,
}

/// How the mass moves.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    /// Moving, the friction's sign `s` (−1, 0 or 1) held over the step.
    Moving(i8),
    /// Stuck by Coulomb friction (`v = 0`).
    Stuck,
    /// Resting against the end stop (`x` at the stop, `v = 0`).
    Pinned,
}

/// The state.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MassState {
    /// The actuator's force (`K u` without actuator).
    pub f: f64,
    /// Position.
    pub x: f64,
    /// Velocity.
    pub v: f64,
    /// The mode.
    pub mode: Mode,
}

/// Bisections that locate an event inside a step (2⁻⁴⁰ of the step).
const BISECTIONS: usize = 40;

fn sign(v: f64) -> i8 {
    if v > 0.0 {
        1
    } else if v < 0.0 {
        -1
    } else {
        0
    }
}

impl Mass {
    /// States of the model: the actuator's, the position (when measured) and the velocity.
    pub fn order(&self) -> usize {
        usize::from(self.actuator.is_some())
            + match self.output {
                Output::Position => 2,
                Output::Velocity => 1,
            }
    }

    /// The same axis without friction and end stop (its linear part).
    pub fn linear(&self) -> Mass {
        Mass {
            coulomb: 0.0,
            stop: None,
            ..self.clone()
        }
    }

    /// The state at rest under the constant command `u`: the spring balances the force
    /// (against the stop if it lies beyond it), or without a spring the speed where the
    /// viscous friction balances the force beyond Coulomb's.
    pub fn rest(&self, u: f64) -> MassState {
        let f = self.gain * u;
        if self.stiffness > 0.0 {
            let x = f / self.stiffness;
            if let Some(l) = self.stop
                && x >= l
            {
                return MassState {
                    f,
                    x: l,
                    v: 0.0,
                    mode: Mode::Pinned,
                };
            }
            let mode = if self.coulomb > 0.0 {
                Mode::Stuck
            } else {
                Mode::Moving(0)
            };
            return MassState { f, x, v: 0.0, mode };
        }
        if f.abs() <= self.coulomb && self.coulomb > 0.0 {
            return MassState {
                f,
                x: 0.0,
                v: 0.0,
                mode: Mode::Stuck,
            };
        }
        let v = (f - self.coulomb * f.signum()) / self.damping;
        MassState {
            f,
            x: 0.0,
            v,
            mode: Mode::Moving(if self.coulomb > 0.0 { sign(v) } else { 0 }),
        }
    }

    /// The measured quantity of a state.
    pub fn output(&self, s: &MassState) -> f64 {
        match self.output {
            Output::Position => s.x,
            Output::Velocity => s.v,
        }
    }

    /// The force on the mass at rest: the drive's less the spring's.
    fn net_force(&self, s: &MassState) -> f64 {
        s.f - self.stiffness * s.x
    }

    /// The mode a mass at rest (`v = 0`) takes: stuck within the Coulomb force, pinned while
    /// pushed into the stop, else moving in the direction of the force.
    fn at_rest(&self, s: &MassState) -> Mode {
        let net = self.net_force(s);
        let at_stop = self.stop.is_some_and(|l| s.x >= l);
        if at_stop && net >= -self.coulomb {
            return Mode::Pinned;
        }
        if self.coulomb > 0.0 && net.abs() <= self.coulomb {
            return Mode::Stuck;
        }
        Mode::Moving(if self.coulomb > 0.0 { sign(net) } else { 0 })
    }

    /// `(ḟ, ẋ, v̇)` while moving with the friction's sign `s`.
    fn derivative(&self, y: [f64; 3], u: f64, s: i8) -> [f64; 3] {
        let [f, x, v] = y;
        let df = match self.actuator {
            Some(tau) => (self.gain * u - f) / tau,
            None => 0.0,
        };
        let force = f - self.damping * v - self.stiffness * x - self.coulomb * f64::from(s);
        [df, v, force / self.mass]
    }

    fn rk4(&self, y: [f64; 3], u: f64, s: i8, h: f64) -> [f64; 3] {
        let add =
            |a: [f64; 3], k: [f64; 3], c: f64| [a[0] + c * k[0], a[1] + c * k[1], a[2] + c * k[2]];
        let k1 = self.derivative(y, u, s);
        let k2 = self.derivative(add(y, k1, h / 2.0), u, s);
        let k3 = self.derivative(add(y, k2, h / 2.0), u, s);
        let k4 = self.derivative(add(y, k3, h), u, s);
        let mut out = y;
        for i in 0..3 {
            out[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
        }
        out
    }

    /// The actuator's force after `h` at rest (exact: the lag's exponential).
    fn actuator_after(&self, f: f64, u: f64, h: f64) -> f64 {
        match self.actuator {
            Some(tau) => self.gain * u + (f - self.gain * u) * (-h / tau).exp(),
            None => self.gain * u,
        }
    }

    /// Whether a step that ended at `y` from a motion with sign `s` crossed an event: the
    /// velocity through zero against the friction, or the position past the stop.
    fn event(&self, y: [f64; 3], s: i8) -> bool {
        let stopped = s != 0 && f64::from(s) * y[2] <= 0.0;
        let hit = self.stop.is_some_and(|l| y[1] > l);
        stopped || hit
    }

    /// One step of length `h` from `st` under the held command `u`, events located inside it.
    fn step(&self, st: &mut MassState, u: f64, h: f64) {
        if self.actuator.is_none() {
            st.f = self.gain * u;
        }
        let mut left = h;
        // At most a few mode changes inside one step; the last part runs without events.
        for _ in 0..6 {
            if left <= 0.0 {
                return;
            }
            match st.mode {
                Mode::Stuck | Mode::Pinned => {
                    let mode = self.at_rest(st);
                    if mode == st.mode {
                        st.f = self.actuator_after(st.f, u, left);
                        return;
                    }
                    st.mode = mode;
                }
                Mode::Moving(s) => {
                    let y0 = [st.f, st.x, st.v];
                    let y1 = self.rk4(y0, u, s, left);
                    if !self.event(y1, s) {
                        (st.f, st.x, st.v) = (y1[0], y1[1], y1[2]);
                        return;
                    }
                    // The event lies in (lo, hi] of the step.
                    let (mut lo, mut hi) = (0.0, left);
                    for _ in 0..BISECTIONS {
                        let mid = 0.5 * (lo + hi);
                        if self.event(self.rk4(y0, u, s, mid), s) {
                            hi = mid;
                        } else {
                            lo = mid;
                        }
                    }
                    let y = self.rk4(y0, u, s, hi);
                    st.f = y[0];
                    st.x = match self.stop {
                        Some(l) if y[1] > l => l,
                        _ => y[1],
                    };
                    st.v = 0.0;
                    st.mode = self.at_rest(st);
                    left -= hi;
                }
            }
        }
    }

    /// One sample: the command `u` held for `ts` seconds.
    pub fn advance(&self, st: &mut MassState, u: f64, ts: f64) {
        let h = ts / SUBSTEPS as f64;
        for _ in 0..SUBSTEPS {
            self.step(st, u, h);
        }
    }

    /// The dominant time: the mechanical time constant `m/c` of a free axis, `c/k` (the mean
    /// time of the spring–mass–damper's step response) with a spring, plus the actuator's.
    pub fn dominant_time(&self) -> f64 {
        let mech = if self.stiffness > 0.0 {
            (self.damping / self.stiffness).max((self.mass / self.stiffness).sqrt())
        } else {
            self.mass / self.damping
        };
        mech + self.actuator.unwrap_or(0.0)
    }

    /// The static gain of the output on the command (without friction and stop).
    pub fn static_gain(&self) -> f64 {
        match self.output {
            Output::Position => self.gain / self.stiffness,
            Output::Velocity => self.gain / self.damping,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn free(coulomb: f64) -> Mass {
        Mass {
            gain: 2.0,
            actuator: None,
            mass: 1.5,
            damping: 3.0,
            stiffness: 0.0,
            coulomb,
            stop: None,
            output: Output::Velocity,
        }
    }

    /// `m v̇ = K u − c v` from rest: `v(t) = K u / c (1 − e^{−c t / m})`.
    #[test]
    fn mass_damper_step_is_the_exponential() {
        let m = free(0.0);
        let mut st = m.rest(0.0);
        let ts = 0.01;
        for k in 1..=300 {
            m.advance(&mut st, 1.5, ts);
            let t = k as f64 * ts;
            let want = 2.0 * 1.5 / 3.0 * (1.0 - (-3.0 * t / 1.5).exp());
            assert!((st.v - want).abs() < 1e-9, "t {t}: {} vs {want}", st.v);
        }
    }

    /// A mass launched at `v0` against Coulomb and viscous friction stops at
    /// `t* = (m/c) ln(1 + c v0 / F_c)`, at `x* = m v0 / c − F_c t* / c`, and stays.
    #[test]
    fn coulomb_stops_the_mass_when_it_predicts() {
        let (m, c, fc, v0) = (1.5, 3.0, 0.8, 2.0);
        let axis = free(fc);
        let mut st = MassState {
            f: 0.0,
            x: 0.0,
            v: v0,
            mode: Mode::Moving(1),
        };
        let ts = 0.01;
        let t_stop = m / c * (1.0 + c * v0 / fc).ln();
        let x_stop = m * v0 / c - fc * t_stop / c;
        let mut first_zero = None;
        for k in 1..=200 {
            axis.advance(&mut st, 0.0, ts);
            if st.v == 0.0 && first_zero.is_none() {
                first_zero = Some(k);
            }
        }
        assert_eq!(first_zero, Some((t_stop / ts).ceil() as usize));
        assert_eq!(st.mode, Mode::Stuck);
        assert!((st.x - x_stop).abs() < 1e-9, "{} vs {x_stop}", st.x);
        // Without viscous friction: t* = m v0 / F_c, x* = m v0² / (2 F_c).
        let pure = Mass {
            damping: 0.0,
            ..free(fc)
        };
        let mut st = MassState {
            f: 0.0,
            x: 0.0,
            v: v0,
            mode: Mode::Moving(1),
        };
        for _ in 0..500 {
            pure.advance(&mut st, 0.0, ts);
        }
        assert!((st.x - m * v0 * v0 / (2.0 * fc)).abs() < 1e-9, "{}", st.x);
    }

    /// A stuck mass breaks loose only when the force exceeds the Coulomb force.
    #[test]
    fn sticks_within_the_coulomb_force() {
        let axis = free(1.0);
        let mut st = axis.rest(0.0);
        assert_eq!(st.mode, Mode::Stuck);
        for _ in 0..100 {
            axis.advance(&mut st, 0.45, 0.01);
        }
        assert_eq!((st.v, st.mode), (0.0, Mode::Stuck));
        axis.advance(&mut st, 0.55, 0.01);
        assert!(st.v > 0.0);
        // The steady speed beyond it: (K u − F_c) / c.
        for _ in 0..2000 {
            axis.advance(&mut st, 0.55, 0.01);
        }
        assert!((st.v - (1.1 - 1.0) / 3.0).abs() < 1e-9, "{}", st.v);
    }

    /// A spring–mass–damper pushed beyond the stop rests there and leaves it when the force
    /// falls below the spring's.
    #[test]
    fn end_stop_pins_and_releases() {
        let axis = Mass {
            gain: 1.0,
            actuator: None,
            mass: 1.0,
            damping: 4.0,
            stiffness: 4.0,
            coulomb: 0.0,
            stop: Some(0.5),
            output: Output::Position,
        };
        let mut st = axis.rest(0.0);
        for _ in 0..500 {
            axis.advance(&mut st, 4.0, 0.01);
            assert!(st.x <= 0.5);
        }
        assert_eq!((st.x, st.mode), (0.5, Mode::Pinned));
        axis.advance(&mut st, 1.0, 0.01);
        assert!(st.x < 0.5 && matches!(st.mode, Mode::Moving(_)));
    }
}
