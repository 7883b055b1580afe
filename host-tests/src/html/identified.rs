//! The report page of one identification ([`Identified`]): the fitted element's page when the
//! element was fitted (its simulation, figures and reading in units), else the model's (the
//! subspace, refined or closed-loop estimate with its estimator in words), with the figures
//! `--out` draws.

use super::figures::{drawn, drawn_captioned};
use super::headline::Fact;
use super::model_page::ModelRun;
use super::model_words::element_facts;
use super::{HtmlError, InlineFigure, Page, Reproduction};
use crate::figures::{FigureSettings, write_identified};
use crate::model::Element;
use crate::workflow::Identified;

use super::captions::element_caption;

/// The page of `id` titled `title`, with the figures of `settings` and the way to reproduce
/// the run.
pub fn identified_page(
    id: &Identified,
    title: String,
    settings: &FigureSettings,
    reproduction: Reproduction,
) -> Result<Page, HtmlError> {
    let figures = page_figures(id, settings)?;
    let record = &id.record;
    let Some(fit) = &id.element else {
        let in_units = id.in_units();
        let run = ModelRun {
            title,
            element: id.model_element().into(),
            model: &id.estimate.model,
            memory: None,
            units: &in_units,
            parts: &record.parts(),
            skip: record.hold,
            estimation: Some(&id.checks),
            extra: vec![Fact::new("estimator", id.estimate.estimator.clone())],
            truth: settings.truth.as_ref(),
        };
        return Ok(run.page(figures, reproduction));
    };
    let host = fit.model.to_host(record.len());
    let in_units = id.element_in_units().unwrap_or_else(|| id.in_units());
    let estimator = format!(
        "simulation-error fit of the element from the {} model: {} iterations, Σe² {:.6} -> {:.6}",
        if id.model_element() == Element::Static {
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
        title,
        element: fit.model.kind.into(),
        model: &host,
        memory: Some(&fit.model),
        units: &in_units,
        parts: &[(&record.u, &record.y)],
        skip: record.hold,
        estimation: Some(&id.checks),
        extra,
        truth: settings.truth.as_ref(),
    };
    Ok(run.page(figures, reproduction))
}

/// The figures of the page: those `--out` writes, drawn into a scratch folder and inlined,
/// captioned as the element's when the element was fitted.
fn page_figures(
    id: &Identified,
    settings: &FigureSettings,
) -> Result<Vec<InlineFigure>, HtmlError> {
    let write = |dir: &std::path::Path| {
        write_identified(dir, id, settings)
            .map(|w| w.files)
            .map_err(|e| e.to_string())
    };
    match id.element {
        Some(_) => drawn_captioned(write, |stem| {
            element_caption(stem).map(|(t, c)| (t.to_string(), c.to_string()))
        }),
        None => drawn(write),
    }
}
