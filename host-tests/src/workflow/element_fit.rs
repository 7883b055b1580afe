//! The element itself after the identification: the play operator (backlash; also from a
//! static model) or the relay with borders (switch) on the same knots, fitted by simulation
//! error from the identified model, for inputs that reverse inside the range, where two paths
//! do not describe the element.
//!
//! [`ElementFit::Auto`] (the default) runs it when the record's input breaks the Table I
//! structure ([`Runs::breaks_table1`](crate::table1::Runs::breaks_table1): more than one, and more than a tenth, of the monotone
//! runs start inside the range), with a note that says why and how to turn it off; where the
//! fit cannot run (several experiments, an integrating plant) the note says it was not run.

use super::{ElementFit, Field, IdentifyRequest, Syntax, WorkflowError};
use crate::hysteresis::{ElementFitOptions, HysteresisFit, Start, fit_hysteresis};
use crate::identify::HostModel;
use crate::model::Element;
use crate::model::MemoryElement;
use crate::model::Record;
use crate::table1::{count_runs, end_tolerance};

/// Whether to fit the element, and the note that says why.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct Decision {
    /// Fit it.
    pub run: bool,
    /// Why, when the input asked for it.
    pub note: Option<String>,
}

/// Whether [`ElementFit::Auto`] looks at the input at all: backlash and switch only (a
/// static element takes any input).
pub fn applies(request: &IdentifyRequest) -> bool {
    request.fit == ElementFit::Auto && request.element != Element::Static
}

/// Whether to run the fit on `record` (the record as identified).
pub(crate) fn decide(request: &IdentifyRequest, record: &Record) -> Decision {
    let none = Decision {
        run: false,
        note: None,
    };
    match request.fit {
        ElementFit::None => return none,
        ElementFit::Simulation => {
            return Decision {
                run: true,
                note: None,
            };
        }
        ElementFit::Auto if !applies(request) => return none,
        ElementFit::Auto => {}
    }
    let (umin, umax) = (request.umin, request.umax);
    let from = &record.u[record.hold.saturating_sub(1).min(record.len())..];
    let runs = count_runs(from, umin, umax, end_tolerance(umin, umax));
    if !runs.breaks_table1() {
        return none;
    }
    let s = request.syntax;
    let why = runs.described(umin, umax);
    let fit_auto = s.set(Field::Fit, s.text("auto"));
    let blocked = if record.starts.len() > 1 {
        Some(match s {
            Syntax::Cli => "the element's fit takes one record (one --data)".to_string(),
            Syntax::Python => "the element's fit takes one record".to_string(),
        })
    } else if request.integrating {
        Some(format!(
            "the element's fit is not available with {}",
            s.on(Field::Integrating)
        ))
    } else {
        None
    };
    let run = blocked.is_none();
    let note = match blocked {
        Some(reason) => {
            format!("{fit_auto}: {why}; {reason}: not run, the model is the two-path one")
        }
        None => format!(
            "{fit_auto}: {why}: fitting the element itself by simulation error ({} keeps the \
             two-path model)",
            s.set(Field::Fit, s.text("none"))
        ),
    };
    Decision {
        run,
        note: Some(note),
    }
}

/// The element fitted, and the subspace model it starts from.
pub fn element(kind: Element) -> (MemoryElement, Start) {
    match kind.memory() {
        Some(memory) => (memory, Start::TwoPath),
        None => (MemoryElement::Play, Start::Static),
    }
}

/// Fits the element on `record` from the identified model `start`.
pub fn fit(
    request: &IdentifyRequest,
    record: &Record,
    start: &HostModel,
) -> Result<HysteresisFit, WorkflowError> {
    let (kind, from) = element(request.element);
    fit_hysteresis(
        &record.u,
        &record.y,
        start,
        from,
        &ElementFitOptions::new(kind),
    )
    .map_err(|error| {
        let s = request.syntax;
        WorkflowError::ElementFit {
            prefix: s.set(Field::Fit, s.text("simulation")),
            error,
        }
    })
}
