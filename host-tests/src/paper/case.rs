//! The two examples of Section IV and one simulated experiment of each: the true element,
//! plant and noise, the seeds of a run and the identification options of the Monte Carlo.

use hsid::Excitation;
use rand_core::SeedableRng;
use rand_pcg::Pcg32;

use crate::identify::IdentifyOptions;
use crate::sim::{
    Backlash, Lti, Nonlinearity, SimError, Switch, TruePaths, paper_backlash, paper_noise_model,
    paper_plant, paper_switch, simulate,
};
/// The two examples of Section IV.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Case {
    /// Case 1: the switch nonlinearity.
    Switch,
    /// Case 2: the backlash nonlinearity.
    Backlash,
}

impl Case {
    /// Lower-case name.
    pub fn name(self) -> &'static str {
        match self {
            Case::Switch => "switch",
            Case::Backlash => "backlash",
        }
    }

    fn id(self) -> u64 {
        match self {
            Case::Switch => 1,
            Case::Backlash => 2,
        }
    }
}

/// Monte Carlo settings; [`Default`] is the paper's.
#[derive(Clone, Debug, PartialEq)]
pub struct PaperConfig {
    /// Runs per case (paper: 100).
    pub runs: usize,
    /// Base seed; run `r` of a case uses seeds derived from `(seed, case, r)`.
    pub seed: u64,
    /// Hankel columns (paper: 4000).
    pub j: usize,
    /// Future horizon.
    pub f: usize,
    /// Past horizon.
    pub p: usize,
    /// Segments per path, uniform knots (paper: n_p = 7).
    pub segments: usize,
    /// Hold at `u_min` before the excitation, for μ0.
    pub hold: usize,
    /// Samples of the hold skipped while the plant settles.
    pub settle: usize,
    /// Signal-to-noise ratio in dB (paper: 10).
    pub snr_db: f64,
    /// Input interval (paper: [-3, 3]).
    pub u_min: f64,
    /// Input interval (paper: [-3, 3]).
    pub u_max: f64,
    /// Fixed model order, or automatic.
    pub order: Option<usize>,
    /// Border basis (coordinates of the regressor and of the rank-1 split).
    pub basis: hsid::Basis,
}

impl Default for PaperConfig {
    fn default() -> Self {
        Self {
            runs: 100,
            seed: 1,
            j: 4000,
            f: 10,
            p: 10,
            segments: 7,
            hold: 300,
            settle: 150,
            snr_db: 10.0,
            u_min: -3.0,
            u_max: 3.0,
            order: None,
            basis: hsid::Basis::Hat,
        }
    }
}

/// A seed for one purpose of one run (SplitMix64 finaliser over the inputs).
pub fn derive_seed(base: u64, case: u64, run: u64, purpose: u64) -> u64 {
    let mut z = base
        .wrapping_mul(0x9E37_79B9_7F4A_7C15)
        .wrapping_add(case << 48)
        .wrapping_add(run << 8)
        .wrapping_add(purpose);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// One simulated experiment: input and measured output, hold first.
#[derive(Clone, Debug)]
pub struct Experiment {
    /// Input record (hold included).
    pub u: Vec<f64>,
    /// Measured output.
    pub y: Vec<f64>,
    /// Noise-free output.
    pub y_clean: Vec<f64>,
}

/// The element, plant and noise model of a case.
pub fn case_system(case: Case) -> (Box<dyn Nonlinearity>, TruePaths, Lti, Lti) {
    let (nl, paths): (Box<dyn Nonlinearity>, TruePaths) = match case {
        Case::Switch => {
            let s: Switch = paper_switch();
            let p = s.true_paths(-3.0, 3.0);
            (Box::new(s), p)
        }
        Case::Backlash => {
            let b: Backlash = paper_backlash();
            let p = b.true_paths(-3.0, 3.0);
            (Box::new(b), p)
        }
    };
    (nl, paths, paper_plant(), paper_noise_model())
}

/// Why an experiment could not be simulated.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ExperimentError {
    /// The excitation's interval or hold is refused by the core's generator.
    #[error(transparent)]
    Excitation(#[from] hsid::Error),
    /// The simulation of the element, plant and noise failed.
    #[error(transparent)]
    Simulate(#[from] SimError),
}

/// Simulates run `run` of a case: the Table I excitation from the core's generator, the true
/// element, `G(q)` and the coloured noise at the requested SNR (over the excitation part).
pub fn experiment(
    case: Case,
    cfg: &PaperConfig,
    run: usize,
) -> Result<Experiment, ExperimentError> {
    let n = cfg.hold + cfg.j + cfg.f + cfg.p - 1;
    let rng = Pcg32::seed_from_u64(derive_seed(cfg.seed, case.id(), run as u64, 1));
    let u: Vec<f64> = Excitation::new(cfg.u_min, cfg.u_max, cfg.hold, rng)?
        .take(n)
        .collect();
    let (mut nl, _, plant, noise) = case_system(case);
    let mut noise_rng = Pcg32::seed_from_u64(derive_seed(cfg.seed, case.id(), run as u64, 2));
    let snr = cfg.snr_db.is_finite().then_some(cfg.snr_db);
    let sim = simulate(
        &u,
        nl.as_mut(),
        &plant,
        &noise,
        snr,
        cfg.hold..n,
        &mut noise_rng,
    )?;
    Ok(Experiment {
        u,
        y: sim.y,
        y_clean: sim.y_clean,
    })
}

/// The identification options of the Monte Carlo.
pub fn options(cfg: &PaperConfig) -> IdentifyOptions {
    let mut o = IdentifyOptions::uniform(cfg.u_min, cfg.u_max, cfg.segments, cfg.hold);
    o.f = cfg.f;
    o.p = cfg.p;
    o.settle = cfg.settle;
    o.order = cfg.order;
    o.basis = cfg.basis;
    o
}
