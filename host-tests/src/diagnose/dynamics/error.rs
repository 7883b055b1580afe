//! Why a model class beyond the linear dynamics could not be fitted.

use crate::friction::FrictionError;
use crate::hysteresis::HysteresisError;
use crate::sandwich::SandwichError;

/// Why a model class beyond the linear dynamics could not be fitted.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum DynamicsError {
    /// The model has no state or the record no samples.
    #[error(
        "nonlinear dynamics need a model of order ≥ 1 and data (order {order}, {samples} samples)"
    )]
    Empty {
        /// Model order.
        order: usize,
        /// Samples.
        samples: usize,
    },
    /// The starting model does not simulate the record (non-finite output).
    #[error(
        "the model to extend does not simulate the record (non-finite output); fit the linear model first"
    )]
    NotSimulating,
    /// Level-dependent stores start from an order-2 model.
    #[error(
        "level-dependent stores (a cascade of two stores) start from an order-2 model; the model has order {order}"
    )]
    NotOrderTwo {
        /// The model's order.
        order: usize,
    },
    /// The element with memory (play operator or relay) could not be fitted.
    #[error("element with memory: {0}")]
    Hysteresis(#[source] HysteresisError),
    /// Friction on the velocity could not be fitted.
    #[error("friction: {0}")]
    Friction(#[source] FrictionError),
    /// The two-mass drive with play between motor and load could not be fitted.
    #[error("play between motor and load: {0}")]
    TwoMass(#[source] SandwichError),
}
