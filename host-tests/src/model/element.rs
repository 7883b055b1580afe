//! The input element a model assumes: the one enum of the host (the model file's
//! `"nonlinearity"`, the diagnosis's setting, a plant specification's element, the command
//! line's `--nonlinearity`, Python's `nonlinearity=`).

use serde::{Deserialize, Serialize};

/// The input element before the linear part.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
#[serde(rename_all = "snake_case")]
pub enum Element {
    /// Backlash (play operator): two paths, Table I data.
    Backlash,
    /// Switch (hysteresis relay with borders): two paths.
    Switch,
    /// Static, memoryless: one border for both directions, any input.
    Static,
}

impl Element {
    /// Every element, in the order of the documentation.
    pub const ALL: [Element; 3] = [Element::Backlash, Element::Switch, Element::Static];

    /// The name in files, on the command line and in Python: `backlash`, `switch` or
    /// `static`.
    pub fn name(self) -> &'static str {
        match self {
            Element::Backlash => "backlash",
            Element::Switch => "switch",
            Element::Static => "static",
        }
    }

    /// Two paths (backlash or switch), not one shared border.
    pub fn two_path(self) -> bool {
        self != Element::Static
    }
}

impl std::fmt::Display for Element {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// A name that is not an element.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("unknown element {0:?}: give \"backlash\", \"switch\" or \"static\"")]
pub struct UnknownElement(pub String);

impl std::str::FromStr for Element {
    type Err = UnknownElement;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Element::ALL
            .into_iter()
            .find(|e| e.name() == s)
            .ok_or_else(|| UnknownElement(s.to_string()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_through_text_and_json() {
        for e in Element::ALL {
            assert_eq!(e.name().parse::<Element>(), Ok(e));
            let json = serde_json::to_string(&e).unwrap_or_default();
            assert_eq!(json, format!("\"{}\"", e.name()));
            assert_eq!(serde_json::from_str::<Element>(&json).ok(), Some(e));
        }
        assert_eq!(
            "play".parse::<Element>(),
            Err(UnknownElement("play".into()))
        );
        assert!(!Element::Static.two_path() && Element::Switch.two_path());
    }
}
