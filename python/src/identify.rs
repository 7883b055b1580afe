//! `hsid.identify`: a model from numpy arrays, as `hsid identify` makes it from a CSV record.

use hsid::Basis;
use hsid_host::model::Record;
use hsid_host::validation::checks::{BEFORE_FIT, checks_text};
use hsid_host::workflow::{ElementFit, identify_record};
use pyo3::prelude::*;

use crate::arrays::vector;
use crate::error::{Class, Failure};
use crate::model::Model;
use crate::settings;

/// The samples of `u` and `y`: 1-D float arrays of equal length, longer than the hold.
pub fn record(
    u: &Bound<'_, PyAny>,
    y: &Bound<'_, PyAny>,
    hold: usize,
) -> Result<(Vec<f64>, Vec<f64>), Failure> {
    let (u, y) = (vector("u", u)?, vector("y", y)?);
    if u.len() != y.len() {
        return Err(Failure::new(
            Class::Data,
            "length_mismatch",
            format!(
                "u has {} samples but y has {}: give one y per u",
                u.len(),
                y.len()
            ),
        ));
    }
    if hold >= u.len() {
        return Err(Failure::new(
            Class::Data,
            "all_hold",
            format!(
                "{} samples, all inside the hold of {hold}: nothing left to identify from",
                u.len()
            ),
        ));
    }
    Ok((u, y))
}

/// Identifies a Hammerstein model (backlash, switch or static input element, then linear
/// dynamics) from the input `u` and the output `y` (1-D float arrays of equal length, every
/// input inside [umin, umax], the first `hold` samples a hold at umin).
///
/// The library's identify workflow, as `hsid identify` runs it: segments per path (7, 10 or
/// 14), horizons and order are chosen from the data and the model is refined by the
/// prediction-error method; with `fit="auto"` (the default) the element itself is fitted by
/// simulation error when the input reverses inside the range. `nonlinearity` names the
/// element; left out, the backlash is identified with the static element beside it (at the
/// same structure) and the better on the inner hold-out is returned. The paper's estimator is
/// `refine=False, segments=7, f=10, p=10`. `knots` (one array for both paths or a pair)
/// replaces uniform segments; `reference` (an array, one value per sample) gives the
/// closed-loop estimate; `integrating=True` fixes a pole at z = 1 (left out, the record is
/// tested for an output that integrates and identified so when it does, with a note;
/// `integrating=False` keeps it as given); `detrend=True` subtracts the
/// mean output (no hold); `mu0` is a known H(umin) without a hold; `ts` (seconds) and `units`
/// ({"input", "output"}) are recorded in the model file. `friction=True` fits Coulomb
/// friction and an offset on the model's velocity after the identification and returns that
/// model when it simulates the last quarter of the record better (docs/friction.md; with
/// `integrating=True`, `order=1`, `nonlinearity="static"`, `segments=1` and `ts` a note reads it
/// as a rigid body). What was chosen and done is in `Model.notes`. The GIL is released while
/// identifying.
#[pyfunction]
#[pyo3(signature = (u, y, umin, umax, *, segments=None, knots=None, nonlinearity=None,
    f=None, p=None, order=None, hold=300, ts=None, units=None, refine=true, integrating=None,
    detrend=false, mu0=None, fit="auto", reference=None, basis="hat", settle=None,
    friction=false))]
#[allow(clippy::too_many_arguments)]
pub fn identify(
    py: Python<'_>,
    u: &Bound<'_, PyAny>,
    y: &Bound<'_, PyAny>,
    umin: f64,
    umax: f64,
    segments: Option<&Bound<'_, PyAny>>,
    knots: Option<&Bound<'_, PyAny>>,
    nonlinearity: Option<&str>,
    f: Option<usize>,
    p: Option<usize>,
    order: Option<usize>,
    hold: usize,
    ts: Option<f64>,
    units: Option<&Bound<'_, PyAny>>,
    refine: bool,
    integrating: Option<bool>,
    detrend: bool,
    mu0: Option<f64>,
    fit: &str,
    reference: Option<&Bound<'_, PyAny>>,
    basis: &str,
    settle: Option<usize>,
    friction: bool,
) -> PyResult<Model> {
    let (u, y) = record(u, y, hold)?;
    let ts = settings::sample_time(ts)?;
    let units = settings::units(units)?;
    let mut request = settings::request(
        umin,
        umax,
        settings::segments(segments)?,
        settings::knots(knots)?,
        settings::nonlinearity(nonlinearity.unwrap_or("backlash"))?,
        settings::horizons(f, p),
        order,
        refine,
    );
    request.choose_element = nonlinearity.is_none();
    request.integrating = integrating == Some(true);
    request.detect_integrating = integrating.is_none();
    request.detrend = detrend;
    request.mu0 = mu0;
    request.settle = settle;
    request.friction = friction;
    request.fit = ElementFit::from_name(fit).ok_or_else(|| {
        Failure::new(
            Class::Settings,
            "fit",
            format!("fit={fit:?}: give \"auto\", \"none\" or \"simulation\""),
        )
    })?;
    request.basis = match basis {
        "hat" => Basis::Hat,
        "ramp" => Basis::Ramp,
        _ => {
            return Err(Failure::new(
                Class::Settings,
                "basis",
                format!("basis={basis:?}: give \"hat\" or \"ramp\""),
            )
            .into());
        }
    };
    let mut rec = Record::new(u, y)
        .map_err(|e| Failure::new(Class::Data, "length_mismatch", e.to_string()))?
        .with_hold(hold);
    if let Some(r) = reference.filter(|r| !r.is_none()) {
        rec = rec
            .with_reference(vector("reference", r)?)
            .map_err(|e| Failure::new(Class::Data, "length_mismatch", e.to_string()))?;
        request.reference = Some("reference".to_string());
    }
    (rec.ts, rec.units) = (ts, units);
    let id = crate::interrupt::interruptible(py, move || {
        identify_record(&rec, &request).map_err(Failure::from)
    })??;
    Ok(Model::with_notes(id.model_file(), identified_notes(&id)))
}

/// Everything the workflow said, in order: the notes before the model, the data checks (in
/// the command line's words) and the element's note.
fn identified_notes(id: &hsid_host::workflow::Identified) -> Vec<String> {
    let checks = checks_text(&id.checks, &BEFORE_FIT);
    id.notes
        .iter()
        .cloned()
        .chain(checks)
        .chain(id.element_note.iter().cloned())
        .collect()
}
