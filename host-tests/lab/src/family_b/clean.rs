//! The input of one record and its noise-free output: what both the open loop
//! ([`generate`](mod@super::generate)) and the closed loop ([`super::closed_loop`]) simulate
//! before the noise and the class's additions are put on.

/// The input of one record and its noise-free output.
#[derive(Clone, Debug, PartialEq)]
pub struct Clean {
    /// Input.
    pub u: Vec<f64>,
    /// Noise-free output.
    pub y: Vec<f64>,
}
