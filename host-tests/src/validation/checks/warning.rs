//! A violated assumption: which check found it, and what was found in words.

use std::fmt;

use serde::Serialize;

/// The data checks, one per assumption of the method.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Check {
    /// Every monotone input run starts at `u_min` or `u_max` (Table I).
    Table1Structure,
    /// Both paths visited over the whole interval.
    PathCoverage,
    /// The regressor persistently exciting of order `(f + p)·m`.
    PersistentExcitation,
    /// A hold at `u_min` with the output settled in it.
    Hold,
    /// The output sits at an extreme.
    OutputSaturation,
    /// The output takes values on a grid.
    OutputQuantisation,
    /// The input takes few distinct values.
    InputLevels,
    /// The input is correlated with earlier residuals: feedback.
    Feedback,
    /// The output keeps a unit root (an ARX unit-root test does not reject it): an
    /// integrating plant.
    Integrating,
    /// The estimate of the declared order can be normalised: its static gain `G(1)` is told
    /// from zero.
    Order,
}

impl Check {
    /// The check's name, as in the reports.
    pub fn name(self) -> &'static str {
        match self {
            Check::Table1Structure => "table1_structure",
            Check::PathCoverage => "path_coverage",
            Check::PersistentExcitation => "persistent_excitation",
            Check::Hold => "hold",
            Check::OutputSaturation => "output_saturation",
            Check::OutputQuantisation => "output_quantisation",
            Check::InputLevels => "input_levels",
            Check::Feedback => "feedback",
            Check::Integrating => "integrating",
            Check::Order => "order",
        }
    }
}

impl fmt::Display for Check {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.pad(self.name())
    }
}

/// A violated assumption.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Warning {
    /// Which check.
    pub check: Check,
    /// What was found and its consequence, one sentence.
    pub message: String,
}

/// A warning of `check`.
pub fn warn(check: Check, message: String) -> Warning {
    Warning { check, message }
}
