//! What an identification says, as lines of text: what was chosen and done, the model, its
//! simulation and prediction fits on the record as identified, the standard deviations, the
//! reading in units and, when the element was fitted, its fit. `hsid identify` prints these
//! lines; the HTML page and Python take the same pieces.

use super::{Field, Identified, Lines};
use crate::hysteresis::{HysteresisFit, Start};
use crate::identify::HostModel;
use crate::model::MemoryElement;
use crate::refine::InnovationForm;
use crate::refine::stochastic::{noise_text, prediction_report};
use crate::refine::uncertainty::border_covariance;
use crate::report::{UndefinedFit, fit_report, std_text};
use crate::units::UnitReport;
use crate::validation::checks::{BEFORE_FIT, checks_text};

impl Identified {
    /// The model read in units (its poles with their covariance when refined, and then each
    /// gap's and the mean gap's standard deviation from the borders' covariance).
    pub fn in_units(&self) -> UnitReport {
        let r = &self.record;
        let model = &self.estimate.model;
        let cov = self.estimate.std.as_ref().map(|(_, c)| c.as_slice());
        let gap_std = self.estimate.std.as_ref().and_then(|(s, _)| s.mean_gap);
        let two_path = self.model_element().two_path();
        // The standard deviations are the refinement's, of its model (the one reported).
        let borders = self
            .best
            .fit
            .as_ref()
            .filter(|f| self.estimate.std.is_some() && two_path && f.model == *model)
            .map(border_covariance);
        model
            .unit_report(r.ts, r.units.clone(), cov, two_path)
            .with_gap_std(gap_std)
            .with_gap_stds(|dir, u| borders.as_ref().and_then(|c| model.gap_std_at(dir, u, c)))
    }

    /// The fitted element read in units: `G`'s poles and bandwidth, the static gain, the gap of
    /// the borders (input units) and the loop height (output units), with the standard
    /// deviations of the gaps when the fit gave its covariance; `None` without a fit.
    pub(crate) fn element_in_units(&self) -> Option<UnitReport> {
        let fit = self.element.as_ref()?;
        let host = fit.model.to_host(self.record.len());
        let r = &self.record;
        let u = fit.uncertainty.as_ref();
        let layout = fit.model.layout();
        let std_of = |f: &dyn Fn(&HostModel) -> Option<f64>| {
            u.and_then(|u| u.std_of(&layout, &fit.model, |m| f(&m.to_host(0))))
        };
        Some(
            host.unit_report(r.ts, r.units.clone(), None, true)
                .with_gap_std(std_of(&HostModel::mean_gap))
                .with_gap_stds(|dir, x| std_of(&|m| m.gap_at(dir, x))),
        )
    }

    /// Every line `hsid identify` prints about the identification, in order. Each experiment
    /// is simulated and predicted from rest on its own; the hold is left out of the fits.
    pub fn lines(&self) -> Result<Lines, UndefinedFit> {
        let mut lines = self.notes.clone();
        lines.extend(checks_text(&self.checks, &BEFORE_FIT));
        let model = &self.estimate.model;
        let (r, hold) = (&self.record, self.record.hold);
        let parts = r.parts();
        lines.push(model.text());
        let sim: Vec<f64> = parts.iter().flat_map(|p| model.simulate(p.0)).collect();
        lines.push(fit_report(&r.y[hold..], &sim[hold..])?);
        if let Some(noise) = &self.estimate.noise {
            lines.push(noise_text(noise));
            let form = InnovationForm::new(model, noise);
            let pred: Vec<f64> = parts.iter().flat_map(|p| form.predict(p.0, p.1)).collect();
            lines.push(prediction_report(
                &r.y[hold..],
                &pred[hold..],
                noise.sigma2,
            )?);
        }
        if let Some((s, _)) = &self.estimate.std {
            lines.push(std_text(s));
        }
        lines.extend(self.in_units().lines());
        lines.extend(self.element_note.clone());
        if let Some(fit) = &self.element {
            lines.extend(self.element_lines(fit)?);
        }
        Ok(lines)
    }

    /// The fitted element's lines: the fit, the model, its simulation fit, its reading in units.
    fn element_lines(&self, fit: &HysteresisFit) -> Result<Lines, UndefinedFit> {
        let s = self.request.syntax;
        let name = match fit.model.kind {
            MemoryElement::Play => "play operator (backlash)",
            MemoryElement::Relay => "relay with borders (switch)",
        };
        let origin = match fit.start {
            Start::TwoPath => "the two-path model above".to_string(),
            Start::Static => format!(
                "the static model above (a play: {} for a relay)",
                s.set(Field::Nonlinearity, s.text("switch"))
            ),
        };
        let mut lines = vec![format!(
            "simulation-error fit of the {name} on the knots, from {origin}: {} iterations{}, Σe² {:.6} -> {:.6}",
            fit.iterations,
            if fit.budget_reached {
                " (the limit; the last step still gained)"
            } else {
                ""
            },
            fit.initial_cost,
            fit.cost
        )];
        lines.extend(element_text(fit));
        let r = &self.record;
        let sim = fit.simulate(&r.u);
        lines.push(fit_report(&r.y[r.hold..], &sim[r.hold..])?);
        lines.push("the fitted element in units:".to_string());
        if let Some(units) = self.element_in_units() {
            lines.extend(units.lines());
        }
        Ok(lines)
    }
}

/// The fitted element: `G`, its poles, `w(−1)`, the borders and the gap, with standard
/// deviations where the data determine them.
pub(crate) fn element_text(fit: &HysteresisFit) -> Vec<String> {
    let m = &fit.model;
    let u = fit.uncertainty.as_ref();
    let list = |v: &[f64]| {
        v.iter()
            .map(|x| format!("{x:.6}"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let sd = |v: Option<f64>| v.map_or(String::new(), |s| format!(" ± {s:.6}"));
    let mut lines = vec![
        format!(
            "G(q) = B/F, G(1) = 1: F = [{}], B = [{}]",
            list(&m.f),
            list(&m.b)
        ),
        format!(
            "poles: {}",
            m.poles()
                .iter()
                .map(|(re, im)| format!("{re:.6}{im:+.6}i"))
                .collect::<Vec<_>>()
                .join(", ")
        ),
        format!("w(-1) = {:.6}{}", m.w0, sd(u.map(|u| u.w0))),
        format!("knots: {}", list(&m.knots)),
        format!("H_a: {}", list(&m.border_asc)),
        format!("H_d: {}", list(&m.border_desc)),
    ];
    if let Some(u) = u {
        lines.push(format!("sd H_a: {}", list(&u.border_asc)));
        lines.push(format!("sd H_d: {}", list(&u.border_desc)));
    } else {
        lines.push(
            "no standard deviations: the data do not determine every border value (singular JᵀJ)"
                .to_string(),
        );
    }
    if m.kind == MemoryElement::Play {
        lines.push(match m.gap() {
            Some(g) => format!("fitted gap {g:.6}{}", sd(u.and_then(|u| u.gap))),
            None => "fitted gap: none, the borders do not meet at mid-range".to_string(),
        });
    }
    lines
}
