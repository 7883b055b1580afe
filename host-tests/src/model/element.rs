//! The input element a model assumes: the one enum of the host (the model file's
//! `"nonlinearity"`, the diagnosis's setting, a plant specification's element, the command
//! line's `--nonlinearity`, Python's `nonlinearity=`), and the element with memory a model
//! fitted by simulation error simulates (the model file's `"element"`).

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

    /// The element with memory that simulates this element itself: the play operator for a
    /// backlash, the relay with borders for a switch; `None` for a static element.
    pub fn memory(self) -> Option<MemoryElement> {
        match self {
            Element::Backlash => Some(MemoryElement::Play),
            Element::Switch => Some(MemoryElement::Relay),
            Element::Static => None,
        }
    }
}

impl std::fmt::Display for Element {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// An element with memory, simulated as itself on its two borders: the model file's
/// `"element"` (`"play"` or `"relay"`) and the kind of a model fitted by simulation error.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum MemoryElement {
    /// The play operator `w(t) = min(max(w(t−1), H_a(u)), H_d(u))`, `H_a ≤ H_d` (backlash).
    Play,
    /// The relay with borders: `H_a(u)` while the input rises, `H_d(u)` while it falls
    /// (switch).
    Relay,
}

impl MemoryElement {
    /// Both elements with memory.
    pub const ALL: [MemoryElement; 2] = [MemoryElement::Play, MemoryElement::Relay];

    /// The element it simulates: backlash for the play operator, switch for the relay.
    pub fn element(self) -> Element {
        match self {
            MemoryElement::Play => Element::Backlash,
            MemoryElement::Relay => Element::Switch,
        }
    }

    /// The name of the element it simulates, as in files, on the command line and in the
    /// diagnosis: `backlash` or `switch`.
    pub fn name(self) -> &'static str {
        self.element().name()
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

    #[test]
    fn memory_elements_map_to_their_elements_and_keep_the_file_names() {
        for m in MemoryElement::ALL {
            assert_eq!(m.element().memory(), Some(m));
            assert_eq!(m.name(), m.element().name());
        }
        assert_eq!(Element::Static.memory(), None);
        let json: Vec<String> = MemoryElement::ALL
            .iter()
            .map(|m| serde_json::to_string(m).unwrap_or_default())
            .collect();
        assert_eq!(json, ["\"play\"", "\"relay\""]);
        assert_eq!(
            serde_json::from_str::<MemoryElement>("\"relay\"").ok(),
            Some(MemoryElement::Relay)
        );
    }
}
