//! The MATLAB recipe (docs/matlab.md) reads only fields the model format has: every
//! `m.FIELD` and `r.model.FIELD` it uses is a property of docs/model-format.schema.json.

#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::collections::BTreeSet;

/// The names after `prefix` in `text`: `m.A` → `A`.
fn fields_after(text: &str, prefix: &str) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    for (at, _) in text.match_indices(prefix) {
        let before = text[..at].chars().next_back();
        if before.is_some_and(|c| c.is_alphanumeric() || c == '_' || c == '.') {
            continue;
        }
        let rest = &text[at + prefix.len()..];
        let name: String = rest
            .chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_')
            .collect();
        if !name.is_empty() && name != "model" {
            out.insert(name);
        }
    }
    out
}

/// The MATLAB code blocks of the recipe.
fn matlab_code(doc: &str) -> String {
    doc.split("```matlab")
        .skip(1)
        .filter_map(|b| b.split("```").next())
        .collect::<Vec<_>>()
        .join("\n")
}

#[test]
fn every_field_the_recipe_reads_is_in_the_schema() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let doc = std::fs::read_to_string(root.join("docs/matlab.md")).unwrap();
    let schema: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(root.join("docs/model-format.schema.json")).unwrap(),
    )
    .unwrap();
    let props = schema["properties"].as_object().unwrap();
    let code = matlab_code(&doc);
    let mut used = fields_after(&code, "m.");
    used.extend(fields_after(&code, "r.model."));
    for name in [
        "A",
        "B",
        "C",
        "D",
        "sample_time",
        "knots_asc",
        "border_asc",
        "knots_desc",
    ] {
        assert!(
            used.contains(name),
            "the recipe no longer reads {name}: {used:?}"
        );
    }
    let missing: Vec<&String> = used.iter().filter(|n| !props.contains_key(*n)).collect();
    assert!(missing.is_empty(), "fields not in the schema: {missing:?}");
}

#[test]
fn a_misspelt_field_is_found() {
    let code = matlab_code("```matlab\nx = m.knots_up; y = r.model.Bee; z = mm.A;\n```");
    let mut used = fields_after(&code, "m.");
    used.extend(fields_after(&code, "r.model."));
    assert_eq!(
        used,
        BTreeSet::from(["Bee".to_string(), "knots_up".to_string()])
    );
}
