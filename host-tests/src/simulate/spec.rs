//! The plant specification (`hsid simulate --plant SPEC`), as read from JSON: every field is
//! described in `docs/simulate.md`. Unknown fields are refused, and every error names the field
//! by its dotted path.

use serde::Deserialize;

use super::error::SimulateError;
use crate::model::Element;

/// A true plant: input element, linear part, output noise, sample time and units.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlantSpec {
    /// Sample time in seconds; required for a continuous-time plant.
    #[serde(default)]
    pub ts: Option<f64>,
    /// Units of the signals, carried into the output's header.
    #[serde(default)]
    pub units: Option<UnitsSpec>,
    /// The input element.
    pub element: ElementSpec,
    /// The linear part.
    pub plant: LinearSpec,
    /// Output noise; none when absent.
    #[serde(default)]
    pub noise: Option<NoiseSpec>,
}

/// Units of the input and the output, free text.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct UnitsSpec {
    /// Unit of u (e.g. `"V"`).
    #[serde(default)]
    pub input: Option<String>,
    /// Unit of y (e.g. `"deg"`).
    #[serde(default)]
    pub output: Option<String>,
}

/// A named border shape.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Shape {
    /// Zero in `[−width/2, width/2]`, slope `slope` outside.
    Deadband,
    /// `H_a(u) = slope (u − gap/2)`, `H_d(u) = slope (u + gap/2)`.
    Backlash,
    /// The paper's backlash: `H_a(u) = atan(u − 1)`, `H_d(u) = atan(u + 1)`.
    PaperBacklash,
    /// The paper's switch (Section IV-A).
    PaperSwitch,
}

/// Piecewise-linear border: values `y` at strictly increasing knots `u`.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Curve {
    /// Knots, strictly increasing, at least two.
    pub u: Vec<f64>,
    /// Border values at the knots.
    pub y: Vec<f64>,
}

/// The input element: a kind and its borders, as a named shape or as knots and values.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ElementSpec {
    /// Backlash, switch or static.
    pub kind: Element,
    /// A named shape, in place of knots.
    #[serde(default)]
    pub shape: Option<Shape>,
    /// Dead band width (shape `deadband`).
    #[serde(default)]
    pub width: Option<f64>,
    /// Backlash gap (shape `backlash`).
    #[serde(default)]
    pub gap: Option<f64>,
    /// Slope of the shapes `deadband` and `backlash` (default 1).
    #[serde(default)]
    pub slope: Option<f64>,
    /// Ascending border `H_a` (backlash, switch).
    #[serde(default)]
    pub ascending: Option<Curve>,
    /// Descending border `H_d` (backlash, switch).
    #[serde(default)]
    pub descending: Option<Curve>,
    /// The one border of a static element.
    #[serde(default)]
    pub border: Option<Curve>,
}

/// A discrete transfer function in `q⁻¹`.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TransferSpec {
    /// Numerator `b₀, b₁, …`.
    pub num: Vec<f64>,
    /// Denominator `a₀, a₁, …` (`a₀ ≠ 0`).
    pub den: Vec<f64>,
}

/// One continuous-time section of unit static gain: second order (`wn` or `fn_hz`, `zeta`) or
/// first order (`tau`).
#[derive(Clone, Debug, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SectionSpec {
    /// Natural frequency in rad/s.
    #[serde(default)]
    pub wn: Option<f64>,
    /// Natural frequency in Hz.
    #[serde(default)]
    pub fn_hz: Option<f64>,
    /// Damping ratio (≥ 0).
    #[serde(default)]
    pub zeta: Option<f64>,
    /// Time constant in seconds.
    #[serde(default)]
    pub tau: Option<f64>,
}

/// The linear part: a discrete transfer function, or continuous-time sections discretised by a
/// zero-order hold at `ts`.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LinearSpec {
    /// Discrete numerator (with `den`).
    #[serde(default)]
    pub num: Option<Vec<f64>>,
    /// Discrete denominator (with `num`).
    #[serde(default)]
    pub den: Option<Vec<f64>>,
    /// Natural frequency in rad/s of one inline section.
    #[serde(default)]
    pub wn: Option<f64>,
    /// Natural frequency in Hz of one inline section.
    #[serde(default)]
    pub fn_hz: Option<f64>,
    /// Damping ratio of one inline section.
    #[serde(default)]
    pub zeta: Option<f64>,
    /// Time constant in seconds of one inline section.
    #[serde(default)]
    pub tau: Option<f64>,
    /// Continuous sections in series.
    #[serde(default)]
    pub cascade: Option<Vec<SectionSpec>>,
    /// Static gain of the continuous plant (default 1).
    #[serde(default)]
    pub gain: Option<f64>,
    /// Extra delay in whole samples (default 0).
    #[serde(default)]
    pub delay: Option<usize>,
}

impl LinearSpec {
    /// The section given inline (`wn`/`fn_hz`, `zeta`, `tau` at the top of `plant`), if any.
    pub(crate) fn inline_section(&self) -> Option<SectionSpec> {
        let s = SectionSpec {
            wn: self.wn,
            fn_hz: self.fn_hz,
            zeta: self.zeta,
            tau: self.tau,
        };
        (s != SectionSpec::default()).then_some(s)
    }
}

/// Output noise: a level (SNR on the record or innovation standard deviation), a colour and a
/// seed.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NoiseSpec {
    /// Signal-to-noise ratio in dB, met exactly on the record.
    #[serde(default)]
    pub snr_db: Option<f64>,
    /// Standard deviation of the white noise that drives the colour filter.
    #[serde(default)]
    pub std: Option<f64>,
    /// `"white"` (default) or a filter `{"num": …, "den": …}`.
    #[serde(default)]
    pub colour: Option<ColourSpec>,
    /// Seed of the PCG32 generator (default 1).
    #[serde(default)]
    pub seed: Option<u64>,
}

/// The colour of the output noise.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(
    untagged,
    expecting = "\"white\" or a filter {\"num\": [...], \"den\": [...]}"
)]
pub enum ColourSpec {
    /// `"white"`.
    Named(ColourName),
    /// A noise filter `v = num/den e`.
    Filter(TransferSpec),
}

/// Named noise colours.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ColourName {
    /// White noise.
    White,
}

impl Shape {
    /// The name used in the specification.
    pub fn name(self) -> &'static str {
        match self {
            Self::Deadband => "deadband",
            Self::Backlash => "backlash",
            Self::PaperBacklash => "paper-backlash",
            Self::PaperSwitch => "paper-switch",
        }
    }
}

impl PlantSpec {
    /// Parses a specification from JSON text; an error names the offending field. A unit
    /// that holds a double quote or a control character is refused
    /// ([`check_unit_text`](crate::units::check_unit_text)).
    pub fn from_json_str(text: &str) -> Result<Self, SimulateError> {
        let de = &mut serde_json::Deserializer::from_str(text);
        let spec: Self = serde_path_to_error::deserialize(de).map_err(|e| {
            if e.inner().is_syntax() || e.inner().is_eof() {
                SimulateError::Json {
                    reason: e.inner().to_string(),
                }
            } else {
                SimulateError::Format {
                    field: e.path().to_string(),
                    reason: e.inner().to_string(),
                }
            }
        })?;
        if let Some(u) = &spec.units {
            for (field, unit) in [("units.input", &u.input), ("units.output", &u.output)] {
                if let Some(unit) = unit {
                    crate::units::check_unit_text(unit).map_err(|e| SimulateError::Format {
                        field: field.to_string(),
                        reason: format!("{unit:?}: {e}"),
                    })?;
                }
            }
        }
        Ok(spec)
    }
}
