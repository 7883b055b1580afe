//! Friction after the identification (`--friction`, Python `friction=True`): the model's
//! element and `G` with Coulomb friction and an offset on its velocity
//! ([`crate::friction`]), fitted by simulation error from the model the workflow reports, and
//! reported in its place only when it simulates the inner hold-out better.
//!
//! The hold-out is the one the linear baseline is scored on: the friction model is fitted on
//! the first [`FIT_FRACTION`] of the record (the rest left out of its error, the whole input
//! driving its simulation) and simulated to the end; the model without friction is the
//! identified one, fitted on the whole record (an advantage the friction model has to
//! overcome). For an integrating plant both simulate the position (the sum of the
//! increments), each from the initial position and velocity that fit the first part best.

use super::{IdentifyRequest, Lines, baseline::fit_percent};
use crate::choose::holdout::{FIT_FRACTION, holdout_start, nrmse};
use crate::friction::{
    Friction, FrictionFit, FrictionModel, FrictionOptions, Initial, Physical, VelocitySign,
    fit_friction, velocity_sign_arx,
};
use crate::identify::HostModel;
use crate::model::Record;
use crate::model_file::Units;

/// The friction model is reported when its hold-out NRMSE is below this share of the model's
/// without friction (a 4 % smaller squared error): a fit that only matches the model without
/// friction (a record with no friction, where `F_c` and `v_s` trade against `G`'s damping) keeps
/// the simpler model.
const REPORT_MARGIN: f64 = 0.98;

/// What the friction step found.
#[derive(Clone, Debug, PartialEq)]
pub struct FrictionStep {
    /// The friction model fitted on the whole record.
    pub fit: FrictionFit,
    /// Simulation NRMSE on the held-out part without friction (the identified model).
    pub without: f64,
    /// The same with friction (fitted on the first part).
    pub with: f64,
    /// The friction model is the one reported.
    pub reported: bool,
    /// The model as a rigid body, when it reads as one.
    pub physical: Option<Physical>,
    /// The residual test of the identified model: does its residual depend on the direction
    /// it moves? `None` where it cannot be run (the model moves one way only).
    pub evidence: Option<VelocitySign>,
}

/// The friction step on `record` (as identified) from `model`; `Err` with the line that says
/// why it gave nothing.
pub(crate) fn step(
    record: &Record,
    request: &IdentifyRequest,
    model: &HostModel,
) -> Result<(FrictionStep, Lines), String> {
    let flag = request.syntax.name(super::Field::Friction);
    let (u, y) = (&record.u, &record.y);
    let cut = holdout_start(y.len(), 0);
    let skip: Vec<bool> = (0..y.len()).map(|t| t >= cut).collect();
    let opts = FrictionOptions::default();
    let integrating = request.integrating;
    let fail = |e: crate::friction::FrictionError| format!("{flag}: not fitted: {e}");
    let part = fit_friction(u, y, &skip, model, integrating, &opts).map_err(fail)?;
    // The scores: the position of an integrating plant, else the output.
    let target: Vec<f64> = match integrating {
        true => crate::integrating::integrate(y, 0.0),
        false => y.clone(),
    };
    let plain = FrictionModel::normalised_plain(model, integrating);
    let plain_start = match integrating {
        true => plain.initial_from(u, &target[..cut]),
        false => Initial::Rest {
            u_start: model.u_min(),
        },
    };
    let score = |sim: &[f64]| nrmse(&target[cut..], &sim[cut..]).unwrap_or(f64::INFINITY);
    let plain_sim = plain.simulate_from(u, plain_start);
    let without = score(&plain_sim);
    let h = model.element_output_from(u, model.u_min());
    let evidence = direction_evidence(&plain_sim, y, &h, model.order);
    let with = score(&part.model.simulate_from(u, part.initial));
    let fit = fit_friction(u, y, &[], model, integrating, &opts).map_err(fail)?;
    let reported = with < REPORT_MARGIN * without;
    let physical = record.ts.and_then(|ts| Physical::of(&fit.model, ts));
    let mut lines = vec![evidence_line(evidence.as_ref(), flag)];
    lines.push(friction_line(&fit.model.friction, flag, integrating));
    let what = match integrating {
        true => "the position",
        false => "the output",
    };
    let verdict = match reported {
        true => "the model with friction is reported",
        false => {
            "the model without friction is kept (friction did not simulate the held-out samples better)"
        }
    };
    lines.push(format!(
        "{flag}: {what} simulated on the last {:.0} % of the record (the model with friction \
         fitted on the first {:.0} %): fit {:.1} % without friction, {:.1} % with: {verdict}",
        100.0 * (1.0 - FIT_FRACTION),
        100.0 * FIT_FRACTION,
        fit_percent(without),
        fit_percent(with),
    ));
    if let Some(p) = &physical {
        lines.push(physical_line(p, record.units.as_ref(), flag));
    }
    Ok((
        FrictionStep {
            fit,
            without,
            with,
            reported,
            physical,
            evidence,
        },
        lines,
    ))
}

/// The direction test in the identified model's equation ([`velocity_sign_arx`]): `sim` its
/// simulation (the position of an integrating plant), `s` the record's output (an integrating
/// plant's increments), `h` its element's output, `n` its order.
fn direction_evidence(sim: &[f64], s: &[f64], h: &[f64], n: usize) -> Option<VelocitySign> {
    let velocity = crate::friction::evidence::change_from_rest(sim);
    velocity_sign_arx(s, h, &velocity, n)
}

/// The evidence's line.
fn evidence_line(e: Option<&VelocitySign>, flag: &str) -> String {
    match e {
        Some(e) => format!(
            "{flag}: the identified model's equation error {} on the direction it moves (the \
             sign of its simulated velocity as a regressor beside its ARX terms: coefficient \
             {:+.3e}, t = {:.1} with Newey–West errors over {} samples, a Coulomb force of \
             {:.1} % of the element's output's spread; the test fires beyond |t| = {} and {} %)",
            if e.fires() {
                "depends"
            } else {
                "does not depend significantly"
            },
            e.difference,
            e.t,
            e.samples,
            100.0 * e.force_share,
            VelocitySign::THRESHOLD,
            100.0 * VelocitySign::MIN_FORCE_SHARE
        ),
        None => format!(
            "{flag}: the identified model moves one way only (or the regression is singular): \
             its equation error cannot be tested for the direction of motion"
        ),
    }
}

/// The friction's line, in the element's output units.
fn friction_line(f: &Friction, flag: &str, integrating: bool) -> String {
    let velocity = match integrating {
        true => "the increment per sample",
        false => "the output's change per sample",
    };
    format!(
        "{flag}: Coulomb {:.6} and offset {:.6} (in the units of the element's output), the \
         sign smoothed over {:.3e} of {velocity}, the element's output {} sample(s) late",
        f.coulomb, f.offset, f.velocity_scale, f.delay
    )
}

/// The rigid-body reading's line, with units when they are known.
fn physical_line(p: &Physical, units: Option<&Units>, flag: &str) -> String {
    let (i, o) = match units {
        Some(u) => (u.input.as_str(), u.output.as_str()),
        None => ("input units", "output units"),
    };
    format!(
        "{flag}: as a rigid body driven by the input (a force): mass {:.4} {i} s²/{o}, viscous \
         friction {:.4} {i} s/{o}, Coulomb friction {:.4} {i}, offset {:.4} {i}",
        p.mass, p.viscous, p.coulomb, p.offset
    )
}
