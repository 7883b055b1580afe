//! Simulated Table I experiments with one effect the identifier is not told about, for the
//! tests and the confusion table.
//!
//! Two plants (the paper's second-order `G` and a first-order lag), two elements unlike the
//! paper's (a switch on `[−2, 4]` with `tanh` borders clipped at −1, a backlash on
//! `[−2.5, 2.5]` with shifted `tanh` borders), white output noise at 20 dB, and at most one of
//! the catalog's effects:
//!
//! | effect | what the simulated plant does | size |
//! |---|---|---|
//! | `offset_drift` | sensor drift: a ramp added to the output | 6 σ_v at the end |
//! | `input_delay` | three extra samples of transport delay | — |
//! | `unmodeled_dynamics` | a sensor lag `0.25/(1 − 0.75 q⁻¹)` after `G` | — |
//! | `output_nonlinearity` | the output clipped at the 70th percentile (overflow) | — |
//! | `periodic_disturbance` | a sinusoid of period 23.7 samples | RMS 2 σ_v |
//! | `colored_noise` | the noise is `G_v e` with the paper's `G_v` instead of white | same SNR |
//! | `outliers` | 1.5 % of the samples get spikes of ±8…15 σ_v | — |
//!
//! The identification is told the plant's order (2 or 1), the element's interval, uniform
//! knots (8 segments per path) and horizons `f = p` that cover the plant's dominant time
//! constant (12 for the paper's G, 10 for the first-order lag); the record (hold of 300
//! samples and 5000 excitation samples) is split 70/30 into estimation and validation.

use rand::RngExt;
use rand_core::SeedableRng;
use rand_distr::{Distribution, StandardNormal};
use rand_pcg::Pcg32;

use hsid_host::diagnose::{DiagnoseError, DiagnoseOptions, Diagnosis, Effect, Validation};
use hsid_host::identify::IdentifyOptions;
use hsid_host::model::{Element, Record};
use hsid_host::paper::derive_seed;
use hsid_host::sim::{
    Backlash, Lti, Nonlinearity as SimElement, Switch, paper_noise_model, paper_plant,
};
use hsid_host::sim::{table1_excitation, variance, with_hold};

/// The linear part of a scenario.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Plant {
    /// The paper's `G(q)` (second order).
    Paper,
    /// `G(q) = q⁻¹ 0.2 / (1 − 0.8 q⁻¹)`.
    FirstOrder,
}

impl Plant {
    /// Both plants.
    pub const ALL: [Plant; 2] = [Plant::Paper, Plant::FirstOrder];

    /// Name.
    pub fn name(self) -> &'static str {
        match self {
            Plant::Paper => "paper G",
            Plant::FirstOrder => "first order",
        }
    }

    /// Order.
    pub fn order(self) -> usize {
        match self {
            Plant::Paper => 2,
            Plant::FirstOrder => 1,
        }
    }

    /// The transfer function.
    pub fn lti(self) -> Lti {
        match self {
            Plant::Paper => paper_plant(),
            Plant::FirstOrder => {
                Lti::new(vec![0.0, 0.2], vec![1.0, -0.8]).unwrap_or_else(|_| paper_plant())
            }
        }
    }
}

/// One simulated experiment.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Scenario {
    /// The undeclared effect (`None`: clean data).
    pub effect: Option<Effect>,
    /// The plant.
    pub plant: Plant,
    /// Backlash or switch.
    pub kind: Element,
    /// Seed.
    pub seed: u64,
    /// Excitation samples after the hold.
    pub samples: usize,
    /// SNR of the output noise, dB.
    pub snr_db: f64,
}

impl Scenario {
    /// A scenario with the defaults (5000 samples, 20 dB).
    pub fn new(effect: Option<Effect>, plant: Plant, kind: Element, seed: u64) -> Self {
        Self {
            effect,
            plant,
            kind,
            seed,
            samples: 5000,
            snr_db: 20.0,
        }
    }
}

/// The simulated data with what the diagnosis needs and the truth to score it.
#[derive(Clone, Debug)]
pub struct ScenarioData {
    /// The whole record (hold first).
    pub record: Record,
    /// Diagnosis options (the identifier is told the plant order and the interval only).
    pub options: DiagnoseOptions,
    /// Validation: the 70/30 split.
    pub validation: Validation,
    /// Noise floor of the simulation error: RMS of the noise actually added over the
    /// validation samples (outliers not counted).
    pub noise_floor: f64,
    /// Noise floor of the one-step prediction error: RMS of the white innovations over the
    /// validation samples.
    pub innovation_floor: f64,
}

/// Hold samples of the scenarios.
pub const HOLD: usize = 300;

/// The scenario's switch: `H_a(u) = max(−1, 1.3 tanh(0.9 (u − 1.2)))`,
/// `H_d(u) = max(−1, 1.3 tanh(0.9 (u + 0.2)))` on `[−2, 4]`.
pub fn scenario_switch() -> Switch {
    Switch::from_fns(
        |u| (1.3 * (0.9 * (u - 1.2)).tanh()).max(-1.0),
        |u| (1.3 * (0.9 * (u + 0.2)).tanh()).max(-1.0),
    )
}

/// The scenario's backlash: `H_a(u) = 1.1 tanh(0.7 (u − 0.9))`, `H_d(u) = 1.1 tanh(0.7 (u + 0.5))`
/// on `[−2.5, 2.5]`.
pub fn scenario_backlash() -> Backlash {
    Backlash::from_fns(
        |u| 1.1 * (0.7 * (u - 0.9)).tanh(),
        |u| 1.1 * (0.7 * (u + 0.5)).tanh(),
    )
}

/// The input interval of an element.
pub fn interval(kind: Element) -> (f64, f64) {
    match kind {
        Element::Switch => (-2.0, 4.0),
        _ => (-2.5, 2.5),
    }
}

/// Simulates a scenario.
pub fn generate(s: &Scenario) -> Result<ScenarioData, String> {
    let (u_min, u_max) = interval(s.kind);
    let effect_id = s.effect.map_or(0, |e| e as u64 + 1);
    let plant_id = s.plant as u64;
    let kind_id = s.kind as u64;
    let seed = |purpose: u64| derive_seed(s.seed, kind_id * 16 + plant_id, effect_id, purpose);
    let mut rng = Pcg32::seed_from_u64(seed(1));
    let ex = table1_excitation(s.samples, u_min, u_max, &mut rng).map_err(|e| e.to_string())?;
    let u = with_hold(HOLD, u_min, &ex);
    let n = u.len();
    let mut element: Box<dyn SimElement> = match s.kind {
        Element::Switch => Box::new(scenario_switch()),
        // Initial output 0 is clamped to H_d(u_min) = P_a(u_min) by the first sample.
        _ => Box::new(scenario_backlash()),
    };
    element.reset();
    let h: Vec<f64> = u.iter().map(|&v| element.step(v)).collect();
    let plant = s.plant.lti();
    let mut lin = plant.filter(&h);
    match s.effect {
        Some(Effect::InputDelay) => {
            let d = 3;
            let first = lin[0];
            lin = std::iter::repeat_n(first, d)
                .chain(lin[..n - d].iter().copied())
                .collect();
        }
        Some(Effect::UnmodeledDynamics) => {
            let lag = Lti::new(vec![0.25], vec![1.0, -0.75]).map_err(|e| e.to_string())?;
            // Start the lag at rest at the first value.
            let first = lin[0];
            let shifted: Vec<f64> = lin.iter().map(|v| v - first).collect();
            lin = lag.filter(&shifted).iter().map(|v| v + first).collect();
        }
        _ => {}
    }
    let var_y = variance(&lin[HOLD..]);
    let v_std = (var_y / 10f64.powf(s.snr_db / 10.0)).sqrt();
    let mut noise_rng = Pcg32::seed_from_u64(seed(2));
    let mut gauss = |sd: f64| -> Vec<f64> {
        (0..n)
            .map(|_| {
                let z: f64 = StandardNormal.sample(&mut noise_rng);
                sd * z
            })
            .collect()
    };
    let (v, e) = if s.effect == Some(Effect::ColoredNoise) {
        let gv = paper_noise_model();
        let e_std = v_std / gv.impulse_energy().sqrt();
        let e = gauss(e_std);
        (gv.filter(&e), e)
    } else {
        let e = gauss(v_std);
        (e.clone(), e)
    };
    let mut y: Vec<f64> = lin.clone();
    match s.effect {
        Some(Effect::OutputNonlinearity) => {
            let mut sorted = lin[HOLD..].to_vec();
            sorted.sort_by(f64::total_cmp);
            let cap = sorted[(sorted.len() * 7) / 10];
            for v in &mut y {
                *v = v.min(cap);
            }
        }
        Some(Effect::OffsetDrift) => {
            for (t, v) in y.iter_mut().enumerate() {
                *v += 6.0 * v_std * t as f64 / n as f64;
            }
        }
        Some(Effect::PeriodicDisturbance) => {
            let w = 2.0 * std::f64::consts::PI / 23.7;
            let phase = rng.random_range(0.0..std::f64::consts::TAU);
            let a = 2.0 * std::f64::consts::SQRT_2 * v_std;
            for (t, v) in y.iter_mut().enumerate() {
                *v += a * (w * t as f64 + phase).sin();
            }
        }
        _ => {}
    }
    for (yv, nv) in y.iter_mut().zip(&v) {
        *yv += nv;
    }
    if s.effect == Some(Effect::Outliers) {
        let mut orng = Pcg32::seed_from_u64(seed(3));
        for v in y.iter_mut().skip(HOLD) {
            if orng.random::<f64>() < 0.015 {
                let size = orng.random_range(8.0..15.0) * v_std;
                *v += if orng.random::<bool>() { size } else { -size };
            }
        }
    }
    let split = 0.7;
    let at = HOLD + ((n - HOLD) as f64 * split).round() as usize;
    let rms = |x: &[f64]| (x.iter().map(|a| a * a).sum::<f64>() / x.len().max(1) as f64).sqrt();
    let mut id = IdentifyOptions::uniform(u_min, u_max, 8, HOLD);
    id.order = Some(s.plant.order());
    // Horizons that cover the plant's dominant time constant: the paper's G settles in about
    // 60 samples, the first-order lag in about 15.
    let h = match s.plant {
        Plant::Paper => 12,
        Plant::FirstOrder => 10,
    };
    id.f = h;
    id.p = h;
    Ok(ScenarioData {
        record: Record::new(u, y).map_err(|e| e.to_string())?,
        options: DiagnoseOptions::new(id, s.kind),
        validation: Validation::Split(split),
        noise_floor: rms(&v[at..]),
        innovation_floor: rms(&e[at..]),
    })
}

/// A simulated two-tank plant for the level-dependent stores (`state_dependent_dynamics`),
/// integrated independently of the model class (50 Euler steps per sample; the stores use 4):
/// `x1' = q(u) − a1 √x1` with the upper tank overflowing above 3.2 (40 % of the excess
/// reaching the lower tank), `x2' = a1 √x1 − a2 √x2`, output `y = 2 x2` (volts), a pump curve
/// `q(u) = 0.01 u + 0.0012 u²` the identifier does not know. With [`Outflow::Linear`] the
/// outflows are proportional to the levels and nothing overflows (a linear plant: the stores
/// must not be needed).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TwoTanks {
    /// How the tanks drain.
    pub outflow: Outflow,
    /// RMS of the white sensor noise (V).
    pub noise: f64,
    /// Seed of the input and the noise.
    pub seed: u64,
}

/// How the tanks of [`TwoTanks`] drain.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Outflow {
    /// Through an opening: `a √x` (Torricelli), the upper tank overflowing.
    SquareRoot,
    /// Proportional to the level, no overflow.
    Linear,
}

/// Records of a [`TwoTanks`] experiment.
#[derive(Clone, Debug)]
pub struct TankRecords {
    /// Estimation record (1500 samples).
    pub estimation: Record,
    /// Validation record (1500 samples, another input).
    pub validation: Record,
    /// RMS of the noise added to the validation record.
    pub noise_floor: f64,
}

impl TwoTanks {
    /// The noise-free output for pump voltages `u` (from levels 1, 1).
    pub fn simulate(&self, u: &[f64]) -> Vec<f64> {
        let (mut x1, mut x2) = (1.0f64, 1.0f64);
        let steps = 50;
        let dt = 1.0 / steps as f64;
        u.iter()
            .map(|&v| {
                let y = 2.0 * x2;
                let q_in = 0.01 * v + 0.0012 * v * v;
                for _ in 0..steps {
                    let (q1, q2) = match self.outflow {
                        Outflow::SquareRoot => {
                            (0.05 * x1.max(0.0).sqrt(), 0.04 * x2.max(0.0).sqrt())
                        }
                        Outflow::Linear => (0.03 * x1, 0.025 * x2),
                    };
                    x1 += dt * (q_in - q1);
                    let over = match self.outflow {
                        Outflow::SquareRoot => (x1 - 3.2).max(0.0),
                        Outflow::Linear => 0.0,
                    };
                    x1 -= over;
                    x2 += dt * (q1 - q2) + 0.4 * over;
                }
                y
            })
            .collect()
    }

    /// An estimation and a validation experiment: pump voltages at random levels in
    /// [0, 10] V held for 15 to 60 samples, white sensor noise.
    pub fn records(&self) -> TankRecords {
        let mut rng = Pcg32::seed_from_u64(self.seed);
        let mut run = || {
            let mut u = Vec::with_capacity(1500);
            while u.len() < 1500 {
                let level = rng.random_range(0.0..10.0);
                let hold = rng.random_range(15..60);
                u.extend(std::iter::repeat_n(level, hold));
            }
            u.truncate(1500);
            let noise: Vec<f64> = (0..u.len())
                .map(|_| {
                    let z: f64 = StandardNormal.sample(&mut rng);
                    self.noise * z
                })
                .collect();
            let y: Vec<f64> = self
                .simulate(&u)
                .iter()
                .zip(&noise)
                .map(|(y, e)| y + e)
                .collect();
            let floor = (noise.iter().map(|e| e * e).sum::<f64>() / noise.len() as f64).sqrt();
            (Record::from_samples(u.into_iter().zip(y)), floor)
        };
        let (estimation, _) = run();
        let (validation, noise_floor) = run();
        TankRecords {
            estimation,
            validation,
            noise_floor,
        }
    }

    /// The diagnosis options for the experiment: static nonlinearity with 5 uniform segments
    /// on [0, 10] V, order 2, no hold.
    pub fn options() -> DiagnoseOptions {
        let mut id = IdentifyOptions::uniform(0.0, 10.0, 5, 0);
        id.order = Some(2);
        DiagnoseOptions::new(id, Element::Static)
    }

    /// Diagnoses the experiment (estimation record, validated on the separate validation
    /// record) with `options`; returns the diagnosis and the validation noise floor.
    pub fn diagnose(&self, options: &DiagnoseOptions) -> Result<(Diagnosis, f64), DiagnoseError> {
        let r = self.records();
        let d = hsid_host::diagnose::diagnose(
            &r.estimation,
            &Validation::Separate {
                record: r.validation,
                skip: 0,
            },
            options,
        )?;
        Ok((d, r.noise_floor))
    }
}
