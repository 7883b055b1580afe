//! The model in words for the headline: the order, each pole read in continuous time (time
//! constant, or natural frequency and damping, with standard deviations when refined), the
//! static gain, the bandwidth and the gap or dead band, all in the record's units. The numbers
//! are formatted by [`UnitReport::lines`], the same text `identify` prints.

use super::headline::Fact;
use crate::units::UnitReport;

/// What the input element is, for the sentence and the facts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ModelElement {
    /// Backlash (gear play): two borders, a gap.
    Backlash,
    /// Switch (hysteresis): two borders, a gap.
    Switch,
    /// One memoryless border: a dead band where it is flat.
    Static,
    /// Two borders, the kind not recorded (a model file without `nonlinearity`).
    TwoPath,
    /// The play operator itself on two borders (a model with `"element": "play"`).
    Play,
    /// The relay with borders itself (a model with `"element": "relay"`).
    Relay,
}

impl From<crate::model::MemoryElement> for ModelElement {
    fn from(k: crate::model::MemoryElement) -> Self {
        match k {
            crate::model::MemoryElement::Play => ModelElement::Play,
            crate::model::MemoryElement::Relay => ModelElement::Relay,
        }
    }
}

impl From<crate::model::Element> for ModelElement {
    fn from(n: crate::model::Element) -> Self {
        match n {
            crate::model::Element::Backlash => ModelElement::Backlash,
            crate::model::Element::Switch => ModelElement::Switch,
            crate::model::Element::Static => ModelElement::Static,
        }
    }
}

impl ModelElement {
    fn name(self) -> &'static str {
        match self {
            ModelElement::Backlash => "backlash",
            ModelElement::Switch => "switch (hysteresis)",
            ModelElement::Static => "static nonlinearity",
            ModelElement::TwoPath => "two-path element (backlash or switch)",
            ModelElement::Play => "play operator (backlash, simulated on inner loops too)",
            ModelElement::Relay => "relay with borders (switch, simulated on inner loops too)",
        }
    }
}

/// The label of the mean gap's fact.
pub const MEAN_GAP: &str = "mean gap (between the borders)";

/// The input unit of the report, or a neutral word.
pub fn input_unit(r: &UnitReport) -> &str {
    r.units.as_ref().map_or("input units", |u| u.input.as_str())
}

/// The mean gap as the headline writes it: with its standard deviation, rounded to it, when
/// the model has one (else five decimals), and the input unit.
pub(crate) fn gap_text(r: &UnitReport) -> Option<String> {
    r.mean_gap_text().map(|g| format!("{g} {}", input_unit(r)))
}

/// One sentence: the element, its gap or dead band, and the order of the linear part.
pub fn sentence(element: ModelElement, order: usize, r: &UnitReport) -> String {
    let play = match (gap_text(r), &r.dead_band) {
        (Some(g), _) => format!(" with a mean gap of {g}"),
        (None, Some(d)) => format!(
            " with a dead band {:.5} {u} wide",
            d.width(),
            u = input_unit(r)
        ),
        (None, None) => String::new(),
    };
    format!(
        "A {}{play}, followed by linear dynamics of order {order}.",
        element.name()
    )
}

/// The facts of the model: order, poles, bandwidth, gain, gap or dead band.
pub(crate) fn model_facts(order: usize, r: &UnitReport) -> Vec<Fact> {
    let mut facts = vec![Fact::new("order of the linear part", order.to_string())];
    for line in r.lines() {
        let labelled = ["pole ", "bandwidth", "static gain"]
            .iter()
            .any(|p| line.starts_with(p));
        if let (true, Some((label, value))) = (labelled, line.split_once(": ")) {
            facts.push(Fact::new(label, value));
        } else if line.starts_with("± ") {
            facts.push(Fact::new("± values", line.trim_start_matches("± : ")));
        } else if line.starts_with("sample time") {
            facts.push(Fact::new(
                "sample time",
                line.trim_start_matches("sample time "),
            ));
        }
    }
    if let Some(g) = gap_text(r) {
        facts.push(Fact::new(MEAN_GAP, g));
    }
    if let Some(d) = &r.dead_band {
        facts.push(Fact::new(
            "dead band",
            format!(
                "flat from u = {:.5} to {:.5} {u} (width {:.5} {u})",
                d.from,
                d.to,
                d.width(),
                u = input_unit(r)
            ),
        ));
    }
    facts
}

/// The facts of an element model besides its reading in units: the play's gap at mid-range
/// (as `identify` prints it after the fit, with its standard deviation when the fit gave one)
/// and the element's output before the record, `w(−1)`.
pub fn element_facts(
    m: &crate::hysteresis::HysteresisModel,
    gap_sd: Option<f64>,
    r: &UnitReport,
) -> Vec<Fact> {
    let mut facts = Vec::new();
    if m.kind == crate::model::MemoryElement::Play {
        let sd = gap_sd.map_or(String::new(), |s| format!(" ± {s:.6}"));
        facts.push(Fact::new(
            "gap of the play at mid-range",
            match m.gap() {
                Some(g) => format!("{g:.6}{sd} {}", input_unit(r)),
                None => "none: the borders do not meet at mid-range".to_string(),
            },
        ));
    }
    facts.push(Fact::new(
        "element output before the record, w(-1)",
        format!("{:.6}", m.w0),
    ));
    facts
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;
    use crate::model_file::Units;
    use crate::units::gain::tests::first_order;

    #[test]
    fn a_backlash_in_volts_reads_in_words() {
        // Borders P_a = (−2.5, −0.5, 1.5), P_d = (−1.5, 0.5, 2.5) on knots −1, 0, 1: gap 0.5.
        let m = first_order(0.9, 0.1, vec![-2.5, -0.5, 1.5], vec![-1.5, 0.5, 2.5]);
        let units = Units {
            input: "V".into(),
            output: "deg".into(),
        };
        let r = m.unit_report(Some(0.01), Some(units), None, true);
        assert_eq!(
            sentence(ModelElement::Backlash, 1, &r),
            "A backlash with a mean gap of 0.50000 V, followed by linear dynamics of order 1."
        );
        let facts = model_facts(1, &r);
        let value = |l: &str| facts.iter().find(|f| f.label == l).unwrap().value.clone();
        assert_eq!(value("mean gap (between the borders)"), "0.50000 V");
        assert_eq!(value("pole 0.90000+0.00000j"), "time constant 0.09491 s");
        assert!(value("static gain").contains("deg per V"));
    }
}
