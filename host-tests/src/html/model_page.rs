//! The page of a plain model on one record: `identify` (on its estimation record, with the
//! data checks) and `validate` (on a fresh record). A model whose element is the play
//! operator or relay itself (`crate::hysteresis`) is simulated as that element.

use super::advice::BEFORE_FIT;
use super::checks::{data_rows, test_rows};
use super::gap_table::gap_table;
use super::headline::{Fact, Headline};
use super::model_words::{MEAN_GAP, ModelElement, input_unit, model_facts, sentence};
use super::{InlineFigure, Page, Reproduction};
use crate::figures::TrueBorders;
use crate::hysteresis::HysteresisModel;
use crate::identify::HostModel;
use crate::report::fit_report;
use crate::units::{UnitReport, gap_text};
use crate::validation::{Warning, residual_tests};

/// The label of the true mean gap's fact, after the mean gap's.
pub const TRUE_MEAN_GAP: &str = "true mean gap (--true-plant)";

/// A model and the record it is shown on.
pub struct ModelRun<'a> {
    /// The page title, plain text.
    pub title: String,
    /// The input element.
    pub element: ModelElement,
    /// The model (for an element model, its [`HysteresisModel::to_host`]: the linear part,
    /// the knots and the borders the residual tests and the reading in units use).
    pub model: &'a HostModel,
    /// `Some` for a model whose element is the play operator or relay itself: the page's
    /// simulation is this model's, not the two-path reading of `model`.
    pub memory: Option<&'a HysteresisModel>,
    /// The model read in units.
    pub units: &'a UnitReport,
    /// The record's parts `(u, y)`, each simulated from rest on its own.
    pub parts: &'a [(&'a [f64], &'a [f64])],
    /// Samples at the start left out of the fit and the tests (the hold).
    pub skip: usize,
    /// `Some` on the estimation record: its data checks ([`BEFORE_FIT`], run when it was
    /// identified); `None` on a validation record.
    pub estimation: Option<&'a [Warning]>,
    /// Further facts (e.g. the noise model's prediction fit), after the fit.
    pub extra: Vec<Fact>,
    /// The true borders of a simulated record (`--true-plant`): the true gap beside the
    /// identified one.
    pub truth: Option<&'a TrueBorders>,
}

impl ModelRun<'_> {
    /// The model's simulation of the input `u` from rest: the element model's when there is
    /// one.
    fn simulate(&self, u: &[f64]) -> Vec<f64> {
        match self.memory {
            Some(h) => crate::hysteresis::simulate::simulate(h, u),
            None => self.model.simulate(u),
        }
    }

    /// The page with `figures` and `reproduction`.
    pub fn page(&self, figures: Vec<InlineFigure>, reproduction: Reproduction) -> Page {
        let u: Vec<f64> = self
            .parts
            .iter()
            .flat_map(|p| p.0.iter().copied())
            .collect();
        let y: Vec<f64> = self
            .parts
            .iter()
            .flat_map(|p| p.1.iter().copied())
            .collect();
        let sim: Vec<f64> = self.parts.iter().flat_map(|p| self.simulate(p.0)).collect();
        let skip = self.skip.min(y.len());
        let on = if self.estimation.is_some() {
            "in sample, on the estimation record"
        } else {
            "out of sample, on the validation record"
        };
        let fit = fit_report(&y[skip..], &sim[skip..]).unwrap_or_else(|e| e.to_string());
        let fit = format!(
            "{} ({on}).",
            fit.replacen("simulation fit", "Simulation fit", 1)
        );
        let mut facts = model_facts(self.model.order, self.units);
        if let Some(t) = self.truth
            && let Some(i) = facts.iter().position(|f| f.label == MEAN_GAP)
        {
            let unit = input_unit(self.units);
            facts.insert(
                i + 1,
                Fact::new(
                    TRUE_MEAN_GAP,
                    format!("{} {unit}", gap_text(t.mean_gap(), None)),
                ),
            );
        }
        facts.extend(self.extra.iter().cloned());
        let shared = self.element == ModelElement::Static;
        let mut checks = match self.estimation {
            Some(warnings) => data_rows(warnings, &BEFORE_FIT),
            None => Vec::new(),
        };
        // The residual tests need 20 samples after the first `skip`.
        let n = u.len().min(y.len()).min(sim.len());
        let tests = (skip + 20 <= n).then(|| {
            let residual: Vec<f64> = (skip..n).map(|i| y[i] - sim[i]).collect();
            let m = self.model;
            residual_tests(
                &m.knots_asc,
                &m.knots_desc,
                shared,
                &u[..n],
                &residual,
                &sim[skip..n],
                skip..n,
            )
        });
        let checks_note = match (&tests, self.estimation) {
            (None, _) => format!(
                "Too few samples after the first {skip} for the residual tests (20 needed)."
            ),
            (Some(t), Some(_)) => format!(
                "Data checks on the estimation record; residual tests (1 % level) on the \
                 simulation residual of its {} samples after the hold. hsid diagnose runs \
                 the same tests on fresh data and acts on them.",
                t.samples
            ),
            (Some(t), None) => format!(
                "Residual tests (1 % level) on the simulation residual of the {} validation \
                 samples scored. The data checks concern the estimation record: see the \
                 identify report.",
                t.samples
            ),
        };
        if let Some(t) = &tests {
            checks.extend(test_rows(t, "simulation residual"));
        }
        Page {
            title: self.title.clone(),
            headline: Headline {
                lead: vec![sentence(self.element, self.model.order, self.units), fit],
                facts,
                tables: gap_table(self.units, self.truth).into_iter().collect(),
            },
            figures,
            checks_note,
            checks,
            reproduction,
        }
    }
}
