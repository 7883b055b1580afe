//! What a user asks of one identification, checked once for every front end: the command
//! line and Python build an [`IdentifyRequest`], and [`IdentifyRequest::validate`] gives the
//! library's options and choices or a [`RequestError`] that names the setting in the front
//! end's own words ([`Syntax`]).

use crate::model::Element;
use hsid::Basis;

use crate::choose::{self, Choices, ModelStage, SEGMENT_CANDIDATES, Segments};
use crate::identify::{IdentifyOptions, MAX_CHANNELS, max_segments};
use crate::refine::knots::{AUTO_CANDIDATES, SegmentCount};

/// Whether the element itself is fitted by simulation error after the identification.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ElementFit {
    /// When the input breaks the Table I structure (inner loops) and the fit can run.
    Auto,
    /// Never: the identified model as it is.
    None,
    /// Always (one record, no integrator).
    Simulation,
}

impl ElementFit {
    /// The name on the command line and in Python: `auto`, `none` or `simulation`.
    pub fn name(self) -> &'static str {
        match self {
            ElementFit::Auto => "auto",
            ElementFit::None => "none",
            ElementFit::Simulation => "simulation",
        }
    }

    /// The setting named `name`, if any.
    pub fn from_name(name: &str) -> Option<Self> {
        [ElementFit::Auto, ElementFit::None, ElementFit::Simulation]
            .into_iter()
            .find(|f| f.name() == name)
    }
}

/// A setting of the request, for messages.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Field {
    /// The interval's lower end.
    UMin,
    /// The interval's upper end.
    UMax,
    /// Segments per path.
    Segments,
    /// Knots of the ascending path.
    KnotsAsc,
    /// Knots of the descending path.
    KnotsDesc,
    /// The hold.
    Hold,
    /// Detrending.
    Detrend,
    /// The element's fit.
    Fit,
    /// The integrating plant.
    Integrating,
    /// The input element.
    Nonlinearity,
    /// The closed-loop reference.
    Reference,
    /// The record itself.
    Data,
    /// The model order.
    Order,
    /// Friction on the velocity.
    Friction,
}

/// The most work a refinement at a given order may ask for before it starts: samples ×
/// parameters² × [`REFINE_ITERATIONS`], the multiply–adds of its iterations' normal equations
/// at their limit (at about 10⁹ a second, some minutes on one core).
pub const MAX_REFINE_WORK: f64 = 1e12;

/// The refinement's iteration limit the work is counted with.
pub const REFINE_ITERATIONS: usize = 100;

/// The most segments per path a count may ask for: those the record does not support are
/// merged into neighbours first, so a count beyond the capacity can fit a short record; a
/// larger count is refused before any work (merging it would cost more than it could give).
pub const MAX_SEGMENT_COUNT: usize = 1024;

/// How a front end spells its settings.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Syntax {
    /// `hsid identify --umin …`.
    Cli,
    /// `hsid.identify(…, umin=…)`.
    Python,
}

impl Syntax {
    /// The setting's name.
    pub fn name(self, f: Field) -> &'static str {
        match (self, f) {
            (Syntax::Cli, Field::UMin) => "--umin",
            (Syntax::Cli, Field::UMax) => "--umax",
            (Syntax::Cli, Field::Segments) => "--segments",
            (Syntax::Cli, Field::KnotsAsc) => "--knots-asc",
            (Syntax::Cli, Field::KnotsDesc) => "--knots-desc",
            (Syntax::Cli, Field::Hold) => "--hold",
            (Syntax::Cli, Field::Detrend) => "--detrend",
            (Syntax::Cli, Field::Fit) => "--fit",
            (Syntax::Cli, Field::Integrating) => "--integrating",
            (Syntax::Cli, Field::Nonlinearity) => "--nonlinearity",
            (Syntax::Cli, Field::Reference) => "--reference-column",
            (Syntax::Cli, Field::Data) => "--data",
            (Syntax::Cli, Field::Order) => "--order",
            (Syntax::Cli, Field::Friction) => "--friction",
            (Syntax::Python, Field::UMin) => "umin",
            (Syntax::Python, Field::UMax) => "umax",
            (Syntax::Python, Field::Segments) => "segments",
            (Syntax::Python, Field::KnotsAsc) => "knots (ascending)",
            (Syntax::Python, Field::KnotsDesc) => "knots (descending)",
            (Syntax::Python, Field::Hold) => "hold",
            (Syntax::Python, Field::Detrend) => "detrend",
            (Syntax::Python, Field::Fit) => "fit",
            (Syntax::Python, Field::Integrating) => "integrating",
            (Syntax::Python, Field::Nonlinearity) => "nonlinearity",
            (Syntax::Python, Field::Reference) => "reference",
            (Syntax::Python, Field::Data) => "u, y",
            (Syntax::Python, Field::Order) => "order",
            (Syntax::Python, Field::Friction) => "friction",
        }
    }

    /// The setting with a value: `--hold 0` or `hold=0`.
    pub fn set(self, f: Field, value: impl std::fmt::Display) -> String {
        match self {
            Syntax::Cli => format!("{} {value}", self.name(f)),
            Syntax::Python => format!("{}={value}", self.name(f)),
        }
    }

    /// A text value as the front end writes it: `static` or `"static"`.
    pub fn text(self, value: &str) -> String {
        match self {
            Syntax::Cli => value.to_string(),
            Syntax::Python => format!("{value:?}"),
        }
    }

    /// A switch turned on: `--detrend` or `detrend=True`.
    pub fn on(self, f: Field) -> String {
        match self {
            Syntax::Cli => self.name(f).to_string(),
            Syntax::Python => format!("{}=True", self.name(f)),
        }
    }

    /// One record in the front end's words.
    fn one_record(self) -> &'static str {
        match self {
            Syntax::Cli => "one record (one --data)",
            Syntax::Python => "one record",
        }
    }
}

/// A request that cannot be carried out, with the setting at fault.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{message}")]
pub struct RequestError {
    /// The setting at fault.
    pub field: Field,
    /// A short stable name of the problem (Python's error `kind`).
    pub kind: &'static str,
    /// What is wrong and what to do, in the front end's words.
    pub message: String,
}

impl RequestError {
    fn new(field: Field, kind: &'static str, message: String) -> Self {
        Self {
            field,
            kind,
            message,
        }
    }
}

/// One identification as the user asks for it. [`IdentifyRequest::new`] gives the defaults of
/// `hsid identify` and `hsid.identify`.
#[derive(Clone, Debug, PartialEq)]
pub struct IdentifyRequest {
    /// Lower end of the input interval.
    pub umin: f64,
    /// Upper end of the input interval.
    pub umax: f64,
    /// Uniform segments per path, or `auto`; `None`: 7, 10 or 14 by BIC of the refined model
    /// (7 without refinement). Ignored when knots are given.
    pub segments: Option<SegmentCount>,
    /// Knots of the ascending path (`umin` first, `umax` last).
    pub knots_asc: Option<Vec<f64>>,
    /// Knots of the descending path.
    pub knots_desc: Option<Vec<f64>>,
    /// Model order; `None`: from the data.
    pub order: Option<usize>,
    /// Horizons `(f, p)`; `None`: from the data.
    pub horizons: Option<(usize, usize)>,
    /// The input element.
    pub element: Element,
    /// The element was not named (the default): beside a two-path `element`, the static
    /// element is identified at its structure and reported when it simulates the inner
    /// hold-out better ([`static_beside`](crate::choose::static_beside),
    /// [`baseline`](super::baseline)). False: the element named is the model's.
    pub choose_element: bool,
    /// Border basis.
    pub basis: Basis,
    /// Known μ0 for a record without a hold.
    pub mu0: Option<f64>,
    /// Subtract the mean output first (records without a hold).
    pub detrend: bool,
    /// The plant integrates: one pole at z = 1, the stable part identified on increments.
    pub integrating: bool,
    /// When `integrating` is false, test the record for an integrating output first and
    /// identify it as integrating when the unit root stands ([`detect`](super::detect); the
    /// default); false: identify it as given.
    pub detect_integrating: bool,
    /// Refine by the prediction-error method (the default).
    pub refine: bool,
    /// The element's simulation-error fit.
    pub fit: ElementFit,
    /// The closed-loop estimate from the record's reference, named so (the CSV column or
    /// Python's `reference`); `None`: open loop.
    pub reference: Option<String>,
    /// Samples of the hold skipped while the plant settles; `None`: half the hold.
    pub settle: Option<usize>,
    /// After the model, fit friction on its velocity ([`crate::friction`]) and report the
    /// model with it when it simulates the inner hold-out better ([`super::friction`]).
    pub friction: bool,
    /// How messages and notes spell the settings.
    pub syntax: Syntax,
}

/// A request checked: the library's options and choices.
#[derive(Clone, Debug)]
pub struct Plan {
    /// Interval, knots, horizons, order, hold of the record as given.
    pub options: IdentifyOptions,
    /// What is chosen from the data.
    pub choices: Choices,
}

impl IdentifyRequest {
    /// The defaults on `[umin, umax]`: a backlash, everything else chosen from the data,
    /// refined, the element fitted when the input asks for it.
    pub fn new(umin: f64, umax: f64, syntax: Syntax) -> Self {
        Self {
            umin,
            umax,
            segments: None,
            knots_asc: None,
            knots_desc: None,
            order: None,
            horizons: None,
            element: Element::Backlash,
            choose_element: true,
            basis: Basis::Hat,
            mu0: None,
            detrend: false,
            integrating: false,
            detect_integrating: true,
            refine: true,
            fit: ElementFit::Auto,
            reference: None,
            settle: None,
            friction: false,
            syntax,
        }
    }

    /// Whether the user gave the model's structure: knots, a segment count or horizons (the
    /// linear baseline then does not replace the model, and a refusal stands).
    pub fn structure_given(&self) -> bool {
        self.knots_asc.is_some()
            || self.knots_desc.is_some()
            || matches!(self.segments, Some(SegmentCount::Fixed(_)))
            || self.horizons.is_some()
    }

    /// Checks the settings that do not depend on the record and gives the options for a
    /// record with a hold of `hold` samples.
    pub fn validate(&self, hold: usize) -> Result<Plan, RequestError> {
        let s = self.syntax;
        let (umin, umax) = (self.umin, self.umax);
        if !(umin.is_finite() && umax.is_finite() && umin < umax) {
            return Err(RequestError::new(
                Field::UMin,
                "invalid_interval",
                format!(
                    "invalid input interval [{umin}, {umax}]: {} must be finite and below {}",
                    s.name(Field::UMin),
                    s.name(Field::UMax)
                ),
            ));
        }
        if self.segments == Some(SegmentCount::Fixed(0)) {
            return Err(RequestError::new(
                Field::Segments,
                "segments",
                format!(
                    "{}: each path needs at least one segment",
                    s.set(Field::Segments, 0)
                ),
            ));
        }
        let most = max_segments(self.element == Element::Static);
        // Checked before the knots are built (a count near `usize::MAX` cannot be allocated).
        if let Some(SegmentCount::Fixed(n)) = self.segments
            && n > MAX_SEGMENT_COUNT
        {
            return Err(RequestError::new(
                Field::Segments,
                "segments_capacity",
                format!(
                    "{}: at most {MAX_SEGMENT_COUNT} segments per path are asked for (those the \
                     record does not support are merged, and at most {most} per path fit the \
                     largest capacity of {MAX_CHANNELS} channels): give fewer",
                    s.set(Field::Segments, n)
                ),
            ));
        }
        if self.detrend && hold > 0 {
            return Err(RequestError::new(
                Field::Detrend,
                "detrend_with_hold",
                format!(
                    "{} applies to data without a hold ({}); with {} μ0 is measured by the \
                     hold: drop {} or give {}",
                    s.name(Field::Detrend),
                    s.set(Field::Hold, 0),
                    s.set(Field::Hold, hold),
                    s.name(Field::Detrend),
                    s.set(Field::Hold, 0)
                ),
            ));
        }
        if self.detrend && (self.mu0.is_some() || self.integrating) {
            return Err(RequestError::new(
                Field::Detrend,
                "detrend_conflict",
                format!(
                    "{} shifts the output and cannot go with a given μ0 or an integrating plant: \
                     drop one",
                    s.name(Field::Detrend)
                ),
            ));
        }
        if self.fit == ElementFit::Simulation && self.integrating {
            return Err(RequestError::new(
                Field::Fit,
                "fit_integrating",
                match s {
                    Syntax::Cli => "--fit simulation needs a plant without an integrator (not \
                                    --integrating yes): drop one, or give --fit auto or none"
                        .to_string(),
                    Syntax::Python => "fit=\"simulation\" needs a plant without an integrator \
                                       (not integrating=True): drop one, or give fit=\"auto\" or \
                                       \"none\""
                        .to_string(),
                },
            ));
        }
        if let Some(name) = &self.reference {
            if self.element == Element::Static {
                return Err(RequestError::new(
                    Field::Reference,
                    "reference_static",
                    format!(
                        "{} estimates a two-path element (backlash or switch): drop {}",
                        s.set(Field::Reference, name),
                        s.set(Field::Nonlinearity, s.text("static"))
                    ),
                ));
            }
            if self.integrating {
                return Err(RequestError::new(
                    Field::Reference,
                    "reference_integrating",
                    format!(
                        "{} is not available with {}",
                        s.set(Field::Reference, name),
                        s.on(Field::Integrating)
                    ),
                ));
            }
        }
        let fixed = match self.segments {
            Some(SegmentCount::Fixed(n)) => n,
            _ => 7,
        };
        let mut options = IdentifyOptions::uniform(umin, umax, fixed, hold);
        options.mu0 = self.mu0;
        options.static_nonlinearity = self.element == Element::Static;
        if let Some(k) = &self.knots_asc {
            options.knots_asc = k.clone();
        }
        if let Some(k) = &self.knots_desc {
            options.knots_desc = k.clone();
        }
        for (field, k) in [
            (Field::KnotsAsc, &options.knots_asc),
            (Field::KnotsDesc, &options.knots_desc),
        ] {
            let word = match field {
                Field::KnotsAsc => "ascending",
                _ => "descending",
            };
            if let Some((prev, next)) = k
                .windows(2)
                .map(|w| (w[0], w[1]))
                .find(|(a, b)| !(a.is_finite() && b.is_finite() && b > a))
            {
                return Err(RequestError::new(
                    field,
                    "knots_not_increasing",
                    format!(
                        "{} must be finite and strictly increasing: {next} follows {prev}; give \
                         them in increasing order, each once",
                        match s.name(field) {
                            name if name.contains(word) => name.to_string(),
                            name => format!("{name} (the {word} path's knots)"),
                        }
                    ),
                ));
            }
            if k.first() != Some(&umin) || k.last() != Some(&umax) {
                return Err(RequestError::new(
                    field,
                    "knot_endpoints",
                    format!(
                        "{} must start at {} and end at {}",
                        s.name(field),
                        s.set(Field::UMin, umin),
                        s.set(Field::UMax, umax)
                    ),
                ));
            }
        }
        let knots_given = self.knots_asc.is_some() || self.knots_desc.is_some();
        if knots_given && options.channels() > MAX_CHANNELS {
            let field = match (&self.knots_asc, &self.knots_desc) {
                (None, Some(_)) => Field::KnotsDesc,
                _ => Field::KnotsAsc,
            };
            return Err(RequestError::new(
                field,
                "knots_capacity",
                format!(
                    "{} knots ascending and {} descending need {} channels: the largest \
                     capacity holds at most {MAX_CHANNELS} channels (at most {most} segments per \
                     path): give fewer knots",
                    options.knots_asc.len(),
                    options.knots_desc.len(),
                    options.channels()
                ),
            ));
        }
        (options.f, options.p) = self.horizons.unwrap_or((10, 10));
        options.order = self.order;
        options.basis = self.basis;
        options.settle = self.settle.unwrap_or(hold / 2);
        let choices = Choices {
            segments: match self.segments {
                _ if knots_given => Segments::Given,
                Some(SegmentCount::Fixed(_)) => Segments::Given,
                Some(SegmentCount::Auto) => Segments::FromData(AUTO_CANDIDATES.collect()),
                None => Segments::FromData(SEGMENT_CANDIDATES.to_vec()),
            },
            knots: match knots_given {
                true => choose::KnotPlacement::Given,
                false => choose::KnotPlacement::FromData,
            },
            horizons: match self.horizons {
                Some(_) => choose::Horizons::Given,
                None => choose::Horizons::FromData,
            },
            estimator: if !self.refine || self.reference.is_some() {
                ModelStage::Subspace
            } else {
                ModelStage::Refined
            },
            ..Choices::default()
        };
        Ok(Plan { options, choices })
    }

    /// Checks the request against `record` ([`validate`](Self::validate) and what depends on
    /// the record) and gives the plan for it.
    pub(crate) fn plan_for(&self, record: &crate::model::Record) -> Result<Plan, RequestError> {
        self.check_record(record)?;
        self.validate(record.hold)
    }

    /// Checks what depends on the record: the element's fit and the closed-loop estimate on
    /// one experiment, the reference present, the first experiment longer than the hold.
    pub(crate) fn check_record(&self, record: &crate::model::Record) -> Result<(), RequestError> {
        let s = self.syntax;
        let experiments = record.starts.len();
        if let Some(name) = &self.reference {
            if experiments > 1 {
                return Err(RequestError::new(
                    Field::Reference,
                    "reference_records",
                    format!(
                        "{} takes {}: join the experiments into one file",
                        s.set(Field::Reference, name),
                        s.one_record()
                    ),
                ));
            }
            if record.reference.is_none() {
                return Err(RequestError::new(
                    Field::Reference,
                    "reference_missing",
                    format!(
                        "{}: the record has no reference values",
                        s.set(Field::Reference, name)
                    ),
                ));
            }
        }
        if self.fit == ElementFit::Simulation && experiments > 1 {
            return Err(RequestError::new(
                Field::Fit,
                "fit_records",
                format!(
                    "{} takes {}: the element's state does not carry across experiments",
                    s.set(Field::Fit, s.text("simulation")),
                    s.one_record()
                ),
            ));
        }
        self.check_hold(record.first_len(), record.hold)?;
        self.check_work(record.u.len())
    }

    /// Checks that a refinement at a given order stays within [`MAX_REFINE_WORK`] on a record
    /// of `samples` samples: its parameters are the order's denominator, numerator and initial
    /// state, the border channels (the most segments the request may choose) and a noise model
    /// of order 2. Orders chosen from the data are bounded by the horizons and refined on the
    /// choice window; without refinement the work is a few passes whatever the order.
    pub fn check_work(&self, samples: usize) -> Result<(), RequestError> {
        let Some(order) = self
            .order
            .filter(|_| self.refine && self.reference.is_none())
        else {
            return Ok(());
        };
        let s = self.syntax;
        let count = match self.segments {
            Some(SegmentCount::Fixed(n)) => n,
            Some(SegmentCount::Auto) => AUTO_CANDIDATES.max().unwrap_or(0),
            None => SEGMENT_CANDIDATES.iter().copied().max().unwrap_or(0),
        };
        let path = |k: &Option<Vec<f64>>| k.as_ref().map_or(count, |k| k.len().saturating_sub(1));
        let channels = 1
            + path(&self.knots_asc)
            + match self.element {
                Element::Static => 0,
                _ => path(&self.knots_desc),
            };
        let parameters = 3 * order + channels + 4;
        let work = samples as f64 * (parameters * parameters) as f64 * REFINE_ITERATIONS as f64;
        if work <= MAX_REFINE_WORK {
            return Ok(());
        }
        Err(RequestError::new(
            Field::Order,
            "work",
            format!(
                "{} on {samples} samples: a refinement of {parameters} parameters costs samples × \
                 parameters² per iteration, {work:.1e} multiply–adds at its {REFINE_ITERATIONS} \
                 iterations, above the {MAX_REFINE_WORK:.0e} a run may ask for before it starts \
                 (minutes to hours on one core): give a lower order, fewer segments, {}, or a \
                 shorter record",
                s.set(Field::Order, order),
                match s {
                    Syntax::Cli => "--no-refine",
                    Syntax::Python => "refine=False",
                },
            ),
        ))
    }

    /// Checks that a first experiment of `samples` samples outlasts a hold of `hold` samples
    /// (of the increments, which lose one sample of each, for an integrating plant): with
    /// every sample inside the hold there is nothing to identify from.
    pub fn check_hold(&self, samples: usize, hold: usize) -> Result<(), RequestError> {
        let s = self.syntax;
        let (hold, first) = match self.integrating {
            true => (hold.saturating_sub(1), samples.saturating_sub(1)),
            false => (hold, samples),
        };
        if hold < first {
            return Ok(());
        }
        Err(RequestError::new(
            Field::Hold,
            "all_hold",
            match s {
                Syntax::Cli => format!(
                    "{first} samples, all inside the hold of {hold} (--hold): nothing left to identify from"
                ),
                Syntax::Python => format!(
                    "{first} samples, all inside the hold of {hold}: nothing left to identify from"
                ),
            },
        ))
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    #[test]
    fn paper_settings_give_the_paper_estimator() {
        let mut r = IdentifyRequest::new(-3.0, 3.0, Syntax::Python);
        r.segments = Some(SegmentCount::Fixed(7));
        r.horizons = Some((10, 10));
        r.refine = false;
        let plan = r.validate(300).unwrap();
        assert_eq!(plan.options, IdentifyOptions::uniform(-3.0, 3.0, 7, 300));
        assert_eq!(plan.choices.segments, Segments::Given);
        assert_eq!(plan.choices.horizons, choose::Horizons::Given);
        assert_eq!(plan.choices.estimator, ModelStage::Subspace);
    }

    #[test]
    fn defaults_choose_from_the_data_and_refine() {
        let mut r = IdentifyRequest::new(-1.0, 1.0, Syntax::Cli);
        r.element = Element::Static;
        r.order = Some(3);
        let plan = r.validate(0).unwrap();
        assert_eq!(
            plan.choices.segments,
            Segments::FromData(SEGMENT_CANDIDATES.to_vec())
        );
        assert_eq!(plan.choices.horizons, choose::Horizons::FromData);
        assert_eq!(plan.choices.estimator, ModelStage::Refined);
        assert!(plan.options.static_nonlinearity);
        assert_eq!(plan.options.order, Some(3));
    }

    #[test]
    fn each_front_end_reads_the_error_in_its_own_words() {
        let mut r = IdentifyRequest::new(-1.0, 1.0, Syntax::Cli);
        r.knots_asc = Some(vec![-1.0, 0.0, 0.9]);
        let e = r.validate(300).unwrap_err();
        assert_eq!(e.field, Field::KnotsAsc);
        assert_eq!(e.kind, "knot_endpoints");
        assert_eq!(
            e.message,
            "--knots-asc must start at --umin -1 and end at --umax 1"
        );
        r.syntax = Syntax::Python;
        assert_eq!(
            r.validate(300).unwrap_err().message,
            "knots (ascending) must start at umin=-1 and end at umax=1"
        );
        // Unsorted, repeated or non-finite knots are refused before any work, in each
        // front end's words.
        for (knots, next, prev) in [
            (vec![-1.0, 0.5, 0.0, 1.0], "0", "0.5"),
            (vec![-1.0, 0.0, 0.0, 1.0], "0", "0"),
            (vec![-1.0, f64::NAN, 1.0], "NaN", "-1"),
        ] {
            let mut r = IdentifyRequest::new(-1.0, 1.0, Syntax::Cli);
            r.knots_desc = Some(knots);
            let e = r.validate(300).unwrap_err();
            assert_eq!(
                (e.field, e.kind),
                (Field::KnotsDesc, "knots_not_increasing")
            );
            assert_eq!(
                e.message,
                format!(
                    "--knots-desc (the descending path's knots) must be finite and strictly \
                     increasing: {next} follows {prev}; give them in increasing order, each once"
                )
            );
            r.syntax = Syntax::Python;
            assert!(
                r.validate(300)
                    .unwrap_err()
                    .message
                    .starts_with("knots (descending) must be finite and strictly increasing: ")
            );
        }
        let mut r = IdentifyRequest::new(1.0, -1.0, Syntax::Python);
        assert_eq!(r.validate(0).unwrap_err().kind, "invalid_interval");
        r = IdentifyRequest::new(-1.0, 1.0, Syntax::Cli);
        r.detrend = true;
        assert_eq!(
            r.validate(300).unwrap_err().message,
            "--detrend applies to data without a hold (--hold 0); with --hold 300 μ0 is \
             measured by the hold: drop --detrend or give --hold 0"
        );
    }

    #[test]
    fn the_closed_loop_estimate_needs_a_two_path_element_and_one_record() {
        let mut r = IdentifyRequest::new(-1.0, 1.0, Syntax::Cli);
        r.reference = Some("r".into());
        r.element = Element::Static;
        assert_eq!(
            r.validate(0).unwrap_err().message,
            "--reference-column r estimates a two-path element (backlash or switch): drop \
             --nonlinearity static"
        );
        r.element = Element::Backlash;
        let plan = r.validate(0).unwrap();
        assert_eq!(plan.choices.estimator, ModelStage::Subspace);
        let mut rec = crate::model::Record::new(vec![0.0; 4], vec![0.0; 4]).unwrap();
        rec.starts = vec![0, 2];
        assert_eq!(r.check_record(&rec).unwrap_err().kind, "reference_records");
        rec.starts = vec![0];
        assert_eq!(r.check_record(&rec).unwrap_err().kind, "reference_missing");
    }

    /// A given order is refused before the work when its refinement's normal equations would
    /// cost more than [`MAX_REFINE_WORK`] multiply–adds (`samples × d² × 100`), in each front
    /// end's words; what the defaults choose, a short record and no refinement pass.
    #[test]
    fn a_refinement_too_large_for_the_record_is_refused_before_it_starts() {
        let mut r = IdentifyRequest::new(-1.0, 1.0, Syntax::Cli);
        r.order = Some(30);
        // 14 segments a path at most: d = 3 · 30 + 29 + 4 = 123.
        assert!(r.check_work(6_300).is_ok());
        let e = r.check_work(1_000_000).unwrap_err();
        assert_eq!((e.field, e.kind), (Field::Order, "work"));
        assert!(
            e.message
                .starts_with("--order 30 on 1000000 samples: a refinement of 123 parameters")
                && e.message.contains("1.5e12 multiply–adds")
                && e.message.contains("--no-refine"),
            "{}",
            e.message
        );
        // 10⁶ · 123² · 100 = 1.51e12 over the limit; 650,000 samples (0.98e12) within it.
        assert!(r.check_work(650_000).is_ok());
        assert!(r.check_work(670_000).is_err());
        // Given knots count as given: 3 segments a path, d = 3 · 30 + 7 + 4 = 101.
        r.knots_asc = Some(vec![-1.0, -0.5, 0.5, 1.0]);
        r.knots_desc = r.knots_asc.clone();
        assert!(r.check_work(950_000).is_ok());
        assert!(r.check_work(1_000_000).is_err());
        r.refine = false;
        assert!(r.check_work(100_000_000).is_ok());
        let mut p = IdentifyRequest::new(-1.0, 1.0, Syntax::Python);
        assert!(p.check_work(100_000_000).is_ok(), "the order from the data");
        p.order = Some(2);
        p.segments = Some(SegmentCount::Fixed(10));
        assert!(p.check_work(1_000_000).is_ok(), "the tour's servo at 10⁶");
        p.order = Some(40);
        let e = p.check_work(1_000_000).unwrap_err();
        assert!(
            e.message.starts_with("order=40 on 1000000 samples")
                && e.message.contains("refine=False"),
            "{}",
            e.message
        );
    }
}
