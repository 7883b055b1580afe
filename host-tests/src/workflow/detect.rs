//! An integrating record found in the data: when the request leaves the question open
//! ([`IdentifyRequest::detect_integrating`]), the record is tested for a unit root in its
//! output ([`unit_root`], the augmented Dickey–Fuller test with the input's regressor
//! channels as covariates) before anything is identified. A unit root that the test does not
//! reject at 1 % routes the record to the integrating identification (one pole fixed at
//! `z = 1`, the stable part on the output's increments), with a note; a stable plant's record
//! rejects it and is identified as it is.
//!
//! Only the desktop's refined identification of one open-loop record asks: the paper's
//! estimator, a closed-loop estimate, several experiments, a detrended record and the
//! element's simulation fit (which the integrating route cannot run) keep the record as
//! given.

use super::{ElementFit, IdentifyRequest, Syntax};
use crate::model::Record;
use crate::validation::residual::regressor;
use crate::validation::unit_root::{CRITICAL_1PCT, UnitRoot, unit_root};

/// Input lags of the test's covariates (`0 … LAGS`).
pub const LAGS: usize = 4;

/// Whether `request` on `record` asks for the test.
fn asks(request: &IdentifyRequest, record: &Record) -> bool {
    request.detect_integrating
        && !request.integrating
        && request.refine
        && !request.detrend
        && request.reference.is_none()
        && request.fit != ElementFit::Simulation
        && record.starts.len() <= 1
}

/// The unit-root test of `record` (after its hold) on the one-segment regressor of
/// `[umin, umax]`; `None` when the record is too short for it.
pub fn test(record: &Record, umin: f64, umax: f64) -> Option<UnitRoot> {
    let from = record.hold.min(record.len());
    let knots = [umin, umax];
    let (_, z, _, _) = regressor(&record.u[from..], &knots, &knots, true);
    unit_root(&z, &record.y[from..], &record.time[from..], LAGS)
}

/// `request` as carried out on `record`: routed to the integrating identification, with the
/// note that says why, when it asks for the test ([`asks`]) and the unit root stands; else as
/// it is.
pub(crate) fn route(
    request: &IdentifyRequest,
    record: &Record,
) -> (IdentifyRequest, Option<String>) {
    let (on, off) = match request.syntax {
        Syntax::Cli => ("--integrating", "--integrating no"),
        Syntax::Python => ("integrating=True", "integrating=False"),
    };
    let found = asks(request, record)
        .then(|| test(record, request.umin, request.umax))
        .flatten()
        .filter(|t| !t.rejected());
    match found {
        Some(t) => (
            IdentifyRequest {
                integrating: true,
                ..request.clone()
            },
            Some(format!(
                "the output integrates: an ARX model of it on the input ({} output lags) keeps \
                 a unit root (Dickey–Fuller τ = {:.2}, not below the 1 % critical value \
                 {CRITICAL_1PCT}; Σaᵢ − 1 = {:+.4}), so the record is identified as \
                 integrating ({on}); {off} identifies it as it is",
                t.ar_order, t.tau, t.rho
            )),
        ),
        None => (request.clone(), None),
    }
}
