//! What can go wrong while reading or writing a model file.

use std::fmt;
use std::path::PathBuf;

use super::FORMAT;
use crate::io::{FileError, LimitedReadError, TooLarge};

/// A model file that could not be read or written.
///
/// `Display` gives one line that starts with the file name, e.g.
/// `m.json: field "B": has 1 entries, expected order = 2`.
#[derive(Debug)]
pub enum ModelFileError {
    /// The file could not be opened, read, created or written (not found, permission denied,
    /// ...).
    File(FileError),
    /// The file is larger than [`MAX_MODEL_FILE_BYTES`](super::MAX_MODEL_FILE_BYTES): not a
    /// model file (those are kilobytes); refused before it is read.
    TooLarge(TooLarge),
    /// The file has no `format` key, or names another format or version than [`FORMAT`].
    Version {
        /// File that was being read.
        path: PathBuf,
        /// The `format` value found (`None`: no `format` key, a file of the unversioned
        /// layout written before the format had a version).
        found: Option<String>,
    },
    /// The JSON text is malformed or does not have the fields and types of the format.
    Json {
        /// File that was being read or written.
        path: PathBuf,
        /// Where in the document the problem is (e.g. `A[1][0]`); `None` for the document as a
        /// whole (malformed JSON, or a place the reader cannot name).
        location: Option<String>,
        /// The underlying error.
        source: serde_json::Error,
    },
    /// The model is well-formed JSON but inconsistent (wrong matrix shape, lengths that differ,
    /// non-finite numbers, knots out of order).
    Invalid {
        /// File that was being read or written.
        path: PathBuf,
        /// The JSON key of the offending field, e.g. `A`, `border_desc` or `noise.c`.
        field: &'static str,
        /// What is wrong.
        reason: String,
    },
}

impl fmt::Display for ModelFileError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::File(e) => e.fmt(f),
            Self::TooLarge(e) => write!(
                f,
                "{e}: a model file is a few kilobytes; give the JSON file identify, solve or \
                 diagnose wrote"
            ),
            Self::Version { path, found: None } => write!(
                f,
                "{}: no \"format\" key: the file is of the unversioned model layout, this hsid \
                 reads \"{FORMAT}\"; identify the model again with this hsid (its --json)",
                path.display()
            ),
            Self::Version {
                path,
                found: Some(v),
            } => write!(
                f,
                "{}: model format \"{v}\", this hsid reads \"{FORMAT}\"; write the model with \
                 the hsid that reads it, or identify it again with this one",
                path.display()
            ),
            Self::Json {
                path,
                location,
                source,
            } => match location {
                None => write!(f, "{}: {source}", path.display()),
                Some(at) => write!(f, "{}: field {at}: {source}", path.display()),
            },
            Self::Invalid {
                path,
                field,
                reason,
            } => write!(f, "{}: field \"{field}\": {reason}", path.display()),
        }
    }
}

impl std::error::Error for ModelFileError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::File(e) => Some(e),
            Self::Json { source, .. } => Some(source),
            Self::TooLarge(e) => Some(e),
            Self::Version { .. } | Self::Invalid { .. } => None,
        }
    }
}

impl From<FileError> for ModelFileError {
    fn from(e: FileError) -> Self {
        Self::File(e)
    }
}

impl From<LimitedReadError> for ModelFileError {
    fn from(e: LimitedReadError) -> Self {
        match e {
            LimitedReadError::File(e) => Self::File(e),
            LimitedReadError::TooLarge(e) => Self::TooLarge(e),
        }
    }
}
