//! Why a model class of the example could not be fitted or was refused.

use hsid_host::diagnose::dynamics::DynamicsError;

/// Why a model class of the example could not be fitted or was refused.
#[derive(Clone, Debug, PartialEq)]
pub enum ClassError {
    /// The fit itself failed (no state, no data, no finite simulation).
    Fit(DynamicsError),
    /// The fitted model has more than one steady state for a constant input: from the lowest
    /// and the highest state the record visits it settles at different outputs (the plant
    /// is assumed to have one steady state per input level, the static gain curve).
    Multistable {
        /// The constant `h` where the steady states differ.
        level: f64,
        /// Two of the steady outputs it settles at.
        outputs: (f64, f64),
    },
    /// The internal-overflow class needs an order-2 model with real poles.
    NotTwoRealPoles {
        /// The model's poles `(re, im)`.
        poles: Vec<(f64, f64)>,
    },
}

impl std::fmt::Display for ClassError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ClassError::Fit(e) => e.fmt(f),
            ClassError::Multistable { level, outputs } => write!(
                f,
                "the fitted polynomial state term has more than one steady state at h = {level:.4} (outputs {:.4} and {:.4}, from the lowest and the highest state the record visits): refused",
                outputs.0, outputs.1
            ),
            ClassError::NotTwoRealPoles { poles } => write!(
                f,
                "the internal-overflow class needs an order-2 model with two real poles; the model has {poles:?}"
            ),
        }
    }
}

impl std::error::Error for ClassError {}

impl From<DynamicsError> for ClassError {
    fn from(e: DynamicsError) -> Self {
        ClassError::Fit(e)
    }
}
