//! The model file (`hsid-model/1`): round trip, keys, version, shape and type errors, and its
//! JSON Schema in `docs/`.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use hsid_host::io::{FileAction, FileError};
use hsid_host::model::Element;
use hsid_host::model_file::{
    FORMAT, FormatTag, ModelFile, ModelFileError, ModelStd, NoiseFile, Units,
};
use serde_json::{Value, json};

use crate::common;

use common::{Scratch, schema_errors};

fn scratch(test: &str) -> Scratch {
    Scratch::new(test)
}

fn model() -> ModelFile {
    ModelFile {
        format: FormatTag,
        nonlinearity: Some(Element::Switch),
        order: 2,
        a: vec![vec![1.8858, -0.9048], vec![1.0, 0.0]],
        b: vec![1.0, 0.0],
        c: vec![0.1994, -0.1804],
        d: 0.0,
        poles: vec![[0.9429, 0.1256], [0.9429, -0.1256]],
        mu0: -0.25,
        knots_asc: vec![-3.0, -2.0, -1.0, 0.0, 1.0, 2.0, 3.0],
        knots_desc: vec![-3.0, -2.0, -1.0, 0.0, 1.0, 2.0, 3.0],
        border_asc: vec![-1.0, -1.0, -0.5, 0.0, 0.5, 1.0, 1.0],
        border_desc: vec![-1.0, -1.0, -0.6, 0.1, 0.6, 1.0, 1.0],
        singular_values: vec![10.0, 5.0, 0.1, 0.01],
        u_min: -3.0,
        u_max: 3.0,
        sample_time: Some(0.01),
        units: Some(Units {
            input: "V".into(),
            output: "rad/s".into(),
        }),
        f: 10,
        p: 10,
        samples: 8000,
        noise: Some(NoiseFile {
            c: vec![1.0, 0.5],
            d: vec![1.0, -0.85],
            sigma2: 0.01,
        }),
        std: Some(ModelStd {
            poles: vec![[0.001, 0.002], [0.001, 0.002]],
            mu0: 0.03,
            border_asc: vec![0.03; 7],
            border_desc: vec![0.03; 7],
            mean_gap: Some(0.004),
        }),
        integrating: false,
        element: None,
        friction: None,
    }
}

#[test]
fn json_round_trip_and_keys() {
    let dir = scratch("json");
    let p = dir.join("model.json");
    let m = model();
    m.save(&p).unwrap();
    assert_eq!(ModelFile::load(&p).unwrap(), m);

    let value: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&p).unwrap()).unwrap();
    let mut keys: Vec<&str> = value
        .as_object()
        .unwrap()
        .keys()
        .map(|k| k.as_str())
        .collect();
    keys.sort_unstable();
    let mut expected = vec![
        "format",
        "order",
        "A",
        "B",
        "C",
        "D",
        "poles",
        "mu0",
        "knots_asc",
        "knots_desc",
        "border_asc",
        "border_desc",
        "singular_values",
        "u_min",
        "u_max",
        "nonlinearity",
        "f",
        "p",
        "samples",
        "sample_time",
        "units",
        "noise",
        "std",
    ];
    expected.sort_unstable();
    assert_eq!(keys, expected);
    assert_eq!(value["A"][0][1], serde_json::json!(-0.9048));
    assert_eq!(value["poles"][1], serde_json::json!([0.9429, -0.1256]));

    let unknown = ModelFile {
        nonlinearity: None,
        ..model()
    };
    unknown.save(&p).unwrap();
    assert_eq!(ModelFile::load(&p).unwrap().nonlinearity, None);
}

fn json_with(edit: impl FnOnce(&mut serde_json::Map<String, serde_json::Value>)) -> String {
    let mut v = serde_json::to_value(model()).unwrap();
    edit(v.as_object_mut().unwrap());
    serde_json::to_string(&v).unwrap()
}

fn field_of(err: &ModelFileError) -> &str {
    match err {
        ModelFileError::Invalid { field, .. } => field,
        other => panic!("expected InvalidModel, got {other:?}"),
    }
}

#[test]
fn json_shape_errors_name_the_field() {
    use serde_json::json;
    let cases: Vec<(&str, String)> = vec![
        (
            "A",
            json_with(|m| drop(m.insert("A".into(), json!([[1.0, 2.0]])))),
        ),
        (
            "A",
            json_with(|m| drop(m.insert("A".into(), json!([[1.0, 2.0], [3.0]])))),
        ),
        ("B", json_with(|m| drop(m.insert("B".into(), json!([1.0]))))),
        (
            "C",
            json_with(|m| drop(m.insert("C".into(), json!([1.0, 2.0, 3.0])))),
        ),
        (
            "poles",
            json_with(|m| drop(m.insert("poles".into(), json!([])))),
        ),
        (
            "border_asc",
            json_with(|m| drop(m.insert("border_asc".into(), json!([0.0, 1.0])))),
        ),
        (
            "border_desc",
            json_with(|m| drop(m.insert("knots_desc".into(), json!([0.0])))),
        ),
        (
            "u_max",
            json_with(|m| drop(m.insert("u_max".into(), json!(-4.0)))),
        ),
    ];
    for (field, text) in cases {
        let err = ModelFile::from_json_str("m.json", &text).unwrap_err();
        assert_eq!(field_of(&err), field, "{err}");
        assert!(
            err.to_string()
                .starts_with(&format!("m.json: field \"{field}\": ")),
            "{err}"
        );
    }
}

#[test]
fn json_type_errors_name_the_field() {
    use serde_json::json;
    let missing = json_with(|m| drop(m.remove("A")));
    let err = ModelFile::from_json_str("m.json", &missing).unwrap_err();
    assert!(matches!(err, ModelFileError::Json { .. }));
    assert!(err.to_string().contains("missing field `A`"), "{err}");

    let wrong = json_with(|m| drop(m.insert("A".into(), json!([[1.0, "x"], [0.0, 1.0]]))));
    let err = ModelFile::from_json_str("m.json", &wrong).unwrap_err();
    assert!(
        err.to_string().starts_with("m.json: field A[0][1]: "),
        "{err}"
    );

    let pole = json_with(|m| drop(m.insert("poles".into(), json!([[1.0], [0.0, 1.0]]))));
    let err = ModelFile::from_json_str("m.json", &pole).unwrap_err();
    assert!(err.to_string().contains("field poles[0]"), "{err}");

    let unknown = json_with(|m| drop(m.insert("a".into(), json!(1))));
    let err = ModelFile::from_json_str("m.json", &unknown).unwrap_err();
    assert!(err.to_string().contains("unknown field `a`"), "{err}");

    let err = ModelFile::from_json_str("m.json", "{\"format\": \"hsid-model/1\", \"order\": 2,")
        .unwrap_err();
    assert!(matches!(err, ModelFileError::Json { .. }), "{err:?}");
    let err = ModelFile::from_json_str("m.json", &format!("{} x", json_with(|_| ()))).unwrap_err();
    assert!(matches!(err, ModelFileError::Json { .. }), "{err:?}");
}

#[test]
fn json_non_finite_is_refused_on_save() {
    let dir = scratch("json-nan");
    let p = dir.join("nan.json");
    let mut m = model();
    m.border_desc[3] = f64::NAN;
    let err = m.save(&p).unwrap_err();
    assert_eq!(field_of(&err), "border_desc");
    assert!(!p.exists());
}

#[test]
fn json_load_missing_file() {
    let err = ModelFile::load("/nonexistent/model.json").unwrap_err();
    assert!(
        matches!(
            err,
            ModelFileError::File(FileError {
                action: FileAction::Read,
                ..
            })
        ),
        "{err:?}"
    );
}

#[test]
fn the_file_reads_back_to_the_same_bytes() {
    let text = model().to_json_string("m.json").unwrap();
    let back = ModelFile::from_json_str("m.json", &text).unwrap();
    assert_eq!(back.to_json_string("m.json").unwrap(), text);
    assert!(text.ends_with("}\n"));
    assert!(
        text.starts_with(&format!("{{\n  \"format\": \"{FORMAT}\",")),
        "{text}"
    );
}

#[test]
fn an_unversioned_file_names_the_version_expected() {
    let old = json_with(|m| drop(m.remove("format")));
    let err = ModelFile::from_json_str("old.json", &old).unwrap_err();
    assert!(
        matches!(err, ModelFileError::Version { found: None, .. }),
        "{err:?}"
    );
    let text = err.to_string();
    assert!(
        text.starts_with("old.json: no \"format\" key") && text.contains("\"hsid-model/1\""),
        "{text}"
    );
    // Checked before the fields: an old file with the old layout gets the same message.
    let older = r#"{"order": 1, "A": [[0.5]], "nonlinearity": "backlash"}"#;
    let err = ModelFile::from_json_str("old.json", older).unwrap_err();
    assert!(
        matches!(err, ModelFileError::Version { found: None, .. }),
        "{err:?}"
    );
}

#[test]
fn another_version_is_named() {
    let v2 = json_with(|m| drop(m.insert("format".into(), json!("hsid-model/2"))));
    let err = ModelFile::from_json_str("m.json", &v2).unwrap_err();
    match &err {
        ModelFileError::Version { found: Some(v), .. } => assert_eq!(v, "hsid-model/2"),
        other => panic!("{other:?}"),
    }
    assert!(
        err.to_string()
            .starts_with("m.json: model format \"hsid-model/2\", this hsid reads \"hsid-model/1\""),
        "{err}"
    );
    let number = json_with(|m| drop(m.insert("format".into(), json!(1))));
    let err = ModelFile::from_json_str("m.json", &number).unwrap_err();
    assert!(
        matches!(&err, ModelFileError::Version { found: Some(v), .. } if v == "1"),
        "{err:?}"
    );
}

#[test]
fn noise_and_std_are_checked() {
    let cases: Vec<(&str, String)> = vec![
        (
            "noise.c",
            json_with(|m| m["noise"]["c"] = json!([0.5, 1.0])),
        ),
        ("noise.d", json_with(|m| m["noise"]["d"] = json!([]))),
        (
            "noise.sigma2",
            json_with(|m| m["noise"]["sigma2"] = json!(-1.0)),
        ),
        (
            "std.poles",
            json_with(|m| m["std"]["poles"] = json!([[0.1, 0.1]])),
        ),
        (
            "std.border_desc",
            json_with(|m| m["std"]["border_desc"] = json!([0.1])),
        ),
        ("std", json_with(|m| m["std"]["mu0"] = json!(-0.1))),
        (
            "sample_time",
            json_with(|m| drop(m.insert("sample_time".into(), json!(0.0)))),
        ),
    ];
    for (field, text) in cases {
        let err = ModelFile::from_json_str("m.json", &text).unwrap_err();
        assert_eq!(field_of(&err), field, "{err}");
    }
    let none = json_with(|m| {
        for k in ["noise", "std", "units", "sample_time", "nonlinearity"] {
            m.insert(k.into(), Value::Null);
        }
    });
    let m = ModelFile::from_json_str("m.json", &none).unwrap();
    assert_eq!(
        (m.noise, m.std, m.units, m.sample_time, m.nonlinearity),
        (None, None, None, None, None)
    );
}

#[test]
fn the_schema_accepts_the_file_and_refuses_what_the_reader_refuses() {
    let good: Value = serde_json::from_str(&model().to_json_string("m.json").unwrap()).unwrap();
    assert_eq!(schema_errors(&good), Vec::<String>::new());
    let bad = [
        json_with(|m| drop(m.remove("format"))),
        json_with(|m| drop(m.insert("format".into(), json!("hsid-model/2")))),
        json_with(|m| drop(m.insert("extra".into(), json!(1)))),
        json_with(|m| drop(m.remove("A"))),
        json_with(|m| drop(m.insert("nonlinearity".into(), json!("relay")))),
        json_with(|m| m["noise"]["c"] = json!([0.5, 1.0])),
        json_with(|m| drop(m.insert("poles".into(), json!([[1.0], [0.0, 1.0]])))),
        json_with(|m| drop(m.insert("units".into(), json!({"input": "V"})))),
    ];
    for text in bad {
        let v: Value = serde_json::from_str(&text).unwrap();
        assert!(!schema_errors(&v).is_empty(), "the schema accepts {text}");
        assert!(ModelFile::from_json_str("m.json", &text).is_err(), "{text}");
    }
}

#[test]
fn an_empty_unit_name_is_refused_naming_the_field() {
    let text = json_with(|m| drop(m.insert("units".into(), json!({"input": "", "output": "deg"}))));
    let e = ModelFile::from_json_str("m.json", &text)
        .unwrap_err()
        .to_string();
    assert!(e.contains("units") && e.contains("empty unit name"), "{e}");
}
