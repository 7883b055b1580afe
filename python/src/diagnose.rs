//! `hsid.diagnose`: the diagnosis of a record, as the JSON report `hsid diagnose --json`
//! writes.

use hsid_host::diagnose::report;
use hsid_host::diagnose::{DiagnoseError, DiagnoseOptions, Validation, diagnose as run};
use hsid_host::identify::IdentifyOptions;
use hsid_host::model::{Element, Record};
use pyo3::prelude::*;

use crate::arrays::vector;
use crate::error::{Class, Failure};
use crate::settings;

/// Diagnoses the record `(u, y)`: identifies the paper's model, checks the data against the
/// method's assumptions, tests the residuals and adds the effects that improve the hold-out
/// fit; returns the JSON report of `hsid diagnose --json` as a dict.
///
/// Validation: `u_val, y_val` (a separate record whose first `validation_skip` samples, the
/// hold by default, are left out), else the last `1 - split` of the samples after the hold.
/// `umin`/`umax` default to the range of the inputs, `f = p = 10`, 7 segments per path.
/// `ts` (seconds) and `units` ({"input", "output"}), checked as `identify` checks them, are
/// added to the report as `"ts"` and `"units"` (the command line puts them in its HTML page
/// and `--model-out` file); without them the dict is the command line's JSON report.
#[pyfunction]
#[pyo3(signature = (u, y, umin=None, umax=None, *, u_val=None, y_val=None, split=0.7,
    validation_skip=None, nonlinearity="backlash", segments=7, knots=None, order=None,
    hold=300, f=None, p=None, ts=None, units=None))]
#[allow(clippy::too_many_arguments)]
pub fn diagnose<'py>(
    py: Python<'py>,
    u: &Bound<'py, PyAny>,
    y: &Bound<'py, PyAny>,
    umin: Option<f64>,
    umax: Option<f64>,
    u_val: Option<&Bound<'py, PyAny>>,
    y_val: Option<&Bound<'py, PyAny>>,
    split: f64,
    validation_skip: Option<usize>,
    nonlinearity: &str,
    segments: usize,
    knots: Option<&Bound<'py, PyAny>>,
    order: Option<usize>,
    hold: usize,
    f: Option<usize>,
    p: Option<usize>,
    ts: Option<f64>,
    units: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyAny>> {
    let ts = settings::sample_time(ts)?;
    let units = settings::units(units)?;
    let est = record(vector("u", u)?, vector("y", y)?)?;
    let val = match (u_val, y_val) {
        (Some(u), Some(y)) => Some(record(vector("u_val", u)?, vector("y_val", y)?)?),
        (None, None) => None,
        _ => {
            return Err(Failure::new(
                Class::Settings,
                "validation",
                "give both u_val and y_val, or neither",
            )
            .into());
        }
    };
    let (lo, hi) = std::iter::once(&est)
        .chain(val.as_ref())
        .flat_map(|r| r.u.iter())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &v| {
            (l.min(v), h.max(v))
        });
    let knots = settings::knots(knots)?;
    let umin = umin
        .or(knots.as_ref().and_then(|k| k.0.first().copied()))
        .unwrap_or(lo);
    let umax = umax
        .or(knots.as_ref().and_then(|k| k.0.last().copied()))
        .unwrap_or(hi);
    let kind = settings::nonlinearity(nonlinearity)?;
    let opts = options(
        umin,
        umax,
        segments,
        knots,
        kind,
        settings::horizons(f, p),
        order,
        hold,
    )?;
    let validation = match val {
        Some(record) => Validation::Separate {
            record,
            skip: validation_skip.unwrap_or(hold),
        },
        None => Validation::Split(split),
    };
    let text = crate::interrupt::interruptible(py, move || {
        let d = run(&est, &validation, &opts).map_err(Failure::from)?;
        serde_json::to_string(&report::to_json(&d))
            .map_err(|e| Failure::new(Class::Data, "json", e.to_string()))
    })??;
    let report = py.import("json")?.call_method1("loads", (text,))?;
    if let Some(ts) = ts {
        report.set_item("ts", ts)?;
    }
    if let Some(u) = units {
        let d = pyo3::types::PyDict::new(py);
        d.set_item("input", u.input)?;
        d.set_item("output", u.output)?;
        report.set_item("units", d)?;
    }
    Ok(report)
}

/// The diagnosis settings of `hsid diagnose` for these keywords.
#[allow(clippy::too_many_arguments)]
fn options(
    umin: f64,
    umax: f64,
    segments: usize,
    knots: Option<settings::KnotPair>,
    kind: Element,
    horizons: Option<(usize, usize)>,
    order: Option<usize>,
    hold: usize,
) -> Result<DiagnoseOptions, Failure> {
    if segments == 0 {
        return Err(Failure::new(
            Class::Settings,
            "segments",
            "segments=0: each path needs at least one segment",
        ));
    }
    let s = settings::settings(
        umin,
        umax,
        Some(settings::SegmentArg::Fixed(segments)),
        knots,
        kind,
        horizons,
        order,
        hold,
        false,
    )?;
    let id: IdentifyOptions = s;
    let nonlinearity = kind;
    Ok(DiagnoseOptions::new(id, nonlinearity))
}

/// The record of `u` and `y`; a length mismatch is reported as the diagnosis reports it.
fn record(u: Vec<f64>, y: Vec<f64>) -> Result<Record, Failure> {
    Record::new(u, y).map_err(|e| Failure::from(DiagnoseError::from(e)))
}
