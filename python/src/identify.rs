//! `hsid.identify`: a model from numpy arrays, as `hsid identify` makes it from a CSV record.

use hsid_host::choose::{best_model, model_file};
use pyo3::prelude::*;

use crate::arrays::vector;
use crate::error::{Class, Failure};
use crate::model::Model;
use crate::settings::{self, Settings};

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
/// By default, as `hsid identify`: segments per path (7, 10 or 14), horizons and order are
/// chosen from the data and the model is refined by the prediction-error method. The paper's
/// estimator is `refine=False, segments=7, f=10, p=10`. `knots` (one array for both paths or a
/// pair) replaces uniform segments; `ts` (seconds) and `units` ({"input", "output"}) are
/// recorded in the model file. The GIL is released while identifying.
#[pyfunction]
#[pyo3(signature = (u, y, umin, umax, *, segments=None, knots=None, nonlinearity="backlash",
    f=None, p=None, order=None, hold=300, ts=None, units=None, refine=true))]
#[allow(clippy::too_many_arguments)]
pub fn identify(
    py: Python<'_>,
    u: &Bound<'_, PyAny>,
    y: &Bound<'_, PyAny>,
    umin: f64,
    umax: f64,
    segments: Option<&Bound<'_, PyAny>>,
    knots: Option<&Bound<'_, PyAny>>,
    nonlinearity: &str,
    f: Option<usize>,
    p: Option<usize>,
    order: Option<usize>,
    hold: usize,
    ts: Option<f64>,
    units: Option<&Bound<'_, PyAny>>,
    refine: bool,
) -> PyResult<Model> {
    let (u, y) = record(u, y, hold)?;
    if let Some(ts) = ts.filter(|t| !(t.is_finite() && *t > 0.0)) {
        return Err(Failure::new(
            Class::Settings,
            "sample_time",
            format!("ts={ts}: give the sample time in seconds, finite and positive"),
        )
        .into());
    }
    let units = settings::units(units)?;
    let Settings {
        options,
        choices,
        kind,
    } = settings::settings(
        umin,
        umax,
        settings::segments(segments)?,
        settings::knots(knots)?,
        settings::nonlinearity(nonlinearity)?,
        settings::horizons(f, p),
        order,
        hold,
        refine,
    )?;
    let file = py.detach(|| {
        best_model(&u, &y, &options, &choices)
            .map(|best| model_file(best, &u, &y, Some(kind)))
            .map_err(Failure::from)
    });
    let mut file = file?;
    file.sample_time = ts;
    file.units = units;
    Ok(Model::new(file))
}
