//! The one model file, versioned (`"format": "hsid-model/1"`): written by every command that
//! produces a model (`identify`, `identify --refine`, `solve`, `diagnose --model-out`) and read
//! by every command that consumes one (`validate`).
//!
//! It holds the plant `(A, B, C, D)` and its poles, μ0, the nonlinearity's kind, knots and
//! border values, the identification's singular values, horizons and sample count, and, when
//! known, the noise model, the standard deviations of a refined model, the sample time and the
//! units. The JSON keys are the field names below except the matrices, `A`, `B`, `C` and `D`;
//! unknown keys are refused and optional fields are written as `null` when unknown. The layout
//! is described in `docs/model-format.md` and `docs/model-format.schema.json`.
//!
//! [`ModelFile::from_json_str`] checks the version first: a file without the `format` key (the
//! unversioned layout of earlier releases) or with another version is a
//! [`ModelFileError::Version`] naming what it found and what is read.

mod check;
mod error;
mod keys;
mod parts;

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::io::{FileError, read_to_string_limited};
use crate::model::Element;

pub use crate::model::MemoryElement;
pub use check::{MAX_MAGNITUDE, MAX_MODEL_KNOTS, MAX_MODEL_ORDER, POLE_TOLERANCE};
pub use error::ModelFileError;
pub use parts::{FormatTag, ModelStd, NoiseFile, Units};

/// The largest model file read, in bytes (16 MiB). A model of the largest capacity the desktop
/// accepts is well under 1 MB; a larger file is refused before it is read
/// ([`ModelFileError::TooLarge`]), so that a wrong path cannot make a reader hold gigabytes.
pub const MAX_MODEL_FILE_BYTES: u64 = 16 << 20;

/// The value of the `format` key this build reads and writes.
pub const FORMAT: &str = "hsid-model/1";

/// An identified model as stored on disk.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ModelFile {
    /// Always [`FORMAT`].
    pub format: FormatTag,
    /// Kind of the input element; `None` when it is a two-path element whose kind was not
    /// recorded (a checkpoint solved by `hsid solve`).
    pub nonlinearity: Option<Element>,
    /// Model order n.
    pub order: usize,
    /// State matrix, n rows of n values.
    #[serde(rename = "A")]
    pub a: Vec<Vec<f64>>,
    /// Input vector, n values.
    #[serde(rename = "B")]
    pub b: Vec<f64>,
    /// Output vector, n values.
    #[serde(rename = "C")]
    pub c: Vec<f64>,
    /// Direct feed-through.
    #[serde(rename = "D")]
    pub d: f64,
    /// Eigenvalues of A as `[re, im]`, n of them.
    pub poles: Vec<[f64; 2]>,
    /// Offset μ₀ = H(u_min) of the nonlinearity.
    pub mu0: f64,
    /// Lower end of the input interval.
    pub u_min: f64,
    /// Upper end of the input interval.
    pub u_max: f64,
    /// Knots of the ascending border (of the one border of a static element).
    pub knots_asc: Vec<f64>,
    /// Knots of the descending border (equal to `knots_asc` for a static element).
    pub knots_desc: Vec<f64>,
    /// Values of the ascending border at `knots_asc`.
    pub border_asc: Vec<f64>,
    /// Values of the descending border at `knots_desc`.
    pub border_desc: Vec<f64>,
    /// Sample time in seconds, when known.
    pub sample_time: Option<f64>,
    /// Units of the input and the output, when known.
    pub units: Option<Units>,
    /// Singular values used for the order selection.
    pub singular_values: Vec<f64>,
    /// Future horizon f of the Hankel matrices.
    pub f: usize,
    /// Past horizon p of the Hankel matrices.
    pub p: usize,
    /// Number of samples used for the identification.
    pub samples: usize,
    /// Noise model of the output, when one was estimated.
    pub noise: Option<NoiseFile>,
    /// Standard deviations of the estimates, when the model was refined.
    pub std: Option<ModelStd>,
    /// The plant integrates: the file holds its stable part `G₀` (identified on the output's
    /// increments, normalised by `G₀(1) = 1`, μ0 and the borders in output units per sample)
    /// and the plant has one more pole, fixed at `z = 1`. Written only when true, so the files
    /// of other plants are unchanged; a file without the key reads as `false`.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub integrating: bool,
    /// The element is the play operator or the relay itself on the borders (a model fitted by
    /// simulation error on any input), not the two paths: both borders share the knots, μ0 is
    /// `w(−1)` (the level the plant rests at before the input) and `G(1) = 1`. Written only
    /// when present, so an older reader refuses such a file as an unknown key rather than
    /// simulate it as a two-path model; a file without it reads as `None`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub element: Option<MemoryElement>,
    /// Friction on the model's velocity ([`crate::friction`]): the element's output less
    /// `coulomb · tanh(v / velocity_scale) + offset` drives `G` (strictly proper, `D = 0`), the
    /// element's output `delay` samples late; `v` is `G`'s output for an integrating plant,
    /// its change per sample otherwise. Written only when present (an older reader refuses
    /// the file rather than simulate it without friction); a file without it reads as `None`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub friction: Option<crate::friction::Friction>,
}

impl ModelFile {
    /// Checks shapes and values (see `check.rs`): `A` is order×order, `B`, `C` and `poles` have
    /// `order` entries, each knot vector has as many entries as its border, knots increase
    /// strictly from `u_min` to `u_max`, every number is finite and at most [`MAX_MAGNITUDE`]
    /// in magnitude, the units hold no double quote or control character, the noise model is
    /// monic, the standard deviations have the shapes of what they describe. `source` is only
    /// used in the error.
    pub fn validate(&self, source: impl AsRef<Path>) -> Result<(), ModelFileError> {
        check::validate(self, source.as_ref())
    }

    /// Serialises to pretty-printed JSON after [`validate`](Self::validate), with a final
    /// line break.
    pub fn to_json_string(&self, source: impl AsRef<Path>) -> Result<String, ModelFileError> {
        let path = source.as_ref();
        self.validate(path)?;
        let mut text = serde_json::to_string_pretty(self).map_err(|source| json(path, source))?;
        text.push('\n');
        Ok(text)
    }

    /// Parses JSON text, refuses a key that an object repeats
    /// ([`ModelFileError::DuplicateKey`]), checks its version and
    /// [`validate`](Self::validate)s it, then checks what a file read must be besides: `A`
    /// stable (its eigenvalues strictly inside the unit circle, for an integrating model too,
    /// whose `A` is the stable part) and `poles` the eigenvalues of `A` (within
    /// [`POLE_TOLERANCE`] relative). `source` is only used in errors.
    ///
    /// A type error inside a field names that field (e.g. `field A[1][0]: invalid type ...`); a
    /// missing field is reported as `missing field `A``.
    pub fn from_json_str(source: impl AsRef<Path>, text: &str) -> Result<Self, ModelFileError> {
        let path = source.as_ref();
        let value: serde_json::Value =
            serde_json::from_str(text).map_err(|source| json(path, source))?;
        if let Some(key) = keys::first_duplicate(text) {
            return Err(ModelFileError::DuplicateKey {
                path: path.to_path_buf(),
                key,
            });
        }
        let found = value.get("format");
        if found.and_then(|v| v.as_str()) != Some(FORMAT) {
            return Err(ModelFileError::Version {
                path: path.to_path_buf(),
                found: found.map(|v| v.as_str().map_or_else(|| v.to_string(), str::to_string)),
            });
        }
        let model: ModelFile = serde_path_to_error::deserialize(value).map_err(|e| {
            // A path of no segment, or of segments the reader could not name, is no place.
            let named = e
                .path()
                .iter()
                .any(|s| !matches!(s, serde_path_to_error::Segment::Unknown));
            let location = named.then(|| e.path().to_string());
            ModelFileError::Json {
                path: path.to_path_buf(),
                location,
                source: e.into_inner(),
            }
        })?;
        model.validate(path)?;
        check::on_read(&model, path)?;
        Ok(model)
    }

    /// Validates the model and writes it to `path` ([`to_json_string`](Self::to_json_string)).
    pub fn save(&self, path: impl AsRef<Path>) -> Result<(), ModelFileError> {
        let path = path.as_ref();
        let text = self.to_json_string(path)?;
        crate::io::write_atomic(path, text).map_err(|source| FileError::write(path, source).into())
    }

    /// Reads a model file ([`from_json_str`](Self::from_json_str)); a file larger than
    /// [`MAX_MODEL_FILE_BYTES`] is refused before it is read.
    pub fn load(path: impl AsRef<Path>) -> Result<Self, ModelFileError> {
        let path = path.as_ref();
        let text = read_to_string_limited(path, MAX_MODEL_FILE_BYTES)?;
        Self::from_json_str(path, &text)
    }
}

fn json(path: &Path, source: serde_json::Error) -> ModelFileError {
    ModelFileError::Json {
        path: path.to_path_buf(),
        location: None,
        source,
    }
}
