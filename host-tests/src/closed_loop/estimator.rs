//! Which estimate a model's Hammerstein part is: the open-loop subspace estimate, or the
//! closed-loop consistent estimate from a logged reference ([`identify_closed_loop`](super::identify_closed_loop)). The
//! feedback check words its warning by it; the diagnosis fits every structure with it.

use serde::Serialize;

/// Which estimate the Hammerstein part is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Estimator {
    /// PI-MOESP on the record (the paper's open-loop estimate); the poles are then refined by
    /// the simulation error as [`FitOptions::refine_poles`](crate::diagnose::model::FitOptions::refine_poles)
    /// says.
    OpenLoop,
    /// PI-MOESP on the data projected on instruments built from the logged reference
    /// ([`identify_closed_loop`](super::identify_closed_loop)), consistent in closed loop; of the order given, or of the
    /// open-loop estimate's order; the poles are not refined.
    Reference,
}

impl Estimator {
    /// The estimator in words, for the reports.
    pub fn describe(self) -> &'static str {
        match self {
            Estimator::OpenLoop => "open-loop subspace (PI-MOESP)",
            Estimator::Reference => {
                "closed-loop subspace (PI-MOESP on instruments from the reference), poles not refined"
            }
        }
    }

    /// Whether the poles may be refined by the simulation error after the subspace step.
    pub(crate) fn refines_poles(self) -> bool {
        self == Estimator::OpenLoop
    }
}
