//! A generality benchmark, written apart from the diagnosis' scenarios: random stable plants of
//! orders 1–4 (real and complex poles, some with a zero), backlash and switch elements whose
//! borders are unlike the paper's, SNR 10–40 dB, white and coloured noise, Table I records of
//! 6,000 samples, each model scored on a fresh validation record against the noise floor.

mod case;
mod element;
mod estimators;
mod plant;
mod score;

use std::fmt;

pub use case::{Case, Colour, HOLD, SimulatedRecord};
pub use element::{Element, random_element};
pub use estimators::{
    Estimator, SAMPLES, default_estimate, diagnose_estimate, paper_estimate, run_case,
};
pub use plant::{Plant, random_plant};
pub use score::{Estimate, Row, Score, confusion, score, table};

use hsid_host::sim::SimError;

/// Why a case could not be simulated.
#[derive(Debug)]
pub enum BenchError {
    /// The simulator refused the plant or the noise.
    Sim(SimError),
    /// The excitation refused the interval.
    Excitation(hsid::Error),
}

impl fmt::Display for BenchError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            BenchError::Sim(e) => write!(f, "simulation: {e}"),
            BenchError::Excitation(e) => write!(f, "excitation: {e}"),
        }
    }
}

impl std::error::Error for BenchError {}

impl From<SimError> for BenchError {
    fn from(e: SimError) -> Self {
        BenchError::Sim(e)
    }
}
