//! What can go wrong while reading or writing a model file.

use std::path::{Path, PathBuf};

use super::FORMAT;
use crate::io::{FileError, LimitedReadError, TooLarge};

/// A model file that could not be read or written.
///
/// `Display` gives one line that starts with the file name, e.g.
/// `m.json: field "B": has 1 entries, expected order = 2`.
#[derive(Debug, thiserror::Error)]
pub enum ModelFileError {
    /// The file could not be opened, read, created or written (not found, permission denied,
    /// ...).
    #[error("{0}")]
    File(#[from] FileError),
    /// The file is larger than [`MAX_MODEL_FILE_BYTES`](super::MAX_MODEL_FILE_BYTES): not a
    /// model file (those are kilobytes); refused before it is read.
    #[error(
        "{0}: a model file is a few kilobytes; give the JSON file identify, solve or \
         diagnose wrote"
    )]
    TooLarge(#[source] TooLarge),
    /// The file has no `format` key, or names another format or version than [`FORMAT`].
    #[error("{}", version_text(.path, .found.as_deref()))]
    Version {
        /// File that was being read.
        path: PathBuf,
        /// The `format` value found (`None`: no `format` key, a file of the unversioned
        /// layout written before the format had a version).
        found: Option<String>,
    },
    /// The JSON text is malformed or does not have the fields and types of the format.
    #[error("{path}: {}{source}", field_prefix(.location.as_deref()))]
    Json {
        /// File that was being read or written.
        path: PathBuf,
        /// Where in the document the problem is (e.g. `A[1][0]`); `None` for the document as a
        /// whole (malformed JSON, or a place the reader cannot name).
        location: Option<String>,
        /// The underlying error.
        source: serde_json::Error,
    },
    /// An object of the file repeats a key (JSON readers would keep one of the values
    /// silently).
    #[error(
        "{path}: key \"{key}\" appears twice: a model file states each key once; keep the one \
         meant"
    )]
    DuplicateKey {
        /// File that was being read.
        path: PathBuf,
        /// The repeated key, with its place (`D`, `noise.c`).
        key: String,
    },
    /// The model is well-formed JSON but inconsistent (wrong matrix shape, lengths that differ,
    /// non-finite numbers, knots out of order).
    #[error("{path}: field \"{field}\": {reason}")]
    Invalid {
        /// File that was being read or written.
        path: PathBuf,
        /// The JSON key of the offending field, e.g. `A`, `border_desc` or `noise.c`.
        field: &'static str,
        /// What is wrong.
        reason: String,
    },
}

/// The message of [`ModelFileError::Version`].
fn version_text(path: &Path, found: Option<&str>) -> String {
    match found {
        None => format!(
            "{}: no \"format\" key: the file is of the unversioned model layout, this hsid \
             reads \"{FORMAT}\"; identify the model again with this hsid (its --json)",
            path.display()
        ),
        Some(v) => format!(
            "{}: model format \"{v}\", this hsid reads \"{FORMAT}\"; write the model with \
             the hsid that reads it, or identify it again with this one",
            path.display()
        ),
    }
}

/// `field A[1][0]: ` before a JSON error that names its place, nothing before one that does
/// not.
fn field_prefix(location: Option<&str>) -> String {
    location.map_or_else(String::new, |at| format!("field {at}: "))
}

impl From<LimitedReadError> for ModelFileError {
    fn from(e: LimitedReadError) -> Self {
        match e {
            LimitedReadError::File(e) => Self::File(e),
            LimitedReadError::TooLarge(e) => Self::TooLarge(e),
        }
    }
}
