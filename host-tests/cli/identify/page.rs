//! The HTML report of `hsid identify`: the subspace or refined model's page, or the fitted
//! element's (`--fit`), with the figures `--out` draws.

use hsid_host::model::Element;
use std::path::{Path, PathBuf};

use hsid_host::choose::Best;
use hsid_host::figures::{RecordView, Uncertainty};
use hsid_host::html::model_page::ModelRun;
use hsid_host::html::model_words::element_facts;
use hsid_host::html::{Fact, InlineFigure, Reproduction, figures};
use hsid_host::hysteresis::HysteresisFit;
use hsid_host::model_file::Units;
use hsid_host::workflow::Identified;

use super::IdentifyArgs;
use crate::failure::{Failure, outln};

/// Writes the HTML report of the identification `id` to `path`: the fitted element's page
/// when the element was fitted, else the model's.
pub fn write(
    a: &IdentifyArgs,
    path: &Path,
    id: &Identified,
    view: &RecordView<'_>,
) -> Result<(), Failure> {
    if let Some(fit) = &id.element {
        return write_element_page(a, path, fit, id, view);
    }
    let record = &id.record;
    let in_units = id.in_units();
    let run = ModelRun {
        title: format!("hsid identify: {}", names(&a.data)),
        element: id.request.element.into(),
        model: &id.estimate.model,
        memory: None,
        units: &in_units,
        parts: &record.parts(),
        skip: record.hold,
        estimation: Some(&id.best.options),
        extra: vec![Fact::new("estimator", id.estimate.estimator.clone())],
    };
    let page_figures = html_figures(a, &id.best, view, record.ts, record.units.as_ref())?;
    write_page(a, path, run, page_figures)
}

/// The record files, comma-separated.
fn names(data: &[PathBuf]) -> String {
    let names: Vec<String> = data.iter().map(|p| p.display().to_string()).collect();
    names.join(", ")
}

/// Writes the HTML report of `run` to `path`.
fn write_page(
    a: &IdentifyArgs,
    path: &Path,
    run: ModelRun<'_>,
    figures: Vec<InlineFigure>,
) -> Result<(), Failure> {
    run.page(figures, Reproduction::of_this_run(&a.data))
        .write(path)
        .map_err(|e| e.to_string())?;
    outln!("wrote {}", path.display())?;
    Ok(())
}

/// Writes the HTML report of the fitted element `fit` (`--fit`) on its estimation record:
/// the element's simulation, figures and reading in units, as printed and drawn by `--out`.
fn write_element_page(
    a: &IdentifyArgs,
    path: &Path,
    fit: &HysteresisFit,
    id: &Identified,
    record: &RecordView<'_>,
) -> Result<(), Failure> {
    let r = &id.record;
    let host = fit.model.to_host(r.len());
    let in_units = id.element_in_units().unwrap_or_else(|| id.in_units());
    let estimator = format!(
        "simulation-error fit of the element from the {} model: {} iterations, Σe² {:.6} -> {:.6}",
        if id.request.element == Element::Static {
            "static"
        } else {
            "two-path"
        },
        fit.iterations,
        fit.initial_cost,
        fit.cost
    );
    let mut extra = vec![Fact::new("estimator", estimator)];
    let gap_sd = fit.uncertainty.as_ref().and_then(|u| u.gap);
    extra.extend(element_facts(&fit.model, gap_sd, &in_units));
    let run = ModelRun {
        title: format!("hsid identify: {}", names(&a.data)),
        element: fit.model.kind.into(),
        model: &host,
        memory: Some(&fit.model),
        units: &in_units,
        parts: &[(&r.u, &r.y)],
        skip: r.hold,
        estimation: Some(&id.best.options),
        extra,
    };
    let settings = crate::figures::settings(&a.figures, r.ts, r.units.as_ref(), &host)?;
    let figures = figures::of_element(&fit.model, fit.uncertainty.as_ref(), record, &settings)
        .map_err(|e| e.to_string())?;
    write_page(a, path, run, figures)
}

/// The figures of the HTML report: those `--out` writes, drawn again into a scratch folder.
fn html_figures(
    a: &IdentifyArgs,
    best: &Best,
    record: &RecordView<'_>,
    ts: Option<f64>,
    units: Option<&Units>,
) -> Result<Vec<InlineFigure>, Failure> {
    let model = best.fit.as_ref().map_or(&best.model, |f| &f.model);
    let settings = crate::figures::settings(&a.figures, ts, units, model)?;
    let uncertainty = best.fit.as_ref().map(Uncertainty::Refined);
    Ok(figures::of_model(model, record, uncertainty, &settings).map_err(|e| e.to_string())?)
}
