//! The linear baseline beside the model with the element: both are identified on every record
//! the desktop refines (not for a closed-loop estimate, nor when the request is the linear
//! model itself), scored on the inner hold-out of the estimation record
//! ([`holdout`](crate::choose::holdout)), and the better one is reported; a line gives both
//! fits. When the model with the element cannot be identified at all, the linear model is
//! reported with the reason, so a record whose output responds still gives a model. A
//! structure the user gave ([`IdentifyRequest::structure_given`]: knots, a segment count or
//! horizons) is kept: its model is reported, or its refusal stands, and the line still says
//! which simulates the hold-out better.
//!
//! When the user named no element ([`IdentifyRequest::choose_element`]), the static model at
//! the two-path model's structure ([`static_beside`](crate::choose::static_beside)) is a third
//! candidate on the same hold-out: the element is chosen from the data, not assumed.

use super::{IdentifyRequest, Plan};
use crate::choose::holdout::{FIT_FRACTION, element_holdout, nrmse, pem_holdout};
use crate::choose::{Best, ModelStage, is_linear};
use crate::hysteresis::{ElementFitOptions, HysteresisFit};
use crate::model::{Element, Record};
use crate::refine::pem::simulate_fit;

/// Which candidate is reported.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Reported {
    /// The model with the element (the request's).
    Model,
    /// The linear baseline.
    Linear,
    /// The static element beside the request's two-path one (the element chosen from the
    /// data).
    Static,
}

/// Where the candidates were scored.
#[derive(Clone, Debug, PartialEq)]
pub enum ScoredOn {
    /// The inner hold-out: refitted on the first [`FIT_FRACTION`], simulated on the rest.
    HoldOut,
    /// The whole estimation record, without a refit (a hold-out refit failed: why).
    Whole(String),
}

/// The comparison of the model with the element and the linear baseline.
#[derive(Clone, Debug, PartialEq)]
pub struct Comparison {
    /// The model's simulation NRMSE.
    pub model: f64,
    /// The linear baseline's.
    pub linear: f64,
    /// The static model's, when it was a candidate.
    pub static_model: Option<f64>,
    /// Where.
    pub on: ScoredOn,
    /// The one reported.
    pub reported: Reported,
}

/// What became of the linear baseline.
#[derive(Clone, Debug)]
pub enum Baseline {
    /// Compared with the model with the element.
    Compared(Comparison),
    /// Reported alone: the model with the element could not be identified (why).
    Alone(String),
    /// The model with the element could not be identified (`why`); the static model, left to
    /// the data ([`IdentifyRequest::choose_element`]), was identified with its own choices
    /// and compared with the linear baseline on the inner hold-out.
    Instead {
        /// Why the model with the element could not be identified.
        why: String,
        /// The static model's hold-out NRMSE.
        static_model: f64,
        /// The linear baseline's.
        linear: f64,
        /// [`Reported::Static`] or [`Reported::Linear`].
        reported: Reported,
    },
    /// Not available: the linear model could not be identified (why); the model is reported.
    Failed(String),
}

/// MATLAB's `fit` of an NRMSE, in percent.
pub(crate) fn fit_percent(nrmse: f64) -> f64 {
    100.0 * (1.0 - nrmse)
}

impl Baseline {
    /// The one line that says what was compared and what is reported.
    pub fn report(&self, element: Element) -> String {
        match self {
            Baseline::Compared(c) => {
                let on = match &c.on {
                    ScoredOn::HoldOut => format!(
                        "simulation on the last {:.0} % of the estimation record, each model \
                         refitted on the first {:.0} %",
                        100.0 * (1.0 - FIT_FRACTION),
                        100.0 * FIT_FRACTION
                    ),
                    ScoredOn::Whole(why) => {
                        format!("simulation on the whole estimation record, no hold-out: {why}")
                    }
                };
                let reported = match c.reported {
                    // A structure given leaves no static candidate (`static_candidate`).
                    Reported::Model if c.linear < c.model => format!(
                        "the {element} model is reported as its structure was given (knots, \
                         segments or horizons); the linear model simulates the held-out \
                         samples better"
                    ),
                    Reported::Model => format!("the {element} model is reported"),
                    Reported::Linear => format!(
                        "the linear model is reported (the {element} model{} did not simulate \
                         the held-out samples better)",
                        match c.static_model {
                            Some(_) => " and the static model",
                            None => "",
                        }
                    ),
                    Reported::Static => format!(
                        "the static model is reported: the element was chosen from the data \
                         (the {element} model's memory did not simulate the held-out samples \
                         better; name the element to keep it)"
                    ),
                };
                let static_fit = c
                    .static_model
                    .map(|s| format!("static model: fit {:.1} %; ", fit_percent(s)))
                    .unwrap_or_default();
                format!(
                    "linear OE: fit {:.1} %; {static_fit}{element} model: fit {:.1} % ({on}): \
                     {reported}",
                    fit_percent(c.linear),
                    fit_percent(c.model)
                )
            }
            Baseline::Alone(why) => format!(
                "the {element} model could not be identified ({why}): the linear model (static \
                 element, one segment) is reported"
            ),
            Baseline::Instead {
                why,
                static_model,
                linear,
                reported,
            } => format!(
                "the {element} model could not be identified ({why}): linear OE: fit {:.1} %; \
                 static model: fit {:.1} % (simulation on the last {:.0} % of the estimation \
                 record, each model refitted on the first {:.0} %): {}",
                fit_percent(*linear),
                fit_percent(*static_model),
                100.0 * (1.0 - FIT_FRACTION),
                100.0 * FIT_FRACTION,
                match reported {
                    Reported::Static => "the static model is reported",
                    _ => "the linear model (static element, one segment) is reported",
                }
            ),
            Baseline::Failed(why) => format!("no linear baseline: {why}"),
        }
    }

    /// Whether the static model chosen from the data is the one reported.
    pub fn reports_static(&self) -> bool {
        match self {
            Baseline::Compared(c) => c.reported == Reported::Static,
            Baseline::Instead { reported, .. } => *reported == Reported::Static,
            Baseline::Alone(_) | Baseline::Failed(_) => false,
        }
    }

    /// Whether the linear model is the one reported.
    pub fn reports_linear(&self) -> bool {
        match self {
            Baseline::Compared(c) => c.reported == Reported::Linear,
            Baseline::Instead { reported, .. } => *reported == Reported::Linear,
            Baseline::Alone(_) => true,
            Baseline::Failed(_) => false,
        }
    }
}

/// Whether the baseline is fitted for `request` planned as `plan`: refined, open loop, and not
/// the linear model already.
pub(crate) fn wanted(request: &IdentifyRequest, plan: &Plan) -> bool {
    plan.choices.estimator == ModelStage::Refined
        && request.reference.is_none()
        && !is_linear(&plan.options)
}

/// The hold-out NRMSE of the refined model `best` on `record` ([`pem_holdout`]); `None` when
/// it is not refined or its refit fails.
fn best_holdout(record: &Record, best: &Best) -> Option<f64> {
    pem_holdout(&record.u, &record.y, best.fit.as_ref()?, &best.options).ok()
}

/// The static model `static_best` against the linear baseline `linear` on the inner hold-out
/// of `record`, when the model with the element could not be identified (`why`); `None` when
/// either has no hold-out score (the linear model is then reported alone).
pub(crate) fn instead(
    record: &Record,
    why: String,
    static_best: &Best,
    linear: &Best,
) -> Option<Baseline> {
    let s = best_holdout(record, static_best)?;
    let l = best_holdout(record, linear)?;
    Some(Baseline::Instead {
        why,
        static_model: s,
        linear: l,
        reported: match s < l {
            true => Reported::Static,
            false => Reported::Linear,
        },
    })
}

/// The model with the element (`model`, with its `element` fit when one was run) against the
/// linear baseline `linear` and, when it was identified, the static model `static_best` on
/// `record`. A static model without a score on the hold-out (its refit failed) is left out.
pub(crate) fn compare(
    record: &Record,
    request: &IdentifyRequest,
    model: &Best,
    element: Option<&HysteresisFit>,
    linear: &Best,
    static_best: Option<&Best>,
) -> Option<Comparison> {
    let (u, y) = (&record.u[..], &record.y[..]);
    let linear_fit = linear.fit.as_ref()?;
    let model_fit = model.fit.as_ref()?;
    let model_score = match element {
        Some(e) => element_holdout(
            u,
            y,
            &model_fit.model,
            e.start,
            &ElementFitOptions::new(e.model.kind),
        ),
        None => pem_holdout(u, y, model_fit, &model.options),
    };
    let linear_score = pem_holdout(u, y, linear_fit, &linear.options);
    let (m, l, on) = match (model_score, linear_score) {
        (Ok(m), Ok(l)) => (m, l, ScoredOn::HoldOut),
        (m, l) => {
            let why = [m.err(), l.err()]
                .into_iter()
                .flatten()
                .map(|e| e.to_string())
                .collect::<Vec<_>>()
                .join("; ");
            let whole_pem = |fit| {
                let sim = simulate_fit(u, y, fit).ok()?;
                let start = y.len() - sim.len();
                nrmse(&y[start..], &sim)
            };
            let m = match element {
                Some(e) => {
                    let hold = record.hold.min(y.len());
                    nrmse(&y[hold..], &e.simulate(u)[hold..])
                }
                None => whole_pem(model_fit),
            };
            (m?, whole_pem(linear_fit)?, ScoredOn::Whole(why))
        }
    };
    let static_model = match on {
        ScoredOn::HoldOut => static_best.and_then(|s| best_holdout(record, s)),
        ScoredOn::Whole(_) => None,
    };
    let reported = if request.structure_given() {
        Reported::Model
    } else if static_model.is_some_and(|s| s < m && s <= l) {
        Reported::Static
    } else if l < m {
        Reported::Linear
    } else {
        Reported::Model
    };
    Some(Comparison {
        model: m,
        linear: l,
        static_model,
        on,
        reported,
    })
}
