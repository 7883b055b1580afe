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

pub use crate::closed_loop::Estimator;
use crate::closed_loop::identify_closed_loop;
use crate::diagnose::error::DiagnoseError;
use crate::identify::{HostModel, IdentifyOptions, identify};
use crate::model::Record;

impl Estimator {
    /// The estimator of a record: [`Estimator::Reference`] when it carries a reference.
    pub fn of(rec: &Record) -> Self {
        match rec.reference {
            Some(_) => Estimator::Reference,
            None => Estimator::OpenLoop,
        }
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
