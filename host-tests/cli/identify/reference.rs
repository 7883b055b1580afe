//! `hsid identify --reference-column`: the closed-loop consistent estimate from a logged
//! reference in place of the open-loop subspace model.

use hsid_host::choose::Best;
use hsid_host::closed_loop::identify_closed_loop;

use super::IdentifyArgs;
use super::records::Records;
use crate::args::NonlinearityArg;
use crate::failure::{Failure, outln};

/// The estimator, in words.
pub const ESTIMATOR: &str =
    "closed-loop subspace (PI-MOESP on instruments from the reference column), not refined";

/// The refusal of `--reference-column NAME` with `--nonlinearity static` (identify's and
/// diagnose's).
pub fn static_refused(name: &str) -> Failure {
    format!(
        "--reference-column {name} estimates a two-path element (backlash or switch): drop --nonlinearity static"
    )
    .into()
}

/// Refuses what the closed-loop estimate does not cover: a static element, several records.
pub fn refuse_bad_flags(a: &IdentifyArgs) -> Result<(), Failure> {
    let Some(name) = &a.reference_column else {
        return Ok(());
    };
    if a.nonlinearity == NonlinearityArg::Static {
        return Err(static_refused(name));
    }
    if a.data.len() > 1 {
        return Err(format!(
            "--reference-column {name} takes one record (one --data): join the experiments into one file"
        )
        .into());
    }
    Ok(())
}

/// Replaces the open-loop model of `best` by the closed-loop estimate with the reference
/// column `name`, with the same options (knots, horizons, hold) and order; says so, with the
/// open-loop poles it replaces.
pub fn closed_loop(best: &mut Best, records: &Records, name: &str) -> Result<(), Failure> {
    let (u, y, r) = (&records.u, &records.y, &records.r);
    let order = best.model.order;
    let model = identify_closed_loop(u, y, r, &best.options, order).map_err(|e| {
        format!(
            "{} (reference column {name}): {e}",
            records.first().display()
        )
    })?;
    let poles = |m: &hsid_host::identify::HostModel| {
        let text: Vec<String> = m
            .poles()
            .iter()
            .map(|(re, im)| format!("{re:.4}{im:+.4}i"))
            .collect();
        text.join(", ")
    };
    outln!(
        "closed loop: the model is estimated with instruments from the reference column \"{name}\" (order {order}, as the open-loop estimate; see docs/closed-loop.md): poles {} (open-loop estimate: {})",
        poles(&model),
        poles(&best.model)
    )?;
    best.model = model;
    best.fit = None;
    Ok(())
}
