//! One benchmark case: a random plant, a random element, an SNR and a noise colour; its
//! estimation and validation records (Table I excitation, each with its own seed).

use hsid::Excitation;
use rand::RngExt;
use rand_core::SeedableRng;
use rand_pcg::{Pcg32, Pcg64};

use super::BenchError;
use super::element::{Element, random_element};
use super::plant::{Plant, random_plant};
use hsid_host::model::MemoryElement;
use hsid_host::sim::{Lti, SimError, simulate};

/// Samples of the initial hold at `u_min`.
pub const HOLD: usize = 300;

/// The noise added to the output.
#[derive(Clone, Debug)]
pub enum Colour {
    /// White.
    White,
    /// First-order autoregressive, `1 / (1 − a q⁻¹)`.
    Ar1(f64),
    /// First-order moving average, `1 + c q⁻¹`.
    Ma1(f64),
}

impl std::fmt::Display for Colour {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Colour::White => f.write_str("white"),
            Colour::Ar1(a) => write!(f, "AR(1) {a:.2}"),
            Colour::Ma1(c) => write!(f, "MA(1) {c:.2}"),
        }
    }
}

impl Colour {
    /// The noise filter.
    pub fn filter(&self) -> Result<Lti, SimError> {
        match *self {
            Colour::White => Lti::new(vec![1.0], vec![1.0]),
            Colour::Ar1(a) => Lti::new(vec![1.0], vec![1.0, -a]),
            Colour::Ma1(c) => Lti::new(vec![1.0, c], vec![1.0]),
        }
    }
}

/// A benchmark case.
#[derive(Clone, Debug)]
pub struct Case {
    /// Its number in the family.
    pub index: usize,
    /// The linear part.
    pub plant: Plant,
    /// The input element.
    pub element: Element,
    /// Output SNR over the excitation (dB).
    pub snr_db: f64,
    /// The noise colour.
    pub colour: Colour,
    /// Samples after the hold.
    pub samples: usize,
    /// Seed of the records.
    pub seed: u64,
}

/// A simulated record.
#[derive(Clone, Debug)]
pub struct SimulatedRecord {
    /// Input (hold included).
    pub u: Vec<f64>,
    /// Measured output.
    pub y: Vec<f64>,
    /// Noise-free output.
    pub y_clean: Vec<f64>,
}

impl Case {
    /// The `i`-th case of the family drawn from `seed`: orders cycle 1 to 4, elements alternate
    /// backlash and switch, SNR cycles 10, 20, 30, 40 dB, the noise colour cycles white, AR(1),
    /// MA(1), white; everything else is random.
    pub fn draw(seed: u64, index: usize, samples: usize) -> Result<Self, BenchError> {
        let mut rng = Pcg64::seed_from_u64(seed.wrapping_mul(1_000_003).wrapping_add(index as u64));
        let order = 1 + index % 4;
        let kind = if (index / 4).is_multiple_of(2) {
            MemoryElement::Play
        } else {
            MemoryElement::Relay
        };
        let snr_db = [10.0, 20.0, 30.0, 40.0][(index / 8) % 4];
        let colour = match (index / 2) % 4 {
            1 => Colour::Ar1(rng.random_range(0.5..0.9)),
            2 => Colour::Ma1(rng.random_range(0.3..0.8)),
            _ => Colour::White,
        };
        let u_min = -rng.random_range(0.5..3.0);
        let u_max = u_min + rng.random_range(1.0..6.0);
        Ok(Self {
            index,
            plant: random_plant(&mut rng, order)?,
            element: random_element(&mut rng, kind, u_min, u_max),
            snr_db,
            colour,
            samples,
            seed: rng.random(),
        })
    }

    /// The estimation (`which = 0`) or validation (`which = 1`) record.
    pub fn record(&self, which: u64) -> Result<SimulatedRecord, BenchError> {
        let seed = self.seed.wrapping_add(which.wrapping_mul(0x9e37_79b9));
        let e = &self.element;
        let excitation =
            Excitation::<f64, _>::new(e.u_min, e.u_max, HOLD, Pcg32::seed_from_u64(seed))
                .map_err(BenchError::Excitation)?;
        let u: Vec<f64> = excitation.take(HOLD + self.samples).collect();
        let mut element = e.build();
        let mut rng = Pcg64::seed_from_u64(seed ^ 0x5eed);
        let noise = self.colour.filter()?;
        let len = u.len();
        let sim = simulate(
            &u,
            element.as_mut(),
            &self.plant.lti,
            &noise,
            Some(self.snr_db),
            HOLD..len,
            &mut rng,
        )?;
        Ok(SimulatedRecord {
            u,
            y: sim.y,
            y_clean: sim.y_clean,
        })
    }
}
