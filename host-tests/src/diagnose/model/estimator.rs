//! The estimator of the Hammerstein part of every structure a diagnosis fits: the open-loop
//! subspace estimate, or — for a closed-loop record whose controller reference was logged —
//! the closed-loop consistent estimate from the reference ([`crate::closed_loop`]).
//!
//! With a reference, the poles come from the instruments built from the reference and are
//! not refined by the simulation error afterwards: the output-error fit runs on the measured
//! input, which the controller computed from earlier noise, so it would pull the poles back
//! toward the biased open-loop answer. The border values, `B` and `D` are still refit by least
//! squares on the output with `A` and `C` fixed (the paper's Remark 5), as in the open-loop
//! fit; the extensions (output map, element with memory, stores, noise model, …) are fitted
//! on top of that Hammerstein part as usual.

use serde::Serialize;

use super::record::Record;
use crate::closed_loop::identify_closed_loop;
use crate::diagnose::error::DiagnoseError;
use crate::identify::{HostModel, IdentifyOptions, identify};

/// Which estimate the Hammerstein part is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Estimator {
    /// PI-MOESP on the record (the paper's open-loop estimate); the poles are then refined by
    /// the simulation error as [`FitOptions::refine_poles`](super::FitOptions::refine_poles)
    /// says.
    OpenLoop,
    /// PI-MOESP on the data projected on instruments built from the logged reference
    /// ([`identify_closed_loop`]), consistent in closed loop; of the order given, or of the
    /// open-loop estimate's order; the poles are not refined.
    Reference,
}

impl Estimator {
    /// The estimator of a record: [`Estimator::Reference`] when it carries a reference.
    pub fn of(rec: &Record) -> Self {
        match rec.reference {
            Some(_) => Estimator::Reference,
            None => Estimator::OpenLoop,
        }
    }

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
    pub fn refines_poles(self) -> bool {
        self == Estimator::OpenLoop
    }
}

/// The Hammerstein part of the (delayed) input `ud` and the target output, with the
/// (equally delayed) reference when there is one.
pub(super) fn estimate(
    ud: &[f64],
    target: &[f64],
    reference: Option<&[f64]>,
    opts: &IdentifyOptions,
) -> Result<HostModel, DiagnoseError> {
    let Some(r) = reference else {
        return identify(ud, target, opts).map_err(DiagnoseError::Identify);
    };
    // Feedback biases the poles, not the count of states: the open-loop order is kept.
    let order = match opts.order {
        Some(n) => n,
        None => {
            identify(ud, target, opts)
                .map_err(DiagnoseError::Identify)?
                .order
        }
    };
    identify_closed_loop(ud, target, r, opts, order).map_err(DiagnoseError::Reference)
}
