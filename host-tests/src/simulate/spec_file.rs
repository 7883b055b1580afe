//! A plant specification read from its file: bounded in size (a specification is a few hundred
//! bytes; a larger file is refused before it is read) and every error naming the file.

use std::path::{Path, PathBuf};

use super::error::SimulateError;
use super::spec::PlantSpec;
use crate::io::{FileError, LimitedReadError, TooLarge, read_to_string_limited};

/// The largest specification file read, in bytes (1 MiB).
pub const MAX_SPEC_BYTES: u64 = 1 << 20;

/// Why a specification file could not be used.
#[derive(Debug, thiserror::Error)]
pub enum SpecFileError {
    /// The file could not be opened or read, or is not UTF-8.
    #[error(transparent)]
    File(FileError),
    /// The file is larger than [`MAX_SPEC_BYTES`]; it was not read.
    #[error("{0}: a plant specification is a few hundred bytes; is this the right file?")]
    TooLarge(#[source] TooLarge),
    /// The text is not a valid specification.
    #[error("{path}: {error}")]
    Spec {
        /// The file.
        path: PathBuf,
        /// What is wrong, naming the field.
        #[source]
        error: SimulateError,
    },
}

impl PlantSpec {
    /// Reads and checks the specification in `path` ([`PlantSpec::from_json_str`]).
    pub fn load(path: &Path) -> Result<Self, SpecFileError> {
        let text = read_to_string_limited(path, MAX_SPEC_BYTES).map_err(|e| match e {
            LimitedReadError::File(e) => SpecFileError::File(e),
            LimitedReadError::TooLarge(e) => SpecFileError::TooLarge(e),
        })?;
        Self::from_json_str(&text).map_err(|error| SpecFileError::Spec {
            path: path.to_path_buf(),
            error,
        })
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    #[test]
    fn a_file_is_read_checked_and_bounded() {
        let dir = std::env::temp_dir().join(format!("hsid-spec-file-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let servo =
            Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/data/servo-backlash.json");
        let spec = PlantSpec::load(&servo).unwrap();
        assert_eq!(spec.ts, Some(0.01));
        let big = dir.join("big.json");
        std::fs::File::create(&big)
            .unwrap()
            .set_len(MAX_SPEC_BYTES + 1)
            .unwrap();
        let e = PlantSpec::load(&big).unwrap_err();
        assert!(matches!(e, SpecFileError::TooLarge(_)), "{e}");
        let bad = dir.join("bad.json");
        std::fs::write(&bad, r#"{"ts": 0.01}"#).unwrap();
        let e = PlantSpec::load(&bad).unwrap_err();
        assert!(matches!(e, SpecFileError::Spec { .. }), "{e}");
        assert!(e.to_string().starts_with(&bad.display().to_string()), "{e}");
        let e = PlantSpec::load(&dir.join("missing.json")).unwrap_err();
        assert!(matches!(e, SpecFileError::File(_)), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
