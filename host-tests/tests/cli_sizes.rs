//! Desktop sizes on the command line: `hsid identify` at horizons and knot counts far beyond
//! the firmware's, on a long enough record, and the typed errors where the data or the
//! largest capacity compiled in are the limit.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use hsid_host::paper::{Case, PaperConfig, experiment};
use serde_json::Value;

use crate::common;

use common::{Scratch, identify, p};

/// The paper's backlash case at 10 dB SNR with 20 segments per path and `f = p = 30`:
/// `j = 6000` Hankel columns after the hold of 300 samples.
fn long_record() -> hsid_host::paper::Experiment {
    let cfg = PaperConfig {
        f: 30,
        p: 30,
        segments: 20,
        j: 6000,
        ..PaperConfig::default()
    };
    experiment(Case::Backlash, &cfg, 0).unwrap()
}

/// The upper pole of `G(q) = … / (1 − 1.8858 q⁻¹ + 0.9048 q⁻²)`.
fn true_pole() -> (f64, f64) {
    let re = 1.8858_f64 / 2.0;
    (re, (0.9048 - re * re).sqrt())
}

#[test]
fn identify_at_f30_p30_with_20_segments_per_path() {
    let dir = Scratch::new("sizes-f30");
    let e = long_record();
    let data = dir.write_uy("data.csv", &e.u, &e.y);
    let model = dir.join("model.json");
    let args = [
        "--segments",
        "20",
        "--f",
        "30",
        "--p",
        "30",
        "--hold",
        "300",
        "--json",
        p(&model),
    ];
    let run = identify(&data, &args).success();
    assert!(
        run.stdout.contains("order n = 2 (f = 30, p = 30"),
        "{}",
        run.stdout
    );
    let json: Value = serde_json::from_str(&std::fs::read_to_string(&model).unwrap()).unwrap();
    assert_eq!(json["f"], 30);
    assert_eq!(json["p"], 30);
    assert_eq!(json["singular_values"].as_array().unwrap().len(), 30);
    assert_eq!(json["knots_asc"].as_array().unwrap().len(), 21);
    let (re, im) = true_pole();
    let poles = json["poles"].as_array().unwrap();
    let upper = poles
        .iter()
        .map(|v| (v[0].as_f64().unwrap(), v[1].as_f64().unwrap()))
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .unwrap();
    let err = ((upper.0 - re).powi(2) + (upper.1 - im).powi(2)).sqrt();
    assert!(err < 0.02, "pole {upper:?}, true ({re}, {im}): error {err}");
}

/// Within the capacities the data are the limit: the first 2500 samples of the record are
/// too few Hankel columns for 40 channels at `f = p = 30` (typed, with the count needed);
/// beyond the largest capacity the error names it.
#[test]
fn sizes_beyond_the_data_or_the_capacity_are_typed_errors() {
    let dir = Scratch::new("sizes-limits");
    let e = long_record();
    let short = dir.write_uy("short.csv", &e.u[..2500], &e.y[..2500]);
    let args = [
        "--segments",
        "20",
        "--f",
        "30",
        "--p",
        "30",
        "--hold",
        "300",
    ];
    identify(&short, &args).clean_error(&["samples"]);
    let args = ["--segments", "7", "--f", "50", "--p", "47", "--hold", "300"];
    identify(&short, &args).clean_error(&["f + p = 97", "f + p <= 96"]);
    // 33 segments per path given as knots (kept as given): beyond the capacity.
    let knots: Vec<String> = (0..=33)
        .map(|i| format!("{}", -3.0 + 6.0 * i as f64 / 33.0))
        .collect();
    let knots = knots.join(",");
    let args = [
        "--knots-asc",
        &knots,
        "--knots-desc",
        &knots,
        "--hold",
        "300",
    ];
    identify(&short, &args).clean_error(&["channels", "at most 64 channels"]);
    // As a count, the segments the record does not support are merged first: within it here.
    let args = ["--segments", "33", "--hold", "300"];
    let run = identify(&short, &args).success();
    assert!(run.stdout.contains("knots from the data"), "{}", run.stdout);
}
