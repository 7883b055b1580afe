//! Play between two dynamic parts: a two-mass drive whose gear play sits between the motor
//! and the load, fitted by simulation error from the current model.
//!
//! Where the motor side is fast, play in a drive is the input backlash
//! [`crate::hysteresis`] fits; where it is not, the play sits between two dynamic parts and
//! the direction dependence survives the input element. This module carries that case:
//!
//! * [`model`]: the two parts (the motor's speed and the load's) coupled by a shaft with a
//!   dead zone on the difference of their angles, why that form and not a play operator in a
//!   cascade, the units of the play, and the model's own simulator.
//! * [`fit`]: the start from the current model's poles (split between the rigid-body mode
//!   and the shaft's resonance, a few inertia ratios and play sizes) and the simulation-error
//!   fit by the shared Levenberg–Marquardt.
//! * [`uncertainty`]: the play's standard deviation from `σ̂² (JᵀJ)⁻¹`.
//! * [`error`]: why a fit gave no model.

pub mod error;
pub mod fit;
pub mod model;
pub mod uncertainty;

pub use error::SandwichError;
pub use fit::{
    TwoMassFit, TwoMassOptions, fit_two_mass, fit_two_mass_from_poles, fit_two_mass_skipping,
};
pub use model::{Start, TwoMassPlay};
