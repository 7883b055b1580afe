//! `hsid diagnose --reference-column NAME`: the closed-loop estimate from a CSV's reference
//! column, the estimator in the report and the JSON, and the errors of a bad column or flag.

#![allow(clippy::unwrap_used)]

use crate::common;

use hsid_host::closed_loop::{ServoSpec, simulate_servo};
use hsid_host::diagnose::{DiagnoseOptions, Validation, diagnose};
use hsid_host::identify::{HostModel, IdentifyOptions};
use hsid_host::model::{Element, Record};
use hsid_host::model_file::ModelFile;
use serde_json::Value;

/// The pole with the largest imaginary part.
fn upper_pole(m: &HostModel) -> (f64, f64) {
    m.poles().into_iter().fold(
        (f64::NAN, f64::NEG_INFINITY),
        |a, p| if p.1 > a.1 { p } else { a },
    )
}

const FIXED: [&str; 12] = [
    "--umin",
    "-3",
    "--umax",
    "3",
    "--segments",
    "6",
    "--hold",
    "100",
    "--order",
    "2",
    "--max-steps",
    "1",
];

#[test]
#[ignore = "slow tier, run by scripts/slow-checks.sh: a whole diagnosis of a closed-loop servo through the command line, about 60 s"]
fn hsid_diagnose_takes_the_reference_column() {
    let spec = ServoSpec::paper();
    let s = simulate_servo(&spec, 5).unwrap();
    let dir = common::Scratch::new("diagnose-reference-column");
    let data = dir.join("servo.csv");
    hsid_host::io::write_columns(&data, &["u", "y", "r"], &[&s.u, &s.y, &s.r]).unwrap();
    let json = dir.join("diagnosis.json");
    let mut args = vec!["diagnose", "--data", common::p(&data)];
    args.extend(FIXED);
    args.extend(["--reference-column", "r", "--json", common::p(&json)]);
    let run = common::hsid(&args).success();
    eprintln!("{}", run.stdout);
    assert!(
        run.stdout.contains(
            "estimator: closed-loop subspace (PI-MOESP on instruments from the reference)"
        )
    );
    let report: Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(report["estimator"], "reference");
    // The base model written is the library's diagnosis of the same record and reference.
    let file: ModelFile = serde_json::from_value(report["model_before"]["model"].clone()).unwrap();
    let mut id = IdentifyOptions::uniform(-3.0, 3.0, 6, 100);
    id.order = Some(2);
    let mut opts = DiagnoseOptions::new(id, Element::Backlash);
    opts.max_steps = 1;
    let record = Record::new(s.u.clone(), s.y.clone())
        .unwrap()
        .with_reference(s.r.clone())
        .unwrap();
    let lib = diagnose(&record, &Validation::Split(0.7), &opts).unwrap();
    let (cli, lib) = (
        upper_pole(&HostModel::from_json(&file)),
        upper_pole(&lib.base.hammerstein),
    );
    eprintln!("base model's upper pole: hsid {cli:?}, library {lib:?}");
    assert!((cli.0 - lib.0).abs() < 1e-6 && (cli.1 - lib.1).abs() < 1e-6);
    // Without the column the report names the open-loop estimator.
    let mut args = vec!["diagnose", "--data", common::p(&data)];
    args.extend(FIXED);
    let run = common::hsid(&args).success();
    assert!(
        run.stdout
            .contains("estimator: open-loop subspace (PI-MOESP)")
    );
}

#[test]
fn hsid_diagnose_refuses_a_bad_reference_column() {
    let spec = ServoSpec::paper();
    let s = simulate_servo(&spec, 6).unwrap();
    let dir = common::Scratch::new("diagnose-reference-errors");
    let data = dir.join("servo.csv");
    hsid_host::io::write_columns(&data, &["u", "y", "r"], &[&s.u, &s.y, &s.r]).unwrap();
    let run = |extra: &[&str]| {
        let mut args = vec!["diagnose", "--data", common::p(&data)];
        args.extend(FIXED);
        args.extend(extra);
        common::hsid(&args)
    };
    // An unknown column names the columns there are.
    run(&["--reference-column", "setpoint"])
        .clean_error(&["no column \"setpoint\"", "\"u\", \"y\", \"r\""]);
    run(&["--reference-column", "r", "--nonlinearity", "static"])
        .clean_error(&["--reference-column r", "drop --nonlinearity static"]);
    run(&["--reference-column", "r", "--integrating"])
        .clean_error(&["--reference-column r", "--integrating"]);
    // A constant reference column.
    let flat = vec![1.0; s.u.len()];
    hsid_host::io::write_columns(&data, &["u", "y", "r"], &[&s.u, &s.y, &flat]).unwrap();
    run(&["--reference-column", "r"]).clean_error(&["the reference is constant"]);
}
