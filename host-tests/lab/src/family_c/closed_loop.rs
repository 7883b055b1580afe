//! The closed loop: after the hold at `u_min`, a P or PI controller computes the command from
//! the reference and the measured (noisy) output, clamped to the command's range, so the
//! noise is fed back into the command. The records carry the reference.

use super::design::{ControllerKind, Design};
use super::servo::Servo;

/// A discrete P or PI controller.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Controller {
    /// The kind.
    pub kind: ControllerKind,
    /// `K_p`.
    pub kp: f64,
    /// `K_i` (per second; 0 for P).
    pub ki: f64,
}

/// Samples of the tuning check's step response.
const CHECK_SAMPLES: usize = 800;

impl Controller {
    /// The design's controller on the servo's linear part: `K_p = a / G` (`G` the static
    /// gain, `a` the design's loop gain), for PI `K_i = K_p / T_i` with `T_i` the design's
    /// multiple of the dominant time constant; `a` halved (at most six times) until the
    /// linear loop's step response settles (its last quarter within 3 % of the step).
    pub fn tune(d: &Design) -> Option<Controller> {
        let kind = d.controller?;
        let g = d.servo.static_gain();
        let (mut a, ti) = d.loop_gain;
        let ti = ti * d.servo.dominant_time();
        let linear = d.servo.linear();
        let mut c = Controller {
            kind,
            kp: 0.0,
            ki: 0.0,
        };
        for _ in 0..7 {
            c.kp = a / g;
            c.ki = match kind {
                ControllerKind::P => 0.0,
                ControllerKind::Pi => c.kp / ti,
            };
            if c.settles(&linear, d) {
                break;
            }
            a *= 0.5;
        }
        Some(c)
    }

    /// Whether the loop's response to a step of the reference across a third of the
    /// output's range settles.
    fn settles(&self, servo: &Servo, d: &Design) -> bool {
        let (lo, hi) = d.range;
        let g = servo.static_gain();
        let mid = 0.5 * (lo + hi);
        let step = g * (hi - lo) / 3.0;
        let r: Vec<f64> = (0..CHECK_SAMPLES)
            .map(|t| if t < 10 { g * mid } else { g * mid + step })
            .collect();
        let quiet = vec![0.0; r.len()];
        let mut rest = servo.rest(mid);
        let (_, y) = self.run_from(servo, d, &r, &quiet, 0, &mut rest, mid, &|y, v| y + v);
        let tail = &y[3 * CHECK_SAMPLES / 4..];
        let spread = tail.iter().cloned().fold(f64::MIN, f64::max)
            - tail.iter().cloned().fold(f64::MAX, f64::min);
        spread.is_finite() && spread < 0.03 * step.abs()
    }

    /// One record: `hold` samples at `u_min`, then the controller on the reading
    /// `sensor(y, v(t))` of the noise-free output `y`. Returns the command and the noise-free
    /// output.
    pub fn run(
        &self,
        servo: &Servo,
        d: &Design,
        r: &[f64],
        v: &[f64],
        hold: usize,
        sensor: &dyn Fn(f64, f64) -> f64,
    ) -> (Vec<f64>, Vec<f64>) {
        let lo = d.range.0;
        let mut state = servo.rest(lo);
        self.run_from(servo, d, r, v, hold, &mut state, lo, sensor)
    }

    #[allow(clippy::too_many_arguments)]
    fn run_from(
        &self,
        servo: &Servo,
        d: &Design,
        r: &[f64],
        v: &[f64],
        hold: usize,
        state: &mut super::servo::Running,
        u0: f64,
        sensor: &dyn Fn(f64, f64) -> f64,
    ) -> (Vec<f64>, Vec<f64>) {
        let (lo, hi) = d.range;
        let (mut u_prev, mut e_prev) = (u0, f64::NAN);
        let mut us = Vec::with_capacity(r.len());
        let mut ys = Vec::with_capacity(r.len());
        for (t, &rt) in r.iter().enumerate() {
            let y = servo.output(state);
            let e = rt - sensor(y, v.get(t).copied().unwrap_or(0.0));
            let u = if t < hold {
                u0
            } else {
                match self.kind {
                    ControllerKind::P => (self.kp * e).clamp(lo, hi),
                    ControllerKind::Pi => {
                        let de = if e_prev.is_nan() { 0.0 } else { e - e_prev };
                        (u_prev + self.kp * de + self.ki * d.ts * e).clamp(lo, hi)
                    }
                }
            };
            (u_prev, e_prev) = (u, e);
            servo.advance(state, u, d.ts);
            us.push(u);
            ys.push(y);
        }
        (us, ys)
    }

    /// The reference's range: the linear servo's output over the command's range, widened
    /// so that the command reaches both ends (by `(1 + a)/a` for P, whose loop leaves an
    /// error, and by 10 % each side).
    pub fn reference_range(&self, d: &Design) -> (f64, f64) {
        let g = d.servo.static_gain();
        let (lo, hi) = (g * d.range.0, g * d.range.1);
        let widen = match self.kind {
            ControllerKind::P => {
                let a = self.kp * g;
                (1.0 + a) / a
            }
            ControllerKind::Pi => 1.0,
        };
        let span = hi - lo;
        (widen * lo - 0.1 * span, widen * hi + 0.1 * span)
    }

    /// `P 0.82` or `PI 0.41/0.12 s`.
    pub fn describe(&self) -> String {
        match self.kind {
            ControllerKind::P => format!("P {:.3}", self.kp),
            ControllerKind::Pi => format!("PI {:.3}/{:.3}s", self.kp, self.kp / self.ki),
        }
    }
}
