//! Why a model class beyond the linear dynamics could not be fitted.

use crate::hysteresis::HysteresisError;

/// Why a model class beyond the linear dynamics could not be fitted.
#[derive(Clone, Debug, PartialEq)]
pub enum DynamicsError {
    /// The model has no state or the record no samples.
    Empty {
        /// Model order.
        order: usize,
        /// Samples.
        samples: usize,
    },
    /// The starting model does not simulate the record (non-finite output).
    NotSimulating,
    /// Level-dependent stores start from an order-2 model.
    NotOrderTwo {
        /// The model's order.
        order: usize,
    },
    /// The element with memory (play operator or relay) could not be fitted.
    Hysteresis(HysteresisError),
}

impl std::fmt::Display for DynamicsError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            DynamicsError::Empty { order, samples } => write!(
                f,
                "nonlinear dynamics need a model of order ≥ 1 and data (order {order}, {samples} samples)"
            ),
            DynamicsError::NotSimulating => write!(
                f,
                "the model to extend does not simulate the record (non-finite output); fit the linear model first"
            ),
            DynamicsError::NotOrderTwo { order } => write!(
                f,
                "level-dependent stores (a cascade of two stores) start from an order-2 model; the model has order {order}"
            ),
            DynamicsError::Hysteresis(e) => write!(f, "element with memory: {e}"),
        }
    }
}

impl std::error::Error for DynamicsError {}
