//! One device's outcome: a model, or a typed error that costs that device and never the batch.

use crate::model::Element;
use hsid::{CheckpointError, Error};
use serde_json::{Value, json};

use crate::identify::{CheckpointSolve, IdentifyError};

/// Why one device of a fleet has no model.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum DeviceError {
    /// Its directory entry could not be read (the I/O error's text).
    #[error("cannot read the checkpoint: {0}")]
    Unreadable(String),
    /// The checkpoint was read but restoring or solving it failed (truncated, corrupt, not a
    /// checkpoint, or an identification that failed on the data it holds).
    #[error("{0}")]
    Solve(#[source] IdentifyError),
    /// The file is larger than any checkpoint the desktop front end can restore; it was not read.
    #[error(
        "{bytes} bytes, more than the largest checkpoint ({limit} bytes): not a checkpoint; keep only checkpoint files in the directory"
    )]
    FileTooLarge {
        /// The file's size in bytes (or the bytes read before the limit was passed).
        bytes: u64,
        /// The largest checkpoint, in bytes.
        limit: usize,
    },
    /// A valid checkpoint written with other settings than the fleet's.
    #[error(
        "written with other settings than the fleet's ({what}): solve it with its own fleet's settings or on its own (hsid solve --state)"
    )]
    ForeignSettings {
        /// What differs, e.g. `"knots"` or `"horizons f = 8, p = 8 (fleet: f = 10, p = 10)"`.
        what: String,
    },
}

impl DeviceError {
    /// A short stable name of the error's kind, for machines (`"checkpoint_truncated"`,
    /// `"checkpoint_checksum"`, `"foreign_settings"`, `"unreadable"`, …).
    pub fn kind(&self) -> &'static str {
        match self {
            DeviceError::Unreadable(_) => "unreadable",
            DeviceError::FileTooLarge { .. } => "file_too_large",
            DeviceError::ForeignSettings { .. } => "foreign_settings",
            DeviceError::Solve(IdentifyError::Core(Error::Checkpoint(c))) => checkpoint_kind(*c),
            DeviceError::Solve(IdentifyError::TooLarge { .. }) => "too_large",
            DeviceError::Solve(_) => "identification",
        }
    }
}

/// The kind of a checkpoint error: the name the fleet's JSON lines and the Python package's
/// exceptions give it.
pub fn checkpoint_kind(c: CheckpointError) -> &'static str {
    match c {
        CheckpointError::Truncated => "checkpoint_truncated",
        CheckpointError::NotACheckpoint => "not_a_checkpoint",
        CheckpointError::Version => "checkpoint_version",
        CheckpointError::ScalarType => "checkpoint_scalar_type",
        CheckpointError::Checksum => "checkpoint_checksum",
        CheckpointError::SettingsMismatch => "checkpoint_settings_mismatch",
        CheckpointError::Capacity => "checkpoint_capacity",
        CheckpointError::Invalid => "checkpoint_invalid",
        CheckpointError::Summation => "checkpoint_summation",
    }
}

/// One device's outcome, named by its id (the checkpoint's file name).
#[derive(Clone, Debug, PartialEq)]
pub struct DeviceResult {
    /// The device id.
    pub device: String,
    /// The solved checkpoint, or why there is none.
    pub outcome: Result<CheckpointSolve, DeviceError>,
}

impl DeviceResult {
    /// The JSON line of `hsid fleet`: `{"device": …, "model": {…}}` with the model in the
    /// model format, or `{"device": …, "error": {"kind": …, "message": …}}`.
    pub fn to_json(&self) -> Value {
        match &self.outcome {
            Ok(solved) => {
                let kind = solved.shared_knots.then_some(Element::Static);
                let model = serde_json::to_value(solved.model.to_json(kind)).unwrap_or_else(
                    |e| json!({"error": format!("the model did not serialize: {e}")}),
                );
                json!({"device": self.device, "model": model})
            }
            Err(e) => json!({
                "device": self.device,
                "error": {"kind": e.kind(), "message": e.to_string()},
            }),
        }
    }
}
