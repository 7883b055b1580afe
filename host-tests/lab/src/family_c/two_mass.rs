//! A two-mass drive in continuous time: the motor's inertia, a shaft with stiffness and
//! damping whose torque has a dead zone of the gear play on the angle between motor and load,
//! and the load's inertia, each side with viscous friction; the motor's speed is measured.
//!
//! ```text
//! Δ̇ = ω_m − ω_l                       (Δ = θ_m − θ_l)
//! J_m ω̇_m = K u − b_m ω_m − T
//! J_l ω̇_l = T − b_l ω_l
//! T = k (Δ − α) + c (ω_m − ω_l)   for Δ > α   (teeth in contact on the driving flank)
//! T = 0                            for |Δ| ≤ α (in the play)
//! T = k (Δ + α) + c (ω_m − ω_l)   for Δ < −α  (in contact on the other flank)
//! ```
//!
//! The command is held over each sample; each sample is [`SUBSTEPS`] classical Runge–Kutta
//! steps with the contact held over a step, and the instant the angle crosses a flank (`±α`)
//! is found by bisection inside the step, which is continued from there with the new
//! contact. With `α = 0` it is the linear two-mass drive.

/// Runge–Kutta steps per sample.
pub const SUBSTEPS: usize = 20;

/// Bisections that locate a flank inside a step.
const BISECTIONS: usize = 40;

/// The drive's parameters (SI units: N m, kg m², s, rad).
#[derive(Clone, Debug, PartialEq)]
pub struct TwoMass {
    /// `K`: motor torque per command unit.
    pub gain: f64,
    /// `J_m`.
    pub motor_inertia: f64,
    /// `J_l`.
    pub load_inertia: f64,
    /// `b_m`: the motor's viscous friction.
    pub motor_damping: f64,
    /// `b_l`: the load's viscous friction.
    pub load_damping: f64,
    /// `k`: the shaft's stiffness.
    pub stiffness: f64,
    /// `c`: the shaft's damping.
    pub shaft_damping: f64,
    /// `α`: half the gear play, rad.
    pub half_play: f64,
}

/// The state `(Δ, ω_m, ω_l)` and the flank in contact (−1, 0 in the play, 1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TwoMassState {
    /// `Δ`, `ω_m`, `ω_l`.
    pub x: [f64; 3],
    /// The flank in contact.
    pub side: i8,
}

impl TwoMass {
    /// The drive without play.
    pub fn linear(&self) -> TwoMass {
        TwoMass {
            half_play: 0.0,
            ..self.clone()
        }
    }

    /// Three states.
    pub fn order(&self) -> usize {
        3
    }

    /// The flank of an angle.
    fn side_of(&self, d: f64) -> i8 {
        if d > self.half_play {
            1
        } else if d < -self.half_play {
            -1
        } else {
            0
        }
    }

    /// Steady rotation under the constant command `u`: both at `ω = K u / (b_m + b_l)`, the
    /// shaft twisted beyond the flank by the load's torque `b_l ω`.
    pub fn rest(&self, u: f64) -> TwoMassState {
        let w = self.gain * u / (self.motor_damping + self.load_damping);
        let t = self.load_damping * w;
        let s = if t > 0.0 {
            1
        } else if t < 0.0 {
            -1
        } else {
            0
        };
        let d = f64::from(s) * self.half_play + t / self.stiffness;
        TwoMassState {
            x: [d, w, w],
            side: s,
        }
    }

    /// The motor's speed.
    pub fn output(&self, s: &TwoMassState) -> f64 {
        s.x[1]
    }

    fn derivative(&self, x: [f64; 3], u: f64, side: i8) -> [f64; 3] {
        let [d, wm, wl] = x;
        let t = match side {
            0 => 0.0,
            s => {
                self.stiffness * (d - f64::from(s) * self.half_play)
                    + self.shaft_damping * (wm - wl)
            }
        };
        [
            wm - wl,
            (self.gain * u - self.motor_damping * wm - t) / self.motor_inertia,
            (t - self.load_damping * wl) / self.load_inertia,
        ]
    }

    fn rk4(&self, x: [f64; 3], u: f64, side: i8, h: f64) -> [f64; 3] {
        let add =
            |a: [f64; 3], k: [f64; 3], c: f64| [a[0] + c * k[0], a[1] + c * k[1], a[2] + c * k[2]];
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

    /// Whether the angle `d` has left the region of `side`: beyond a flank from the play, or
    /// back inside the play from a contact.
    fn crossed(&self, d: f64, side: i8) -> bool {
        match side {
            0 => d.abs() > self.half_play,
            s => f64::from(s) * d < self.half_play,
        }
    }

    fn step(&self, st: &mut TwoMassState, u: f64, h: f64) {
        let mut left = h;
        for _ in 0..6 {
            if left <= 0.0 {
                return;
            }
            let x1 = self.rk4(st.x, u, st.side, left);
            if !self.crossed(x1[0], st.side) {
                st.x = x1;
                return;
            }
            let (mut lo, mut hi) = (0.0, left);
            for _ in 0..BISECTIONS {
                let mid = 0.5 * (lo + hi);
                if self.crossed(self.rk4(st.x, u, st.side, mid)[0], st.side) {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
            let x = self.rk4(st.x, u, st.side, hi);
            let next = match st.side {
                0 => self.side_of(x[0]),
                _ => 0,
            };
            let flank = match (st.side, next) {
                (0, s) => f64::from(s) * self.half_play,
                (s, _) => f64::from(s) * self.half_play,
            };
            st.x = [flank, x[1], x[2]];
            st.side = next;
            left -= hi;
        }
        st.x = self.rk4(st.x, u, st.side, left);
        st.side = self.side_of(st.x[0]);
    }

    /// One sample: the command `u` held for `ts` seconds.
    pub fn advance(&self, st: &mut TwoMassState, u: f64, ts: f64) {
        let h = ts / SUBSTEPS as f64;
        for _ in 0..SUBSTEPS {
            self.step(st, u, h);
        }
    }

    /// The rigid body's time constant `(J_m + J_l) / (b_m + b_l)`.
    pub fn dominant_time(&self) -> f64 {
        (self.motor_inertia + self.load_inertia) / (self.motor_damping + self.load_damping)
    }

    /// The static gain of the motor's speed on the command.
    pub fn static_gain(&self) -> f64 {
        self.gain / (self.motor_damping + self.load_damping)
    }

    /// The shaft's resonance in contact, `√(k (1/J_m + 1/J_l))`, rad/s.
    pub fn resonance(&self) -> f64 {
        (self.stiffness * (1.0 / self.motor_inertia + 1.0 / self.load_inertia)).sqrt()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{DMatrix, DVector};

    fn drive(half_play: f64) -> TwoMass {
        TwoMass {
            gain: 1.0,
            motor_inertia: 1.0,
            load_inertia: 2.0,
            motor_damping: 0.1,
            load_damping: 0.2,
            stiffness: 400.0,
            shaft_damping: 2.0,
            half_play,
        }
    }

    /// Without play the drive is the linear three-state system; its exact zero-order-hold
    /// discretisation (`e^{A T_s}` and `∫ e^{A s} ds B` from the exponential of the augmented
    /// matrix) gives the same motor speed.
    #[test]
    fn without_play_it_is_the_linear_two_mass_drive() {
        let p = drive(0.0);
        let (jm, jl, bm, bl, k, c) = (1.0, 2.0, 0.1, 0.2, 400.0, 2.0);
        let ts = 0.02;
        let mut m = DMatrix::<f64>::zeros(4, 4);
        let a = [
            [0.0, 1.0, -1.0],
            [-k / jm, -(bm + c) / jm, c / jm],
            [k / jl, c / jl, -(bl + c) / jl],
        ];
        for i in 0..3 {
            for j in 0..3 {
                m[(i, j)] = a[i][j] * ts;
            }
        }
        m[(1, 3)] = 1.0 / jm * ts;
        let e = m.exp();
        let phi = e.view((0, 0), (3, 3)).into_owned();
        let gamma = e.view((0, 3), (3, 1)).into_owned();
        let mut x = DVector::<f64>::zeros(3);
        let mut st = p.rest(0.0);
        let mut worst: f64 = 0.0;
        for t in 0..400 {
            let u = if (t / 37) % 2 == 0 { 1.0 } else { -0.6 } + 0.3 * ((t as f64) * 0.7).sin();
            p.advance(&mut st, u, ts);
            x = &phi * &x + &gamma * u;
            worst = worst.max((st.x[1] - x[1]).abs());
        }
        assert!(worst < 1e-8, "{worst}");
    }

    /// From rest in the middle of the play the motor turns alone until the angle reaches the
    /// flank: `ω_m(t) = K u / b_m (1 − e^{−b_m t / J_m})`, the load still.
    #[test]
    fn in_the_play_the_motor_turns_alone() {
        let p = drive(0.05);
        let mut st = p.rest(0.0);
        let ts = 0.01;
        let u = 0.5;
        let mut checked = 0;
        for n in 1..100 {
            p.advance(&mut st, u, ts);
            let t = n as f64 * ts;
            let wm = u / 0.1 * (1.0 - (-0.1 * t).exp());
            let angle = u / 0.1 * (t - (1.0 - (-0.1 * t).exp()) / 0.1);
            if angle < 0.05 {
                assert!((st.x[1] - wm).abs() < 1e-10, "t {t}");
                assert_eq!(st.x[2], 0.0);
                checked += 1;
            } else {
                assert!(st.x[2] > 0.0);
                break;
            }
        }
        assert!(checked > 5, "{checked}");
    }

    /// The steady rotation of [`TwoMass::rest`] is an equilibrium, play or not.
    #[test]
    fn rest_is_an_equilibrium() {
        for alpha in [0.0, 0.02] {
            let p = drive(alpha);
            let mut st = p.rest(-0.7);
            let start = st;
            for _ in 0..200 {
                p.advance(&mut st, -0.7, 0.01);
            }
            for i in 0..3 {
                assert!((st.x[i] - start.x[i]).abs() < 1e-10, "{alpha}: {st:?}");
            }
            assert_eq!(st.side, -1);
        }
    }
}
