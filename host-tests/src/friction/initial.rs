//! The initial state of an integrating friction model from the first samples of a record:
//! the position and velocity before the first sample whose simulation fits those samples
//! best (least squares, Levenberg–Marquardt from the parabola through them).
//!
//! A line alone is biased when the drive accelerates in those samples (it starts from rest
//! under a step of force, say), and the position an integrating model starts from stays in
//! every later sample: half a millimetre per second of velocity error over a 0.5 s time
//! constant is a quarter of a millimetre for the rest of the record.

use super::model::{FrictionModel, Initial, accelerating_start};
use crate::numerics::lm::{Jacobian, Problem, Settings, minimise};

impl FrictionModel {
    /// Where to start the simulation of a record whose input is `u` and whose output starts
    /// `y_first`: for an integrating model, the position and velocity that fit `y_first`
    /// best (the parabola through them when the fit fails); otherwise rest at the first input.
    pub fn initial_from(&self, u: &[f64], y_first: &[f64]) -> Initial {
        if !self.integrating {
            return Initial::Rest {
                u_start: u.first().copied().unwrap_or(self.plant.u_min()),
            };
        }
        let line = accelerating_start(y_first);
        let k = y_first.len().min(u.len());
        let Initial::Moving { position, velocity } = line else {
            return line;
        };
        if k < 3 {
            return line;
        }
        let u = &u[..k];
        let residual = |th: &[f64]| -> Option<Vec<f64>> {
            let sim = self.simulate_from(
                u,
                Initial::Moving {
                    position: th[0],
                    velocity: th[1],
                },
            );
            let r: Vec<f64> = sim.iter().zip(y_first).map(|(a, b)| a - b).collect();
            r.iter().all(|v| v.is_finite()).then_some(r)
        };
        let size = y_first
            .iter()
            .fold(0.0f64, |m, v| m.max(v.abs()))
            .max(1e-12);
        let typical = [size, velocity.abs().max(size * 1e-3)];
        let problem = Problem {
            residual: &residual,
            admissible: &|_| true,
            jacobian: Jacobian::ForwardDifference { typical: &typical },
        };
        match minimise(&problem, &[position, velocity], &Settings::default()) {
            Ok(min) => Initial::Moving {
                position: min.theta[0],
                velocity: min.theta[1],
            },
            Err(_) => line,
        }
    }

    /// The simulated output for the input `u` of a record whose output starts `y_first` (its
    /// first samples, e.g. 20), from [`initial_from`](Self::initial_from).
    pub fn simulate_after(&self, u: &[f64], y_first: &[f64]) -> Vec<f64> {
        self.simulate_from(u, self.initial_from(u, y_first))
    }
}
