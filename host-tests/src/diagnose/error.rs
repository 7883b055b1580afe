//! Why a diagnosis could not run.

use std::fmt;

use super::dynamics;
use crate::closed_loop::ReferenceError;
use crate::identify::IdentifyError;

/// Why a diagnosis could not run.
#[derive(Debug)]
pub enum DiagnoseError {
    /// The identification failed.
    Identify(IdentifyError),
    /// `u` and `y` differ in length.
    LengthMismatch {
        /// Input samples.
        u: usize,
        /// Output samples.
        y: usize,
    },
    /// Too few samples.
    TooShort {
        /// Samples available.
        samples: usize,
        /// Samples needed.
        need: usize,
    },
    /// An input sample outside the knots' interval.
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
    InvalidSplit(f64),
    /// The held-out range is empty, inside the hold or beyond the record.
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
    Reference(ReferenceError),
    /// A model class beyond the linear dynamics could not be fitted.
    Dynamics(dynamics::DynamicsError),
    /// A figure or report could not be written.
    Output(String),
}

impl fmt::Display for DiagnoseError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            DiagnoseError::Identify(e) => write!(f, "identification failed: {e}"),
            DiagnoseError::Dynamics(e) => write!(f, "{e}"),
            DiagnoseError::Reference(e) => write!(f, "the reference: {e}"),
            DiagnoseError::LengthMismatch { u, y } => {
                write!(f, "u has {u} samples but y has {y}: give one y per u")
            }
            DiagnoseError::TooShort { samples, need } => {
                write!(
                    f,
                    "{samples} samples are too few: at least {need} are needed"
                )
            }
            DiagnoseError::InputOutOfRange {
                record,
                index,
                value,
                u_min,
                u_max,
            } => write!(
                f,
                "{record} sample {index}: u = {value} lies outside the knots' interval [{u_min}, {u_max}]"
            ),
            DiagnoseError::InvalidSplit(v) => {
                write!(f, "split fraction {v} must lie strictly between 0 and 1")
            }
            DiagnoseError::InvalidHoldout { start, end, len } => write!(
                f,
                "held-out range {start}..{end} must be non-empty, after the hold and within the {len} samples"
            ),
            DiagnoseError::KnotNotVisited {
                knot,
                value,
                segment,
            } => {
                write!(f, "static nonlinearity: the basis function of knot {knot}")?;
                if let Some(v) = value {
                    write!(f, " (u = {v})")?;
                }
                write!(f, " is never excited: the input never visits ")?;
                match segment {
                    Some((a, b)) => write!(f, "[{a}, {b}]")?,
                    None => write!(f, "the segments next to it")?,
                }
                write!(
                    f,
                    "; move or remove that knot (--knots, --segments, --select-segments), or record data whose input covers that range"
                )
            }
            DiagnoseError::Output(e) => write!(f, "{e}"),
        }
    }
}

impl std::error::Error for DiagnoseError {}
