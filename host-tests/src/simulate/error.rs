//! What can go wrong while reading a plant specification or simulating.

use std::path::PathBuf;

use crate::io::IoError;
use crate::units::TimeError;

/// Everything that can go wrong in [`simulate_plant`](super::simulate_plant),
/// [`simulate_model`](super::simulate_model) and the reading of their inputs.
///
/// `Display` gives one line that names the field (a dotted path into the specification, e.g.
/// `plant.zeta`) or the line of the input file, what is wrong, and what to do.
#[derive(Debug, thiserror::Error)]
pub enum SimulateError {
    /// The specification is not valid JSON.
    #[error("not valid JSON: {reason}")]
    Json {
        /// The parser's message (with line and column).
        reason: String,
    },
    /// The specification is not valid JSON or does not fit the format (an unknown field, a
    /// wrong type, a missing field).
    #[error("field \"{field}\": {reason}")]
    Format {
        /// Dotted path of the offending place (`.` for the top level).
        field: String,
        /// The parser's message.
        reason: String,
    },
    /// A number of the specification is out of its range.
    #[error("field \"{field}\": {value} is out of range: it must be {must}")]
    OutOfRange {
        /// Dotted path of the field.
        field: String,
        /// The value given.
        value: f64,
        /// The range it must lie in, in words (e.g. "> 0").
        must: &'static str,
    },
    /// A field is required by the other fields given.
    #[error("field \"{field}\" is missing: {why}")]
    Missing {
        /// Dotted path of the missing field.
        field: String,
        /// Why it is required.
        why: &'static str,
    },
    /// Fields were given that cannot go together.
    #[error("field \"{field}\": {why}; remove it")]
    Conflict {
        /// Dotted path of the field that is not used.
        field: String,
        /// Why it cannot be used here.
        why: String,
    },
    /// Knots that do not increase strictly, or knot and value lists of different lengths.
    #[error("field \"{field}\": {reason}")]
    Knots {
        /// Dotted path of the knot list.
        field: String,
        /// What is wrong.
        reason: String,
    },
    /// The discrete-time plant (or noise filter) has a pole on or outside the unit circle.
    #[error(
        "field \"{field}\": unstable (a pole of modulus {radius:.6} >= 1); give a stable plant"
    )]
    Unstable {
        /// Dotted path of the transfer function.
        field: String,
        /// The largest pole modulus.
        radius: f64,
    },
    /// A transfer function the simulator refuses (empty or non-finite coefficients).
    #[error("field \"{field}\": {reason}")]
    TransferFunction {
        /// Dotted path of the transfer function.
        field: String,
        /// What is wrong.
        reason: String,
    },
    /// An input value outside the model's interval, refused with `--strict-interval`
    /// ([`ModelOptions::strict_interval`](super::ModelOptions::strict_interval)).
    #[error(
        "{file} line {line}: u = {value} lies outside the model's interval [{lo}, {hi}]; \
         keep the input inside it or pass --extrapolate"
    )]
    InputOutsideModel {
        /// The input file (`<stdin>` for standard input).
        file: PathBuf,
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
    #[error("{0}")]
    Time(#[from] TimeError),
    /// Coloured noise from the model was requested but the model file has no noise model.
    #[error("the model file has no noise model (\"noise\" is null): use --noise-colour white")]
    NoNoiseModel,
    /// Coloured noise from the model of an integrating plant was requested: its noise model
    /// describes the output's increments, not the output.
    #[error(
        "the model integrates (\"integrating\": true): its noise model describes the output's increments, not the output; use --noise-colour white with --noise-snr DB or --noise-std S"
    )]
    IncrementsNoiseModel,
    /// White noise was requested without a level.
    #[error("white noise needs a level: give --noise-snr DB or --noise-std S")]
    NoNoiseLevel,
    /// The noise-free output is constant over the record: no SNR can be met.
    #[error(
        "the noise-free output is constant over the record, so no SNR can be met; \
         give a noise standard deviation instead"
    )]
    ConstantOutput,
    /// The input file could not be read.
    #[error("{0}")]
    Io(#[from] IoError),
}
