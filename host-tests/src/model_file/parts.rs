//! The parts of a model file besides the plant: the version tag, the nonlinearity's kind, the
//! units, the noise model and the standard deviations.

use serde::{Deserialize, Deserializer, Serialize, Serializer};

use super::FORMAT;

/// The `format` key: serialises as [`FORMAT`] and reads only that value.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct FormatTag;

impl Serialize for FormatTag {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(FORMAT)
    }
}

impl<'de> Deserialize<'de> for FormatTag {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let v = String::deserialize(d)?;
        if v == FORMAT {
            Ok(FormatTag)
        } else {
            Err(serde::de::Error::custom(format!(
                "format \"{v}\", expected \"{FORMAT}\""
            )))
        }
    }
}

/// Units of the signals, as free text (e.g. `"V"`, `"rpm"`).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Units {
    /// Unit of the input u.
    pub input: String,
    /// Unit of the output y.
    pub output: String,
}

/// Noise model `v = C(q)/D(q) e` of the output with `e` white of variance `sigma2`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NoiseFile {
    /// Numerator `[1, c₁, …]` (monic).
    pub c: Vec<f64>,
    /// Denominator `[1, d₁, …]` (monic).
    pub d: Vec<f64>,
    /// Innovation variance `σ_e²`.
    pub sigma2: f64,
}

/// Standard deviations of a refined model's estimates (asymptotic, from the refinement's
/// covariance by the delta method).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ModelStd {
    /// Of the real and imaginary part of each pole, in the order of `poles`.
    pub poles: Vec<[f64; 2]>,
    /// Of μ0.
    pub mu0: f64,
    /// Of the ascending border at each knot of `knots_asc`.
    pub border_asc: Vec<f64>,
    /// Of the descending border at each knot of `knots_desc`.
    pub border_desc: Vec<f64>,
    /// Of the mean gap between the borders (input units), from the refinement's whole
    /// covariance of the borders (their correlations included); absent for a static element
    /// and in files written before it was stored.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mean_gap: Option<f64>,
}
