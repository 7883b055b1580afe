//! The page of `diagnose`: the verdict and the final model in words, the validation error
//! before and after each added effect, the diagnosis figures, and the data checks with the
//! residual tests on the estimation residual and on the validation data before and after.

use super::checks::{data_rows, test_rows};
use super::figures::drawn;
use super::headline::{Fact, Headline, TextTable};
use super::model_words::{model_facts, sentence};
use super::{HtmlError, InlineFigure, Page, Reproduction};
use crate::diagnose::{Diagnosis, Evaluation, figures};
use crate::model::Element;
use crate::model_file::Units;

/// The diagnosis figures (those `--out` writes), inlined; `title` heads each figure.
pub fn diagnosis_figures(d: &Diagnosis, title: &str) -> Result<Vec<InlineFigure>, HtmlError> {
    drawn(|dir| figures::write_figures(d, dir, "", title).map_err(|e| e.to_string()))
}

fn row(name: String, e: &Evaluation) -> Vec<String> {
    vec![
        name,
        format!("{:.5}", e.rmse),
        format!("{:.4}", e.nrmse),
        format!("{:.2} %", e.fit_percent),
    ]
}

/// The validation error of each model along the diagnosis.
fn before_after(d: &Diagnosis) -> TextTable {
    let mut rows = Vec::new();
    if let Some(p) = &d.paper {
        rows.push(row("the paper's estimate alone (subspace)".into(), p));
    }
    rows.push(row("before: the base model".into(), &d.before));
    for (i, s) in d.steps.iter().enumerate() {
        rows.push(vec![
            format!("after step {}: {} ({})", i + 1, s.effect.name(), s.setting),
            format!("{:.5}", s.error_after),
            format!("{:.4}", s.nrmse_after),
            format!("{:.2} %", s.fit_after),
        ]);
    }
    rows.push(row("after: the final model (simulation)".into(), &d.after));
    if let Some(p) = &d.after_prediction {
        rows.push(row(
            "after: the final model (one-step prediction)".into(),
            p,
        ));
    }
    TextTable {
        caption: format!(
            "Validation error on {} samples before and after each step (RMSE in output units; \
             NRMSE = RMSE / std of y; fit = 100 (1 − NRMSE)):",
            d.validation_samples
        ),
        header: ["model", "RMSE", "NRMSE", "fit"].map(String::from).to_vec(),
        rows,
    }
}

/// The page of diagnosis `d`; `ts` and `units` read the final model in seconds and units.
pub fn diagnosis_page(
    d: &Diagnosis,
    title: String,
    ts: Option<f64>,
    units: Option<Units>,
    figures: Vec<InlineFigure>,
    reproduction: Reproduction,
) -> Page {
    // An element with memory added to a static model has two borders.
    let element = d
        .model
        .hysteresis
        .as_ref()
        .map(|el| el.to_host(d.model.hammerstein.samples));
    let two_path = d.nonlinearity != Element::Static || element.is_some();
    // Friction refits `G` with it: the model's own plant is read.
    let friction = d.model.friction.as_ref();
    let m = element
        .as_ref()
        .or(friction.map(|f| &f.plant))
        .unwrap_or(&d.model.hammerstein);
    let output_unit = units.as_ref().map(|u| u.output.clone());
    let r = m.unit_report(ts, units, None, two_path);
    let added: Vec<&str> = d.steps.iter().map(|s| s.effect.name()).collect();
    let mut facts = vec![
        Fact::new("data", d.data_description.clone()),
        Fact::new(
            "effects added",
            if added.is_empty() {
                "none".to_string()
            } else {
                added.join(", ")
            },
        ),
        Fact::new("dead time", d.dead_time.to_string()),
    ];
    facts.extend(model_facts(m.order, &r));
    let mut checks = data_rows(&d.warnings, &d.checks_ran());
    checks.extend(test_rows(&d.tests_estimation, "estimation residual"));
    checks.extend(test_rows(&d.tests_before, "validation, before"));
    checks.extend(test_rows(&d.tests_after, "validation, after"));
    Page {
        title,
        headline: Headline {
            lead: vec![
                format!("Verdict: {}", d.verdict),
                format!(
                    "Final model: {}{}",
                    sentence(d.nonlinearity.into(), m.order, &r),
                    match (friction, &d.model.two_mass) {
                        (Some(_), _) => " Coulomb friction and an offset on its velocity are \
                                         fed back into the linear part's input."
                            .to_string(),
                        (None, Some(tm)) => format!(
                            " A two-mass drive with play between motor and load replaces the \
                             linear part (the facts below are of the part it replaces): {}.",
                            tm.describe(ts, output_unit.as_deref())
                        ),
                        (None, None) => String::new(),
                    }
                ),
            ],
            facts,
            tables: vec![before_after(d)],
        },
        figures,
        checks_note: "Data checks on the estimation record; residual tests at the 1 % level on \
                      the estimation residual of the last deterministic model and on the \
                      validation residual before and after the diagnosis."
            .to_string(),
        checks,
        reproduction,
    }
}
