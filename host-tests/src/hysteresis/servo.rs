//! A simulated servo for the hysteresis fit: the paper's plant behind a backlash of constant
//! play or a relay with a lens between its borders, driven by a smoothed random input with
//! many reversals inside the range (no Table I sweeps) after a hold at `u_min` (which gives
//! the subspace start its μ0), white output noise at a given SNR.

use rand::RngExt;
use rand_core::SeedableRng;
use rand_distr::StandardNormal;
use rand_pcg::Pcg64;

use crate::model::MemoryElement;
use crate::sim::{Backlash, Nonlinearity, Switch, paper_plant, variance};

/// Half the input range: the input lies in `[−RANGE, RANGE]`.
pub const RANGE: f64 = 3.0;

/// A servo and the size of its hysteresis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Servo {
    /// Backlash (`H_a = u − g/2`, `H_d = u + g/2`) or switch (`u ∓ o sin(π(u + 3)/6)`).
    pub kind: MemoryElement,
    /// The play `g` (backlash) or the lens' half height `o` (switch).
    pub width: f64,
    /// Output SNR in dB (variance of the noise-free output over the noise's).
    pub snr_db: f64,
}

/// Samples of the hold at `u_min = −RANGE` that opens every record.
pub const HOLD: usize = 300;

/// A record of the servo.
#[derive(Clone, Debug)]
pub struct ServoRecord {
    /// Input.
    pub u: Vec<f64>,
    /// Measured output.
    pub y: Vec<f64>,
    /// Noise-free output.
    pub y_clean: Vec<f64>,
}

/// Low-pass filtered Gaussian noise (`1/(1 − 0.95 q⁻¹)²`), scaled into `[−RANGE, RANGE]`.
pub(crate) fn smoothed_input(len: usize, rng: &mut Pcg64) -> Vec<f64> {
    let (mut s1, mut s2) = (0.0, 0.0);
    let raw: Vec<f64> = (0..len + 200)
        .map(|_| {
            let e: f64 = rng.sample(StandardNormal);
            s1 = 0.95 * s1 + e;
            s2 = 0.95 * s2 + s1;
            s2
        })
        .skip(200)
        .collect();
    let peak = raw.iter().fold(0.0f64, |m, v| m.max(v.abs())).max(1e-12);
    // `RANGE · v / peak` can round one ulp past the range at the peak.
    raw.iter()
        .map(|v| (RANGE * v / peak).clamp(-RANGE, RANGE))
        .collect()
}

impl Servo {
    /// The element, at rest with output 0.
    fn element(&self) -> Box<dyn Nonlinearity> {
        let w = self.width;
        match self.kind {
            MemoryElement::Play => Box::new(Backlash::from_fns(
                move |u| u - 0.5 * w,
                move |u| u + 0.5 * w,
            )),
            MemoryElement::Relay => {
                let lens =
                    move |u: f64| w * (std::f64::consts::PI * (u + RANGE) / (2.0 * RANGE)).sin();
                Box::new(Switch::from_fns(move |u| u - lens(u), move |u| u + lens(u)))
            }
        }
    }

    /// A record of [`HOLD`] samples at `−RANGE` and `len` samples of smoothed random input
    /// drawn from `seed`; the element starts at rest with output 0, the plant at rest.
    pub fn record(&self, len: usize, seed: u64) -> ServoRecord {
        let mut rng = Pcg64::seed_from_u64(seed);
        let mut u = vec![-RANGE; HOLD];
        u.extend(smoothed_input(len, &mut rng));
        let mut el = self.element();
        let w: Vec<f64> = u.iter().map(|&x| el.step(x)).collect();
        let y_clean = paper_plant().filter(&w);
        let sd = (variance(&y_clean) / 10f64.powf(self.snr_db / 10.0)).sqrt();
        let y = y_clean
            .iter()
            .map(|v| v + sd * rng.sample::<f64, _>(StandardNormal))
            .collect();
        ServoRecord { u, y, y_clean }
    }
}
