//! Why a diagnosis could not run.

use super::dynamics;
use crate::closed_loop::ReferenceError;
use crate::identify::IdentifyError;
use crate::model::RecordError;

/// Why a diagnosis could not run.
#[derive(Debug, thiserror::Error)]
pub enum DiagnoseError {
    /// The caller stopped the run ([`crate::progress::Reporter::stopped`]).
    #[error(transparent)]
    Interrupted(#[from] crate::progress::Interrupted),
    /// The identification failed.
    #[error("identification failed: {0}")]
    Identify(#[source] IdentifyError),
    /// `u` and `y` differ in length.
    #[error("u has {u} samples but y has {y}: give one y per u")]
    LengthMismatch {
        /// Input samples.
        u: usize,
        /// Output samples.
        y: usize,
    },
    /// Too few samples.
    #[error("{samples} samples are too few: at least {need} are needed")]
    TooShort {
        /// Samples available.
        samples: usize,
        /// Samples needed.
        need: usize,
    },
    /// Every sample of the estimation record lies inside the hold.
    #[error(
        "{samples} samples, all inside the hold of {hold}: nothing left to identify from; give a shorter hold"
    )]
    AllHold {
        /// Samples of the record.
        samples: usize,
        /// Samples of the hold.
        hold: usize,
    },
    /// The longest dead time to try is not shorter than the estimation record.
    #[error(
        "a dead time of up to {delay} samples (--max-delay) cannot be tried on an estimation record of {samples} samples: give a shorter --max-delay"
    )]
    MaxDelay {
        /// The longest dead time to try, in samples.
        delay: usize,
        /// Samples of the estimation record.
        samples: usize,
    },
    /// An input sample outside the knots' interval.
    #[error(
        "{record} sample {index}: u = {value} lies outside the knots' interval [{u_min}, {u_max}]"
    )]
    InputOutOfRange {
        /// `estimation` or `validation`.
        record: &'static str,
        /// 0-based sample.
        index: usize,
        /// The value.
        value: f64,
        /// Interval start.
        u_min: f64,
        /// Interval end.
        u_max: f64,
    },
    /// The split fraction is not in (0, 1).
    #[error("split fraction {0} must lie strictly between 0 and 1")]
    InvalidSplit(f64),
    /// The held-out range is empty, inside the hold or beyond the record.
    #[error(
        "held-out range {start}..{end} must be non-empty, after the hold and within the {len} samples"
    )]
    InvalidHoldout {
        /// Start.
        start: usize,
        /// End (exclusive).
        end: usize,
        /// Record length.
        len: usize,
    },
    /// With a static nonlinearity, the input never visits the segments next to a knot (the
    /// core's `NoExcitation`, whose Table I advice does not apply to static data).
    #[error(
        "static nonlinearity: the basis function of knot {knot}{} is never excited: the input never visits {}; move or remove that knot (--knots, --segments, --select-segments), or record data whose input covers that range",
        knot_value(*.value),
        segment_text(*.segment)
    )]
    KnotNotVisited {
        /// Knot index (1-based, as in the core's error).
        knot: usize,
        /// The knot's value, when known.
        value: Option<f64>,
        /// Its neighbours (the segments the input never visits), when known.
        segment: Option<(f64, f64)>,
    },
    /// The closed-loop estimate from the record's reference failed, or the reference is
    /// unusable (length, non-finite, constant, too short, a static element).
    #[error("the reference: {0}")]
    Reference(#[source] ReferenceError),
    /// A model class beyond the linear dynamics could not be fitted.
    #[error("{0}")]
    Dynamics(#[source] dynamics::DynamicsError),
    /// A figure or report could not be written.
    #[error("{0}")]
    Output(String),
    /// A setting beyond what the diagnosis takes, refused before any work
    /// ([`DiagnoseOptions::check`](super::DiagnoseOptions::check)).
    #[error("{name} = {value}: {why}")]
    Setting {
        /// The setting, as the options name it.
        name: &'static str,
        /// Its value.
        value: String,
        /// What it must be.
        why: String,
    },
}

/// A record that could not be made, as the diagnosis reports the same fault in a record it is
/// given: `u` and `y` of different lengths, or a reference of another length than both.
impl From<RecordError> for DiagnoseError {
    fn from(e: RecordError) -> Self {
        match e {
            RecordError::LengthMismatch { u, y } => DiagnoseError::LengthMismatch { u, y },
            // `with_reference` takes a record whose `u` and `y` agree.
            RecordError::ReferenceLength { u, r } => {
                DiagnoseError::Reference(ReferenceError::LengthMismatch { u, y: u, r })
            }
        }
    }
}

/// ` (u = 0.5)` after the knot's index when its value is known.
fn knot_value(value: Option<f64>) -> String {
    value.map_or_else(String::new, |v| format!(" (u = {v})"))
}

/// The segments the input never visits: `[a, b]` when known.
fn segment_text(segment: Option<(f64, f64)>) -> String {
    match segment {
        Some((a, b)) => format!("[{a}, {b}]"),
        None => "the segments next to it".to_owned(),
    }
}
