//! What can go wrong while reading a plant specification or simulating.

use std::fmt;
use std::path::PathBuf;

use crate::io::IoError;
use crate::units::TimeError;

/// Everything that can go wrong in [`simulate_plant`](super::simulate_plant),
/// [`simulate_model`](super::simulate_model) and the reading of their inputs.
///
/// `Display` gives one line that names the field (a dotted path into the specification, e.g.
/// `plant.zeta`) or the line of the input file, what is wrong, and what to do.
#[derive(Debug)]
pub enum SimulateError {
    /// The specification is not valid JSON.
    Json {
        /// The parser's message (with line and column).
        reason: String,
    },
    /// The specification is not valid JSON or does not fit the format (an unknown field, a
    /// wrong type, a missing field).
    Format {
        /// Dotted path of the offending place (`.` for the top level).
        field: String,
        /// The parser's message.
        reason: String,
    },
    /// A number of the specification is out of its range.
    OutOfRange {
        /// Dotted path of the field.
        field: String,
        /// The value given.
        value: f64,
        /// The range it must lie in, in words (e.g. "> 0").
        must: &'static str,
    },
    /// A field is required by the other fields given.
    Missing {
        /// Dotted path of the missing field.
        field: String,
        /// Why it is required.
        why: &'static str,
    },
    /// Fields were given that cannot go together.
    Conflict {
        /// Dotted path of the field that is not used.
        field: String,
        /// Why it cannot be used here.
        why: String,
    },
    /// Knots that do not increase strictly, or knot and value lists of different lengths.
    Knots {
        /// Dotted path of the knot list.
        field: String,
        /// What is wrong.
        reason: String,
    },
    /// The discrete-time plant (or noise filter) has a pole on or outside the unit circle.
    Unstable {
        /// Dotted path of the transfer function.
        field: String,
        /// The largest pole modulus.
        radius: f64,
    },
    /// A transfer function the simulator refuses (empty or non-finite coefficients).
    TransferFunction {
        /// Dotted path of the transfer function.
        field: String,
        /// What is wrong.
        reason: String,
    },
    /// An input value outside the model's interval, without `--extrapolate`.
    InputOutsideModel {
        /// The input file (`<stdin>` for standard input).
        source: PathBuf,
        /// 1-based line of the input file.
        line: usize,
        /// The value.
        value: f64,
        /// The model's `u_min`.
        lo: f64,
        /// The model's `u_max`.
        hi: f64,
    },
    /// The time column is not a time axis (it does not increase strictly).
    Time(TimeError),
    /// Coloured noise from the model was requested but the model file has no noise model.
    NoNoiseModel,
    /// White noise was requested without a level.
    NoNoiseLevel,
    /// The noise-free output is constant over the record: no SNR can be met.
    ConstantOutput,
    /// The input file could not be read.
    Io(IoError),
}

impl fmt::Display for SimulateError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Json { reason } => write!(f, "not valid JSON: {reason}"),
            Self::Format { field, reason } => write!(f, "field \"{field}\": {reason}"),
            Self::OutOfRange { field, value, must } => write!(
                f,
                "field \"{field}\": {value} is out of range: it must be {must}"
            ),
            Self::Missing { field, why } => write!(f, "field \"{field}\" is missing: {why}"),
            Self::Conflict { field, why } => write!(f, "field \"{field}\": {why}; remove it"),
            Self::Knots { field, reason } => write!(f, "field \"{field}\": {reason}"),
            Self::Unstable { field, radius } => write!(
                f,
                "field \"{field}\": unstable (a pole of modulus {radius:.6} >= 1); give a stable plant"
            ),
            Self::TransferFunction { field, reason } => write!(f, "field \"{field}\": {reason}"),
            Self::InputOutsideModel {
                source,
                line,
                value,
                lo,
                hi,
            } => write!(
                f,
                "{} line {line}: u = {value} lies outside the model's interval [{lo}, {hi}]; \
                 keep the input inside it or pass --extrapolate",
                source.display()
            ),
            Self::Time(e) => write!(f, "{e}"),
            Self::NoNoiseModel => write!(
                f,
                "the model file has no noise model (\"noise\" is null): use --noise-colour white"
            ),
            Self::NoNoiseLevel => write!(
                f,
                "white noise needs a level: give --noise-snr DB or --noise-std S"
            ),
            Self::ConstantOutput => write!(
                f,
                "the noise-free output is constant over the record, so no SNR can be met; \
                 give a noise standard deviation instead"
            ),
            Self::Io(e) => write!(f, "{e}"),
        }
    }
}

impl std::error::Error for SimulateError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::Io(e) => Some(e),
            Self::Time(e) => Some(e),
            _ => None,
        }
    }
}

impl From<TimeError> for SimulateError {
    fn from(e: TimeError) -> Self {
        Self::Time(e)
    }
}

impl From<IoError> for SimulateError {
    fn from(e: IoError) -> Self {
        Self::Io(e)
    }
}
