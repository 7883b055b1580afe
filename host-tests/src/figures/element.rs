//! The figures of a model whose element is the play operator (backlash) or the relay with
//! borders (switch) itself (`crate::hysteresis`, `identify --fit`): the borders `H_a`, `H_d`
//! with ±2σ bands, the element's output on the record and the measured points
//! (`element-borders.rs`), and, as for a two-path model, the Bode plot and poles of `G`
//! (`G(1) = 1`) and the measured output against the element model's simulation with its
//! residual. Bode and poles carry no bands: the fit's covariance is not mapped onto them.

use std::path::Path;

use super::error::FigureError;
use super::{
    Context, FigureSettings, RecordView, Written, bode, element_borders, output, residual,
};
use crate::hysteresis::uncertainty::Uncertainty;
use crate::hysteresis::{HysteresisFit, HysteresisModel};

/// Writes every figure of the fitted element model `fit` on `record` into `dir` (created
/// if missing): `borders.*` (the element), `bode-*`, `poles.*`, `output.*`, `residual*`.
pub fn write_element_figures(
    dir: &Path,
    fit: &HysteresisFit,
    record: &RecordView<'_>,
    settings: &FigureSettings,
) -> Result<Written, FigureError> {
    write_element_model_figures(dir, &fit.model, fit.uncertainty.as_ref(), record, settings)
}

/// Writes the figures of [`write_element_figures`] for an element model read from a file
/// (`validate`), with the borders' ±2σ bands when `uncertainty` is given (a model file keeps
/// no covariance of the borders, so `validate` draws none).
pub fn write_element_model_figures(
    dir: &Path,
    model: &HysteresisModel,
    uncertainty: Option<&Uncertainty>,
    record: &RecordView<'_>,
    settings: &FigureSettings,
) -> Result<Written, FigureError> {
    super::check_record(record, settings)?;
    std::fs::create_dir_all(dir).map_err(|source| FigureError::CreateDir {
        path: dir.to_path_buf(),
        source,
    })?;
    let host = model.to_host(record.u.len());
    let cx = Context {
        dir,
        model: &host,
        record: *record,
        simulated: crate::hysteresis::simulate::simulate(model, record.u),
        settings,
        uncertainty: None,
    };
    let mut out = Written::default();
    element_borders::write(&cx, model, uncertainty, &mut out)?;
    bode::write(&cx, &mut out)?;
    super::poles::write(&cx, &mut out)?;
    output::write(&cx, &mut out)?;
    residual::write(&cx, &mut out)?;
    Ok(out)
}
