//! The identify workflow: one record in, one model out, every decision in one place. The
//! command line and Python are its faces: they build an [`IdentifyRequest`] and a
//! [`Record`], call [`identify_record`], and print or return what it
//! gives ([`Identified`]).
//!
//! The steps, in order: the request is checked ([`IdentifyRequest::validate`]); a record
//! whose output keeps a unit root is routed to the integrating identification when the
//! request leaves that open ([`detect`]); an integrating plant's record becomes the record of
//! its increments and a detrended record
//! loses its mean output; segments, horizons and order are chosen and the model refined
//! ([`best_model`]); a closed-loop record's model is replaced by the estimate with instruments
//! from the reference ([`closed_loop`]); the noise model and standard deviations are taken
//! from the refinement or fitted to the subspace model's residual ([`estimate`]); the
//! element itself is fitted by simulation error when the input reverses inside the range
//! ([`element_fit`]); and the linear baseline, identified beside it, is reported instead when
//! it simulates the inner hold-out of the record better or when the model with the element
//! cannot be identified ([`baseline`]).

pub mod baseline;
pub mod closed_loop;
pub mod detect;
pub mod element_fit;
pub mod estimate;
pub mod friction;
pub mod report;
mod request;

use std::borrow::Cow;

pub use baseline::{Baseline, Comparison, Reported, ScoredOn};
pub use estimate::Estimate;
pub use request::{
    ElementFit, Field, IdentifyRequest, MAX_REFINE_WORK, MAX_SEGMENT_COUNT, Plan,
    REFINE_ITERATIONS, RequestError, Syntax,
};

use crate::choose::noise_file;
use crate::choose::{Best, ChooseError, best_model, linear_model, static_beside};
use crate::closed_loop::ReferenceError;
use crate::hysteresis::{HysteresisError, HysteresisFit};
use crate::identify::IdentifyError;
use crate::model::{Element, Record};
use crate::model_file::ModelFile;
use crate::progress;
use crate::validation::{Warning, data_checks};

/// Lines of text for the user, in order (notes, a report).
pub type Lines = Vec<String>;

/// Why [`identify_record`] gave no model.
#[derive(Debug, thiserror::Error)]
pub enum WorkflowError {
    /// The request contradicts itself or the record.
    #[error(transparent)]
    Request(#[from] RequestError),
    /// The identification failed at a sample of the record as given (`index`, 0 = first).
    #[error("{error}")]
    Sample {
        /// The core's error about the sample.
        error: IdentifyError,
        /// The sample of the caller's record.
        index: usize,
    },
    /// The identification failed.
    #[error(transparent)]
    Choose(ChooseError),
    /// The closed-loop estimate failed.
    #[error("{name} (reference): {error}")]
    ClosedLoop {
        /// The reference's name.
        name: String,
        /// Why.
        error: ReferenceError,
    },
    /// The caller stopped the run ([`progress::Reporter::stopped`]).
    #[error(transparent)]
    Interrupted(#[from] progress::Interrupted),
    /// The element's simulation-error fit failed.
    #[error("{prefix}: {error}")]
    ElementFit {
        /// The setting that asked for the fit, in the front end's words.
        prefix: String,
        /// Why.
        error: HysteresisError,
    },
}

/// What one identification gives: the model and everything that was chosen and said on the
/// way.
#[derive(Clone, Debug)]
pub struct Identified {
    /// The record as identified (the increments of an integrating plant, detrended).
    pub record: Record,
    /// The subspace model and what was chosen (segments, horizons, order, the refinement);
    /// its model is the closed-loop estimate for a closed-loop record.
    pub best: Best,
    /// The model to report, its noise model and standard deviations, the estimator in words.
    pub estimate: Estimate,
    /// What was done and why, in order: one line each (the front end prints them before the
    /// model).
    pub notes: Vec<String>,
    /// Why the element's fit was or was not run, when the input asked for it.
    pub element_note: Option<String>,
    /// The element fitted by simulation error, when it was.
    pub element: Option<HysteresisFit>,
    /// The linear baseline beside the model, when it was fitted; when it is reported
    /// ([`Baseline::reports_linear`]), `best` and `estimate` are the linear model's.
    pub baseline: Option<Baseline>,
    /// The request.
    pub request: IdentifyRequest,
    /// The data checks of the record as identified (`validation::checks::BEFORE_FIT`, at the
    /// chosen knots and horizons): the terminal's lines and the page's table.
    pub checks: Vec<Warning>,
    /// The friction step, when the request asked for it and it ran
    /// ([`IdentifyRequest::friction`]); its model is the one reported when
    /// [`FrictionStep::reported`](friction::FrictionStep::reported).
    pub friction: Option<friction::FrictionStep>,
}

impl Identified {
    /// The element of the reported model: the request's, or static when the linear baseline
    /// or the static model chosen from the data is reported.
    pub fn model_element(&self) -> Element {
        model_element(self.baseline.as_ref(), self.request.element)
    }

    /// The model file: the fitted element's when it was fitted, else the model with its noise
    /// model and standard deviations; with the record's sample time and units.
    pub fn model_file(&self) -> ModelFile {
        let friction = self.friction.as_ref().filter(|f| f.reported);
        let mut file = match (&self.element, friction) {
            (_, Some(step)) => step
                .fit
                .model
                .to_file(self.record.len(), self.model_element()),
            (Some(fit), None) => fit.model.to_file(self.record.len()),
            (None, None) => {
                let mut file = self.estimate.model.to_json(Some(self.model_element()));
                file.noise = self.estimate.noise.as_ref().map(noise_file);
                file.std = self.estimate.std.as_ref().map(|(s, _)| s.clone());
                file.integrating = self.request.integrating;
                file
            }
        };
        file.sample_time = self.record.ts;
        file.units = self.record.units.clone();
        file
    }
}

/// Identifies `record` as `request` asks: see the [module](self) for the steps.
pub fn identify_record(
    record: &Record,
    request: &IdentifyRequest,
) -> Result<Identified, WorkflowError> {
    let mut plan = request.plan_for(record)?;
    progress::stage(|| "checking the output for an integrator".to_string())?;
    let (routed, route_note) = detect::route(request, record);
    let request = &routed;
    let mut notes: Lines = route_note.into_iter().collect();
    let source = record;
    // Copied only where changed (the increments, the detrended output), and for the result at
    // the end: a long record is not held twice while it is identified.
    let mut record = Cow::Borrowed(record);
    if request.integrating {
        record = Cow::Owned(record.increments());
        plan.options = crate::integrating::increments_options(&plan.options);
        notes.push(
            "integrating: one pole fixed at z = 1; the stable part G₀ is identified on the \
             output's increments y(t) − y(t − 1) (G₀(1) = 1: μ0, the borders and the fits \
             below are in output units per sample)"
                .to_string(),
        );
    }
    if request.detrend {
        let (detrended, mean) = record.into_owned().detrended();
        record = Cow::Owned(detrended);
        notes.push(format!(
            "detrended: subtracted the mean output {mean:.6} from y"
        ));
    }
    let model =
        progress::stage(|| format!("the model with the {} element", request.element.name()))
            .map_err(ChooseError::from)
            .and_then(|()| best_model(&record.u, &record.y, &plan.options, &plan.choices))
            .map_err(|e| match e {
                ChooseError::Identify(error) => {
                    let index = sample_index(&error).unwrap_or(0);
                    let index = match request.integrating {
                        true => source.increments_source(index),
                        false => index,
                    };
                    WorkflowError::Sample { error, index }
                }
                ChooseError::Interrupted(i) => WorkflowError::Interrupted(i),
                e => WorkflowError::Choose(e),
            });
    let linear = baseline::wanted(request, &plan).then(|| {
        progress::stage(|| "the linear baseline".to_string())
            .map_err(ChooseError::from)
            .and_then(|()| linear_model(&record.u, &record.y, &plan.options, &plan.choices))
    });
    let settled = match (model, linear) {
        (Ok(best), linear) => {
            let beside = static_candidate(&record, request, &plan, &best, linear.is_some())?;
            with_element(&record, request, best, linear, beside, &mut notes)?
        }
        // The model with the element failed where the data chose its structure: the linear
        // model, when there is one, is the answer (a record whose output responds gives a
        // model). A structure the user gave (knots, segments, horizons) keeps its refusal.
        (Err(e), Some(Ok(linear)))
            if !request.structure_given() && !matches!(e, WorkflowError::Interrupted(_)) =>
        {
            static_instead(&record, request, &plan, linear, e.to_string())?
        }
        (Err(e), _) => return Err(e),
    };
    let (best, estimate, element_note, fitted, baseline) = match settled {
        Settled::Element(parts) => {
            let m = *parts;
            (m.best, m.estimate, m.element_note, m.element, m.baseline)
        }
        Settled::Beside(parts) => {
            let (linear, why) = *parts;
            notes.push(why.report(request.element));
            let name = match why.reports_static() {
                true => "static model",
                false => "linear model",
            };
            notes.extend(linear.report().into_iter().map(|l| format!("{name}: {l}")));
            let (estimate, estimate_notes) = estimate::estimate(&linear, &record, request);
            notes.extend(estimate_notes);
            (linear, estimate, None, None, Some(why))
        }
    };
    progress::stage(|| "checking the data against the method's assumptions".to_string())?;
    let element = model_element(baseline.as_ref(), request.element);
    let checks = data_checks(&record.u, &record.y, &best.options, element);
    let friction = match (request.friction, &fitted) {
        (false, _) => None,
        (true, Some(_)) => {
            let s = request.syntax;
            notes.push(format!(
                "{}: not fitted: the element was fitted by simulation error itself ({} keeps \
                 the model friction is fitted on)",
                s.name(Field::Friction),
                s.set(Field::Fit, s.text("none"))
            ));
            None
        }
        (true, None) => {
            progress::stage(|| "fitting friction on the model's velocity".to_string())?;
            match friction::step(&record, request, &estimate.model) {
                Ok((step, lines)) => {
                    notes.extend(lines);
                    Some(step)
                }
                Err(line) => {
                    notes.push(line);
                    None
                }
            }
        }
    };
    Ok(Identified {
        record: record.into_owned(),
        best,
        estimate,
        notes,
        element_note,
        element: fitted,
        baseline,
        request: request.clone(),
        checks,
        friction,
    })
}

/// The model with the element, with what was found beside it.
struct ElementModel {
    best: Best,
    estimate: Estimate,
    element_note: Option<String>,
    element: Option<HysteresisFit>,
    baseline: Option<Baseline>,
}

/// Which model the record gets.
enum Settled {
    /// The model with the element.
    Element(Box<ElementModel>),
    /// The linear baseline or the static model chosen from the data, and why it is reported
    /// ([`Baseline::reports_static`] tells which).
    Beside(Box<(Best, Baseline)>),
}

/// The element of the model reported with `baseline` for a request of `requested`: static
/// when the linear baseline or the static model is reported.
fn model_element(baseline: Option<&Baseline>, requested: Element) -> Element {
    match baseline.is_some_and(|b| b.reports_linear() || b.reports_static()) {
        true => Element::Static,
        false => requested,
    }
}

/// Whether the request leaves the element to the data ([`IdentifyRequest::choose_element`])
/// for `record`: no element named, a two-path default, and a record within the choice window
/// (a longer record keeps the named element: one more whole-record identification is what
/// its window avoids).
fn element_left_to_data(record: &Record, request: &IdentifyRequest, plan: &Plan) -> bool {
    request.choose_element
        && request.element.two_path()
        && plan.choices.window.is_none_or(|w| record.len() <= w)
}

/// The static model beside the two-path model `best`, when the request leaves the element to
/// the data ([`IdentifyRequest::choose_element`]), the linear baseline is fitted
/// (`baselined`: the hold-out compares them) and no structure was given
/// ([`element_left_to_data`]). `None` also when it cannot be identified: the
/// two-path model and the linear baseline remain.
fn static_candidate(
    record: &Record,
    request: &IdentifyRequest,
    plan: &Plan,
    best: &Best,
    baselined: bool,
) -> Result<Option<Best>, WorkflowError> {
    if !(baselined && !request.structure_given() && element_left_to_data(record, request, plan)) {
        return Ok(None);
    }
    progress::stage(|| "the static element at the same structure".to_string())?;
    match static_beside(&record.u, &record.y, &plan.options, &plan.choices, best) {
        Ok(s) => Ok(Some(s)),
        Err(ChooseError::Interrupted(i)) => Err(WorkflowError::Interrupted(i)),
        Err(_) => Ok(None),
    }
}

/// The model when the one with the element could not be identified (`why`): the static model
/// with its own choices of segments, horizons and order, when the request leaves the element
/// to the data ([`element_left_to_data`]), reported instead of the linear
/// baseline `linear` when it simulates the inner hold-out better; else the linear model.
fn static_instead(
    record: &Record,
    request: &IdentifyRequest,
    plan: &Plan,
    linear: Best,
    why: String,
) -> Result<Settled, WorkflowError> {
    let wanted = element_left_to_data(record, request, plan);
    let alone = |why| {
        Ok(Settled::Beside(Box::new((
            linear.clone(),
            Baseline::Alone(why),
        ))))
    };
    if !wanted {
        return alone(why);
    }
    progress::stage(|| "the static element".to_string())?;
    let mut options = plan.options.clone();
    options.static_nonlinearity = true;
    let static_best = match best_model(&record.u, &record.y, &options, &plan.choices) {
        Ok(s) => s,
        Err(ChooseError::Interrupted(i)) => return Err(WorkflowError::Interrupted(i)),
        Err(_) => return alone(why),
    };
    progress::stage(|| "comparing with the linear baseline on the inner hold-out".into())?;
    match baseline::instead(record, why.clone(), &static_best, &linear) {
        Some(b) if b.reports_static() => Ok(Settled::Beside(Box::new((static_best, b)))),
        Some(b) => Ok(Settled::Beside(Box::new((linear, b)))),
        None => alone(why),
    }
}

/// The model with the element from the subspace model `best` on `record`: the closed-loop
/// estimate replaces it for a closed-loop record, the noise model and standard deviations
/// are estimated, the element is fitted when the input asks for it, and the linear baseline
/// `linear` (when it was fitted) is compared with it on the inner hold-out; the linear model
/// when it simulates that better. Notes are added to `notes`.
fn with_element(
    record: &Record,
    request: &IdentifyRequest,
    mut best: Best,
    linear: Option<Result<Best, ChooseError>>,
    beside: Option<Best>,
    notes: &mut Lines,
) -> Result<Settled, WorkflowError> {
    notes.extend(best.report());
    if let Some(name) = &request.reference {
        progress::stage(|| format!("the closed-loop estimate with the reference {name}"))?;
        notes.push(closed_loop::replace(&mut best, record, name)?);
    }
    progress::stage(|| "the noise model".to_string())?;
    let (estimate, estimate_notes) = estimate::estimate(&best, record, request);
    notes.extend(estimate_notes);
    let decision = element_fit::decide(request, record);
    let element = match decision.run {
        true => {
            progress::stage(|| {
                format!(
                    "fitting the {} element by simulation error",
                    request.element.name()
                )
            })?;
            Some(element_fit::fit(request, record, &estimate.model)?)
        }
        false => None,
    };
    let baseline = match linear {
        None => None,
        Some(Err(e)) => Some(Baseline::Failed(e.to_string())),
        Some(Ok(linear)) => {
            progress::stage(|| "comparing with the linear baseline on the inner hold-out".into())?;
            let compared = baseline::compare(
                record,
                request,
                &best,
                element.as_ref(),
                &linear,
                beside.as_ref(),
            );
            // `compare` reports the static model only when it scored one.
            match (compared, beside) {
                (Some(c), _) if c.reported == Reported::Linear => {
                    return Ok(Settled::Beside(Box::new((linear, Baseline::Compared(c)))));
                }
                (Some(c), Some(chosen)) if c.reported == Reported::Static => {
                    return Ok(Settled::Beside(Box::new((chosen, Baseline::Compared(c)))));
                }
                (Some(c), _) => Some(Baseline::Compared(c)),
                (None, _) => Some(Baseline::Failed(
                    "the candidates could not be simulated on the record".to_string(),
                )),
            }
        }
    };
    notes.extend(baseline.as_ref().map(|b| b.report(request.element)));
    Ok(Settled::Element(Box::new(ElementModel {
        best,
        estimate,
        element_note: decision.note,
        element,
        baseline,
    })))
}

/// The sample a core error names, if any.
pub(crate) fn sample_index(e: &IdentifyError) -> Option<usize> {
    match e {
        IdentifyError::Core(
            hsid::Error::NonFinite { index, .. }
            | hsid::Error::InputOutOfRange { index, .. }
            | hsid::Error::HoldNotAtMin { index, .. },
        ) => Some(usize::try_from(*index).unwrap_or(usize::MAX)),
        _ => None,
    }
}
