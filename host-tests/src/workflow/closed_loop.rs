//! The closed-loop consistent estimate from a logged reference in place of the open-loop
//! subspace model (docs/closed-loop.md).

use super::WorkflowError;
use crate::choose::Best;
use crate::closed_loop::identify_closed_loop;
use crate::identify::HostModel;
use crate::model::Record;

/// The estimator, in words.
pub(crate) const ESTIMATOR: &str =
    "closed-loop subspace (PI-MOESP on instruments from the reference column), not refined";

/// Replaces the open-loop model of `best` by the closed-loop estimate with the record's
/// reference (named `name`), with the same options (knots, horizons, hold) and order; the
/// note says so, with the open-loop poles it replaces.
pub fn replace(best: &mut Best, record: &Record, name: &str) -> Result<String, WorkflowError> {
    let r = record.reference.as_deref().unwrap_or_default();
    let order = best.model.order;
    let model =
        identify_closed_loop(&record.u, &record.y, r, &best.options, order).map_err(|error| {
            WorkflowError::ClosedLoop {
                name: name.to_string(),
                error,
            }
        })?;
    let note = format!(
        "closed loop: the model is estimated with instruments from the reference column \"{name}\" (order {order}, as the open-loop estimate; see docs/closed-loop.md): poles {} (open-loop estimate: {})",
        poles(&model),
        poles(&best.model)
    );
    best.model = model;
    best.fit = None;
    Ok(note)
}

/// The poles, as the note lists them.
fn poles(m: &HostModel) -> String {
    let text: Vec<String> = m
        .poles()
        .iter()
        .map(|(re, im)| format!("{re:.4}{im:+.4}i"))
        .collect();
    text.join(", ")
}
