//! Duplicate keys: JSON allows an object to repeat a key and serde keeps the last value, so
//! `"D": 0, "D": 100` would read as `D = 100` without a word. A model file's reader walks the
//! document first and refuses the first key that an object repeats, at any depth.

use std::cell::RefCell;
use std::collections::HashSet;
use std::fmt;

use serde::de::{self, DeserializeSeed, Deserializer, MapAccess, SeqAccess, Visitor};

/// The first key some object of `text` repeats, as its place in the document (`D`,
/// `noise.c`, `units.input`), or `None`. `text` is valid JSON (parsed before): a syntax error
/// found here reads as no duplicate, the parse having reported it.
pub(super) fn first_duplicate(text: &str) -> Option<String> {
    let found = RefCell::new(None);
    let mut de = serde_json::Deserializer::from_str(text);
    let walk = Walk {
        at: String::new(),
        found: &found,
    };
    // The walk stops with an error at the first duplicate; `found` holds it.
    let _ = walk.deserialize(&mut de);
    found.into_inner()
}

/// A value at place `at` of the document; a duplicate key found is put in `found`.
struct Walk<'a> {
    at: String,
    found: &'a RefCell<Option<String>>,
}

impl Walk<'_> {
    fn child(&self, step: &str) -> Self {
        let at = match self.at.is_empty() {
            true => step.to_string(),
            false if step.starts_with('[') => format!("{}{step}", self.at),
            false => format!("{}.{step}", self.at),
        };
        Walk {
            at,
            found: self.found,
        }
    }
}

impl<'de> DeserializeSeed<'de> for Walk<'_> {
    type Value = ();

    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<(), D::Error> {
        d.deserialize_any(self)
    }
}

impl<'de> Visitor<'de> for Walk<'_> {
    type Value = ();

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("any JSON value")
    }

    fn visit_bool<E: de::Error>(self, _: bool) -> Result<(), E> {
        Ok(())
    }

    fn visit_i64<E: de::Error>(self, _: i64) -> Result<(), E> {
        Ok(())
    }

    fn visit_u64<E: de::Error>(self, _: u64) -> Result<(), E> {
        Ok(())
    }

    fn visit_f64<E: de::Error>(self, _: f64) -> Result<(), E> {
        Ok(())
    }

    fn visit_str<E: de::Error>(self, _: &str) -> Result<(), E> {
        Ok(())
    }

    fn visit_unit<E: de::Error>(self) -> Result<(), E> {
        Ok(())
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<(), A::Error> {
        let mut i = 0;
        while seq
            .next_element_seed(self.child(&format!("[{i}]")))?
            .is_some()
        {
            i += 1;
        }
        Ok(())
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<(), A::Error> {
        let mut seen = HashSet::new();
        while let Some(key) = map.next_key::<String>()? {
            let child = self.child(&key);
            if !seen.insert(key) {
                *self.found.borrow_mut() = Some(child.at);
                return Err(de::Error::custom("duplicate key"));
            }
            map.next_value_seed(child)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_first_repeated_key_is_named_at_any_depth() {
        assert_eq!(first_duplicate(r#"{"D": 0, "C": [1], "E": null}"#), None);
        assert_eq!(
            first_duplicate(r#"{"D": 0, "D": 100}"#).as_deref(),
            Some("D")
        );
        assert_eq!(
            first_duplicate(r#"{"noise": {"c": [1], "d": [1], "c": [1, 0.5]}}"#).as_deref(),
            Some("noise.c")
        );
        assert_eq!(
            first_duplicate(r#"{"a": [{"x": 1}, {"x": 1, "x": 2}]}"#).as_deref(),
            Some("a[1].x")
        );
        // The same key in different objects is no duplicate.
        assert_eq!(
            first_duplicate(r#"{"u": {"input": "V"}, "input": "V"}"#),
            None
        );
    }
}
