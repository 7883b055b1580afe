//! A simulated output: with noise, and without.

use super::error::SimulateError;
use super::noise::{Noise, output_noise};

/// A simulated output.
#[derive(Clone, Debug, PartialEq)]
pub struct Output {
    /// The output, noise included.
    pub y: Vec<f64>,
    /// The noise-free output.
    pub y_clean: Vec<f64>,
    /// Standard deviation of the white noise `e` behind the output noise (0 without noise).
    pub e_std: f64,
}

impl Output {
    /// A noise-free output.
    pub fn clean(y_clean: Vec<f64>) -> Self {
        Self {
            y: y_clean.clone(),
            y_clean,
            e_std: 0.0,
        }
    }

    /// `y_clean` with the noise added.
    pub fn noisy(y_clean: Vec<f64>, noise: &Noise) -> Result<Self, SimulateError> {
        let (v, e_std) = output_noise(&y_clean, noise)?;
        Ok(Self {
            y: y_clean.iter().zip(&v).map(|(a, b)| a + b).collect(),
            y_clean,
            e_std,
        })
    }
}
