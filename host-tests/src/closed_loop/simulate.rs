//! A backlash servo in closed loop.
//!
//! The plant is the paper's: a backlash whose borders are the paper's `atan(u ∓ 1)`
//! interpolated on the identification knots (so the two-path model on those knots is exact),
//! then `G(q)` of Section IV, plus measurement noise `v = G_v(q) e` that the controller sees.
//! The controller is proportional with feedforward on a reference `r`, a smoothed random
//! signal: `c(t) = g_ff r(t) + K_p (r(t) − y_m(t − 1))` (one sample of computation delay),
//! passed through a soft limit `tanh` into the open interval `]u_min, u_max[`.
//!
//! The method needs every monotone input run to start at `u_min` or `u_max` (Table I), so
//! the servo interleaves its command with excursions: the input cycles through
//! "command, `u_max`, command, `u_min`", exactly the Table I cycle with the random levels
//! replaced by the controller's output. The record starts with a hold at `u_min` (controller
//! off), for μ0. The input is therefore a function of past noise: a closed-loop record.

use rand::SeedableRng;
use rand_distr::{Distribution, StandardNormal};
use rand_pcg::Pcg64;

use crate::identify::interpolate;
use crate::sim::{Backlash, Lti, Nonlinearity, paper_plant};

/// The servo's settings (config, not state).
#[derive(Clone, Debug, PartialEq)]
pub struct ServoSpec {
    /// Identification knots, ascending, `u_min … u_max` (both paths).
    pub knots: Vec<f64>,
    /// Samples of the initial hold at `u_min`.
    pub hold: usize,
    /// Samples after the hold.
    pub len: usize,
    /// Proportional gain `K_p` on `r − y_m`.
    pub kp: f64,
    /// Feedforward gain `g_ff` on `r`.
    pub feedforward: f64,
    /// Standard deviation of the reference's white source (before smoothing).
    pub reference_std: f64,
    /// Pole of the first-order filter that smooths the reference, in `[0, 1[`.
    pub reference_pole: f64,
    /// Standard deviation of the white noise `e` driving the measurement noise `G_v(q) e`.
    pub noise_std: f64,
    /// Pole `a` of the noise filter `G_v(q) = (1 + 0.5 q⁻¹) / (1 − a q⁻¹)`, in `[0, 1[`
    /// (the paper's: 0.85).
    pub noise_pole: f64,
}

impl ServoSpec {
    /// The paper's interval `[-3, 3]` with 6 segments per path, a hold of 100 samples, 4000
    /// samples after it, `K_p = 1.5`, `g_ff = 1`, a reference of standard deviation 1 (white
    /// source `√(1 − 0.97²)` smoothed by the pole 0.97), noise `e` of standard deviation 0.1
    /// (`v = G_v e` of standard deviation about 0.28, the output's about 0.8).
    pub fn paper() -> Self {
        Self {
            knots: (0..=6).map(|i| -3.0 + i as f64).collect(),
            hold: 100,
            len: 4000,
            kp: 1.5,
            feedforward: 1.0,
            reference_std: (1.0 - 0.97f64 * 0.97).sqrt(),
            reference_pole: 0.97,
            noise_std: 0.1,
            noise_pole: 0.85,
        }
    }

    /// The paper's servo with slowly coloured noise and a livelier reference, a record on which
    /// the open-loop estimate's poles are biased: noise pole 0.97 with `std(e) = 0.045` (so
    /// that `v = G_v e` keeps a standard deviation of about 0.28, as in [`ServoSpec::paper`]),
    /// a reference smoothed by the pole 0.5 (standard deviation 1), 20000 samples after the
    /// hold.
    pub fn coloured() -> Self {
        Self {
            len: 20_000,
            reference_std: (1.0 - 0.5f64 * 0.5).sqrt(),
            reference_pole: 0.5,
            noise_std: 0.045,
            noise_pole: 0.97,
            ..Self::paper()
        }
    }

    /// The same servo without feedback: `K_p = 0` and the feedforward `g_ff + K_p`, so that
    /// the command has the closed loop's spread; with the same seed, the same reference and
    /// noise draws. An open-loop record of the same plant.
    pub fn open_loop(&self) -> Self {
        Self {
            kp: 0.0,
            feedforward: self.feedforward + self.kp,
            ..self.clone()
        }
    }

    fn u_min(&self) -> f64 {
        self.knots.first().copied().unwrap_or(f64::NAN)
    }

    fn u_max(&self) -> f64 {
        self.knots.last().copied().unwrap_or(f64::NAN)
    }

    fn check(&self) -> Result<(), ServoError> {
        let ascending = self.knots.windows(2).all(|w| w[0] < w[1]);
        if self.knots.len() < 2 || !ascending || self.knots.iter().any(|k| !k.is_finite()) {
            return Err(ServoError::Knots);
        }
        let finite = [
            self.kp,
            self.feedforward,
            self.reference_std,
            self.noise_std,
        ];
        if finite.iter().any(|v| !v.is_finite()) || self.noise_std < 0.0 {
            return Err(ServoError::Setting);
        }
        if !(0.0..1.0).contains(&self.reference_pole) {
            return Err(ServoError::ReferencePole(self.reference_pole));
        }
        if !(0.0..1.0).contains(&self.noise_pole) {
            return Err(ServoError::NoisePole(self.noise_pole));
        }
        Ok(())
    }

    /// The element: the paper's backlash borders interpolated on the knots.
    fn element(&self) -> Backlash {
        let k = self.knots.clone();
        let (a, d): (Vec<f64>, Vec<f64>) = k
            .iter()
            .map(|u| ((u - 1.0).atan(), (u + 1.0).atan()))
            .unzip();
        let k2 = k.clone();
        Backlash::from_fns(
            move |u| interpolate(&k, &a, u),
            move |u| interpolate(&k2, &d, u),
        )
    }
}

/// Why a servo cannot be simulated.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
pub enum ServoError {
    /// The knots are fewer than two, not strictly ascending, or not finite.
    #[error("the servo's knots must be at least two finite values in strictly ascending order")]
    Knots,
    /// A gain or standard deviation is not finite, or the noise's is negative.
    #[error("the servo's gains and standard deviations must be finite, the noise's not negative")]
    Setting,
    /// The reference's smoothing pole is outside `[0, 1[`.
    #[error("the reference's smoothing pole {0} must be in [0, 1[")]
    ReferencePole(f64),
    /// The noise filter's pole is outside `[0, 1[`.
    #[error("the noise filter's pole {0} must be in [0, 1[")]
    NoisePole(f64),
}

/// One closed-loop record.
#[derive(Clone, Debug, PartialEq)]
pub struct LoopRecord {
    /// Reference `r(t)` (0 during the hold).
    pub r: Vec<f64>,
    /// Input `u(t)` applied to the element.
    pub u: Vec<f64>,
    /// Measured output `y_m(t) = G H[u](t) + v(t)`.
    pub y: Vec<f64>,
}

/// Simulates the servo of `spec` with the random stream of `seed` (reference and noise).
pub fn simulate_servo(spec: &ServoSpec, seed: u64) -> Result<LoopRecord, ServoError> {
    spec.check()?;
    let mut rng = Pcg64::seed_from_u64(seed);
    let n = spec.hold + spec.len;
    let (lo, hi) = (spec.u_min(), spec.u_max());
    let (mid, half) = ((lo + hi) / 2.0, (hi - lo) / 2.0);
    let mut element = spec.element();
    element.reset();
    let mut g = paper_plant();
    let mut gv = Lti::new(vec![1.0, 0.5], vec![1.0, -spec.noise_pole])
        .map_err(|_| ServoError::NoisePole(spec.noise_pole))?;
    let mut servo = LoopRecord {
        r: Vec::with_capacity(n),
        u: Vec::with_capacity(n),
        y: Vec::with_capacity(n),
    };
    let (mut r, mut y_last) = (0.0, 0.0);
    for t in 0..n {
        let e: f64 = StandardNormal.sample(&mut rng);
        let w: f64 = StandardNormal.sample(&mut rng);
        let u = if t < spec.hold {
            lo
        } else {
            r = spec.reference_pole * r + spec.reference_std * w;
            match (t - spec.hold) % 4 {
                1 => hi,
                3 => lo,
                _ => {
                    let c = spec.feedforward * r + spec.kp * (r - y_last);
                    mid + half * ((c - mid) / half).tanh()
                }
            }
        };
        let y = g.step(element.step(u)) + gv.step(spec.noise_std * e);
        servo.r.push(if t < spec.hold { 0.0 } else { r });
        servo.u.push(u);
        servo.y.push(y);
        y_last = y;
    }
    Ok(servo)
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    #[test]
    fn the_input_keeps_the_table1_cycle_and_the_hold() {
        let spec = ServoSpec::paper();
        let s = simulate_servo(&spec, 1).unwrap();
        assert!(s.u[..spec.hold].iter().all(|&u| u == -3.0));
        for (i, &u) in s.u[spec.hold..].iter().enumerate() {
            match i % 4 {
                1 => assert_eq!(u, 3.0),
                3 => assert_eq!(u, -3.0),
                _ => assert!(u > -3.0 && u < 3.0, "command {u} outside ]-3, 3["),
            }
        }
    }

    #[test]
    fn the_input_depends_on_the_noise_only_through_the_controller() {
        // Same seed (same reference and noise draws), noise on and off: without feedback the
        // inputs agree sample for sample, with feedback they differ.
        let mut spec = ServoSpec::paper();
        let quiet = ServoSpec {
            noise_std: 0.0,
            ..spec.clone()
        };
        let diff = |a: &ServoSpec, b: &ServoSpec| {
            let (x, y) = (simulate_servo(a, 5).unwrap(), simulate_servo(b, 5).unwrap());
            x.u.iter()
                .zip(&y.u)
                .map(|(p, q)| (p - q).abs())
                .fold(0.0, f64::max)
        };
        assert!(diff(&spec, &quiet) > 0.05);
        spec.kp = 0.0;
        let quiet = ServoSpec {
            noise_std: 0.0,
            ..spec.clone()
        };
        assert_eq!(diff(&spec, &quiet), 0.0);
    }

    #[test]
    fn bad_settings_are_typed() {
        let mut spec = ServoSpec::paper();
        spec.reference_pole = 1.0;
        assert_eq!(
            simulate_servo(&spec, 0),
            Err(ServoError::ReferencePole(1.0))
        );
    }
}
