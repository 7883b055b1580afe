//! End-to-end tests of the `hsid` command line: the built binary is run on files written to a
//! scratch folder, and its exit status, stdout, stderr and JSON output are checked.
//!
//! Every error case must exit non-zero with exactly one line on stderr that starts with
//! `hsid:` and names what was wrong, and never with a panic or a backtrace.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use hsid_host::io::write_columns;
use hsid_host::paper::{Case, Experiment, PaperConfig, experiment};
use serde_json::Value;

use crate::common;

use common::{Run, Scratch, hsid, identify, p};

/// Run 0 of the paper's backlash case at 10 dB SNR (j = 4000, hold 300), simulated once.
fn noisy() -> &'static Experiment {
    static E: OnceLock<Experiment> = OnceLock::new();
    E.get_or_init(|| experiment(Case::Backlash, &PaperConfig::default(), 0).unwrap())
}

/// The same experiment without noise.
fn clean() -> &'static Experiment {
    static E: OnceLock<Experiment> = OnceLock::new();
    E.get_or_init(|| {
        let cfg = PaperConfig {
            snr_db: f64::INFINITY,
            ..PaperConfig::default()
        };
        experiment(Case::Backlash, &cfg, 0).unwrap()
    })
}

/// The `fit … %` figure of a fit report line in `stdout`.
fn fit_percent(stdout: &str) -> f64 {
    let line = stdout
        .lines()
        .find(|l| l.starts_with("simulation fit on "))
        .unwrap_or_else(|| panic!("no fit line in:\n{stdout}"));
    let (_, tail) = line.rsplit_once("fit ").unwrap();
    tail.trim_end_matches('%')
        .trim()
        .parse()
        .unwrap_or_else(|e| panic!("cannot parse the fit in {line:?}: {e}"))
}

/// The poles of `G(q) = … / (1 − 1.8858 q⁻¹ + 0.9048 q⁻²)`, `(re, ±im)`.
fn true_pole() -> (f64, f64) {
    let (a1, a2) = (-1.8858_f64, 0.9048_f64);
    let re = -a1 / 2.0;
    let disc = a2 - re * re;
    assert!(disc > 0.0, "the true poles are complex");
    (re, disc.sqrt())
}

fn numbers(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap_or_else(|| panic!("not an array: {v}"))
        .iter()
        .map(|x| x.as_f64().unwrap_or_else(|| panic!("not a number: {x}")))
        .collect()
}

/// Reads a model file and checks its fields and that it is an order-2 model with poles within
/// 0.02 of the true ones.
fn check_model_json(path: &Path) -> Value {
    let text = std::fs::read_to_string(path).unwrap();
    let m: Value = serde_json::from_str(&text).unwrap();
    assert_eq!(m["format"], "hsid-model/1", "{text}");
    assert_eq!(m["nonlinearity"], "backlash", "{text}");
    for key in [
        "noise",
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
    ] {
        assert!(
            m.get(key).is_some(),
            "model JSON has no field {key:?}:\n{text}"
        );
    }
    assert_eq!(m["order"].as_u64(), Some(2), "{text}");
    let a = m["A"].as_array().unwrap();
    assert_eq!(a.len(), 2);
    for row in a {
        assert_eq!(numbers(row).len(), 2);
    }
    assert_eq!(numbers(&m["B"]).len(), 2);
    assert_eq!(numbers(&m["C"]).len(), 2);
    assert!(m["D"].as_f64().unwrap().is_finite());
    assert!(m["mu0"].as_f64().unwrap().is_finite());
    assert!(!numbers(&m["singular_values"]).is_empty());
    assert_eq!(
        numbers(&m["knots_asc"]).len(),
        numbers(&m["border_asc"]).len()
    );
    assert_eq!(
        numbers(&m["knots_desc"]).len(),
        numbers(&m["border_desc"]).len()
    );

    let (re, im) = true_pole();
    let poles: Vec<(f64, f64)> = m["poles"]
        .as_array()
        .unwrap()
        .iter()
        .map(|z| {
            let z = numbers(z);
            assert_eq!(z.len(), 2, "a pole is [re, im]");
            (z[0], z[1])
        })
        .collect();
    assert_eq!(poles.len(), 2);
    for sign in [1.0, -1.0] {
        let best = poles
            .iter()
            .map(|(r, i)| (r - re).hypot(i - sign * im))
            .fold(f64::INFINITY, f64::min);
        assert!(
            best < 0.02,
            "no pole within 0.02 of {re:.4} {:+.4}j: {poles:?}",
            sign * im
        );
    }
    m
}

// ---------------------------------------------------------------------------------------------
// excite
// ---------------------------------------------------------------------------------------------

fn excite(seed: &str) -> Run {
    hsid(&[
        "excite",
        "--umin",
        "-3",
        "--umax",
        "3",
        "--samples",
        "100",
        "--hold",
        "10",
        "--seed",
        seed,
    ])
    .success()
}

#[test]
fn excite_prints_the_table_one_pattern() {
    let run = excite("5");
    assert!(run.stderr.is_empty(), "stderr: {}", run.stderr);
    let mut lines = run.stdout.lines();
    assert_eq!(lines.next(), Some("u"));
    let u: Vec<f64> = lines.map(|l| l.parse().unwrap()).collect();
    assert_eq!(u.len(), 100);
    assert!(u[..10].iter().all(|&v| v == -3.0), "hold: {:?}", &u[..10]);
    for (k, &v) in u[10..].iter().enumerate() {
        match k % 4 {
            0 | 2 => assert!(v > -3.0 && v < 3.0, "sample {}: random level {v}", k + 10),
            1 => assert_eq!(v, 3.0, "sample {}", k + 10),
            _ => assert_eq!(v, -3.0, "sample {}", k + 10),
        }
    }
    // The random levels are not all the same.
    let levels: Vec<f64> = u[10..].iter().step_by(2).copied().collect();
    assert!(levels.windows(2).any(|w| w[0] != w[1]));
}

#[test]
fn excite_is_reproducible_per_seed() {
    let a = excite("5").stdout;
    let b = excite("5").stdout;
    let c = excite("6").stdout;
    assert_eq!(a, b, "same seed, same output");
    assert_ne!(a, c, "another seed, another output");
    // Only the random levels differ.
    for (i, (x, y)) in a.lines().zip(c.lines()).enumerate().skip(1) {
        let k = i - 1;
        if k < 10 || (k - 10) % 2 == 1 {
            assert_eq!(x, y, "sample {k} is not random");
        }
    }
}

#[test]
fn excite_rejects_an_empty_interval() {
    let run = hsid(&["excite", "--umin", "3", "--umax", "-3", "--samples", "10"]);
    run.clean_error(&["[3, -3]"]);
}

#[test]
fn excite_rejects_a_record_no_longer_than_its_hold() {
    // 100 samples under the default hold of 300 would be u_min throughout.
    let run = hsid(&["excite", "--umin", "-1", "--umax", "1", "--samples", "100"]);
    assert!(run.stdout.is_empty(), "{}", run.stdout);
    run.clean_error(&[
        "100 samples are no more than the hold of 300",
        "give more samples",
    ]);
    let run = hsid(&[
        "excite",
        "--umin",
        "-1",
        "--umax",
        "1",
        "--samples",
        "10",
        "--hold",
        "10",
    ]);
    run.clean_error(&["10 samples are no more than the hold of 10"]);
    let run = hsid(&[
        "excite",
        "--umin",
        "-1",
        "--umax",
        "1",
        "--samples",
        "11",
        "--hold",
        "10",
    ]);
    assert_eq!(run.success().stdout.lines().count(), 12);
}

// ---------------------------------------------------------------------------------------------
// identify / validate round trips
// ---------------------------------------------------------------------------------------------

#[test]
fn identify_and_validate_round_trip_on_noisy_data() {
    let dir = Scratch::new("round-trip-noisy");
    let e = noisy();
    assert_eq!(e.u.len(), 300 + 4000 + 10 + 10 - 1);
    let data = dir.write_uy("data.csv", &e.u, &e.y);
    let model = dir.join("model.json");

    let paper = ["--segments", "7", "--hold", "300", "--json", p(&model)];
    let run = identify(&data, &paper).success();
    assert!(run.stdout.contains("order n = 2"), "{}", run.stdout);
    assert!(run.stdout.contains("poles:"), "{}", run.stdout);
    assert!(run.stdout.contains(&format!("wrote {}", p(&model))));
    let fit_identify = fit_percent(&run.stdout);
    check_model_json(&model);

    let run = hsid(&[
        "validate",
        "--model",
        p(&model),
        "--data",
        p(&data),
        "--skip",
        "300",
    ])
    .success();
    let fit = fit_percent(&run.stdout);
    assert!(fit > 50.0, "fit {fit} % on the 10 dB data:\n{}", run.stdout);
    assert!(run.stdout.contains("on 4019 samples"), "{}", run.stdout);
    // The JSON round trip keeps the model: validate reproduces identify's figure.
    assert!(
        (fit - fit_identify).abs() < 0.02,
        "validate {fit} % vs identify {fit_identify} %"
    );
}

#[test]
fn identify_and_validate_round_trip_on_noise_free_data() {
    let dir = Scratch::new("round-trip-clean");
    let e = clean();
    assert_eq!(e.y, e.y_clean, "a non-finite SNR means no noise");
    let data = dir.write_uy("data.csv", &e.u, &e.y);
    let model = dir.join("model.json");

    let paper = ["--segments", "7", "--hold", "300", "--json", p(&model)];
    let run = identify(&data, &paper).success();
    assert!(run.stdout.contains("order n = 2"), "{}", run.stdout);
    check_model_json(&model);

    let run = hsid(&[
        "validate",
        "--model",
        p(&model),
        "--data",
        p(&data),
        "--skip",
        "300",
    ])
    .success();
    let fit = fit_percent(&run.stdout);
    assert!(
        fit > 80.0,
        "fit {fit} % on noise-free data:\n{}",
        run.stdout
    );
}

#[test]
fn identify_with_custom_non_uniform_knots() {
    let dir = Scratch::new("custom-knots");
    let e = noisy();
    let data = dir.write_uy("data.csv", &e.u, &e.y);
    let model = dir.join("model.json");
    identify(
        &data,
        &[
            "--knots-asc",
            "-3,-1,0,1,3",
            "--knots-desc",
            "-3,-2,0,2,3",
            "--json",
            p(&model),
        ],
    )
    .success();
    let m = check_model_json(&model);
    assert_eq!(numbers(&m["knots_asc"]), [-3.0, -1.0, 0.0, 1.0, 3.0]);
    assert_eq!(numbers(&m["knots_desc"]), [-3.0, -2.0, 0.0, 2.0, 3.0]);
    assert_eq!(numbers(&m["border_asc"]).len(), 5);
    assert_eq!(numbers(&m["border_desc"]).len(), 5);
    // Both borders start at mu0.
    let mu0 = m["mu0"].as_f64().unwrap();
    assert!((numbers(&m["border_asc"])[0] - mu0).abs() < 1e-9);
    assert!((numbers(&m["border_desc"])[0] - mu0).abs() < 1e-9);
}

#[test]
fn identify_reads_other_column_names() {
    let dir = Scratch::new("columns");
    let e = noisy();
    let path = dir.join("data.csv");
    // A time column `t` is read too (uniform, so it gives the sample time).
    let t: Vec<f64> = (0..e.u.len()).map(|k| 0.5 * k as f64).collect();
    write_columns(&path, &["t", "cmd", "meas"], &[&t, &e.u, &e.y]).unwrap();
    let run = identify(&path, &["--input-column", "cmd", "--output-column", "meas"]).success();
    assert!(run.stdout.contains("order n = 2"), "{}", run.stdout);
    assert!(run.stdout.contains("sample time 0.5 s"), "{}", run.stdout);
}

// ---------------------------------------------------------------------------------------------
// identify: bad data
// ---------------------------------------------------------------------------------------------

#[test]
fn identify_names_the_line_of_a_malformed_number() {
    let dir = Scratch::new("malformed");
    let data = dir.write("data.csv", "u,y\n-3,0.1\n-3,0.2\n-3,1.2.3\n-3,0.4\n");
    identify(&data, &[]).clean_error(&["data.csv", "line 4", "1.2.3", "\"y\""]);
}

#[test]
fn identify_names_the_columns_when_one_is_missing() {
    let dir = Scratch::new("missing-column");
    let data = dir.write("data.csv", "u,out\n-3,0.1\n-3,0.2\n");
    identify(&data, &[]).clean_error(&["data.csv", "\"y\"", "\"u\", \"out\""]);
}

#[test]
fn identify_rejects_an_empty_file() {
    let dir = Scratch::new("empty");
    let data = dir.write("data.csv", "");
    identify(&data, &[]).clean_error(&["data.csv", "empty"]);
}

#[test]
fn identify_rejects_a_header_only_file() {
    let dir = Scratch::new("header-only");
    let data = dir.write("data.csv", "u,y\n");
    identify(&data, &[]).clean_error(&["data.csv", "no data rows"]);
}

#[test]
fn identify_rejects_a_missing_file() {
    let dir = Scratch::new("no-file");
    let data = dir.join("absent.csv");
    identify(&data, &[]).clean_error(&["absent.csv", "cannot read"]);
}

#[test]
fn identify_names_the_line_of_a_nan() {
    let dir = Scratch::new("nan");
    let e = noisy();
    // Write the record, then replace y of data row 41 (file line 42) by NaN.
    let data = dir.write_uy("data.csv", &e.u, &e.y);
    let text = std::fs::read_to_string(&data).unwrap();
    let text: Vec<String> = text
        .lines()
        .enumerate()
        .map(|(i, l)| {
            if i + 1 == 42 {
                format!("{},NaN", l.split(',').next().unwrap())
            } else {
                l.to_string()
            }
        })
        .collect();
    std::fs::write(&data, text.join("\n") + "\n").unwrap();
    identify(&data, &[]).clean_error(&["data.csv", "line 42", "\"y\"", "NaN"]);
}

#[test]
fn identify_names_an_input_outside_the_interval() {
    let dir = Scratch::new("out-of-range");
    let e = noisy();
    let mut u = e.u.clone();
    u[498] = 3.5; // file line 500
    let data = dir.write_uy("data.csv", &u, &e.y);
    let line = identify(&data, &[]).clean_error(&["data.csv", "3.5", "outside"]);
    assert!(
        line.contains("sample 498") || line.contains("line 500"),
        "the message should locate the sample: {line}"
    );
}

#[test]
fn identify_rejects_unsorted_knots() {
    let dir = Scratch::new("unsorted-knots");
    let e = noisy();
    let data = dir.write_uy("data.csv", &e.u, &e.y);
    identify(&data, &["--knots-asc", "-3,1,0,3"]).clean_error(&["ascending", "increasing"]);
}

#[test]
fn identify_rejects_knots_not_ending_at_umax() {
    let dir = Scratch::new("knots-end");
    let e = noisy();
    let data = dir.write_uy("data.csv", &e.u, &e.y);
    identify(&data, &["--knots-desc", "-3,0,2.5"]).clean_error(&["--knots-desc", "--umax 3"]);
    identify(&data, &["--knots-asc", "-2,0,3"]).clean_error(&["--knots-asc", "--umin -3"]);
}

#[test]
fn identify_rejects_too_few_samples() {
    let dir = Scratch::new("too-few");
    let e = noisy();
    // 200 samples: shorter than the hold itself.
    let data = dir.write_uy("short.csv", &e.u[..200], &e.y[..200]);
    identify(&data, &[]).clean_error(&["short.csv", "200 samples", "inside the hold of 300"]);
    // 500 samples: 200 after the hold, 590 needed for f = p = 10 and the 14 segments given on
    // each path.
    let data = dir.write_uy("short2.csv", &e.u[..500], &e.y[..500]);
    let knots: Vec<String> = (0..=14)
        .map(|i| format!("{}", -3.0 + 6.0 * i as f64 / 14.0))
        .collect();
    let knots = knots.join(",");
    identify(&data, &["--knots-asc", &knots, "--knots-desc", &knots]).clean_error(&[
        "short2.csv",
        "200 samples after the hold",
        "590 needed",
    ]);
    // By default the segments the few samples do not support are merged: fewer channels, a
    // model, and a line that says so.
    let run = identify(&data, &[]).success();
    assert!(
        run.stdout
            .lines()
            .any(|l| l.starts_with("knots from the data")),
        "{}",
        run.stdout
    );
}

#[test]
fn identify_rejects_a_constant_input() {
    let dir = Scratch::new("constant");
    let u = vec![-3.0; 1000];
    let y = vec![0.5; 1000];
    let data = dir.write_uy("data.csv", &u, &y);
    identify(&data, &[]).clean_error(&["data.csv", "never excited"]);
}

#[test]
fn identify_rejects_an_order_above_the_horizon() {
    let dir = Scratch::new("order");
    let e = noisy();
    let data = dir.write_uy("data.csv", &e.u, &e.y);
    identify(&data, &["--order", "12"]).clean_error(&["order 12", "f = 10"]);
}

#[test]
fn identify_rejects_a_hold_too_short_to_settle() {
    let dir = Scratch::new("hold");
    let e = noisy();
    let data = dir.write_uy("data.csv", &e.u, &e.y);
    identify(&data, &["--hold", "10", "--settle", "10"]).clean_error(&["hold of 10", "10 skipped"]);
}

#[test]
fn identify_rejects_a_hold_longer_than_the_recorded_one() {
    let dir = Scratch::new("long-hold");
    let e = noisy();
    let data = dir.write_uy("data.csv", &e.u, &e.y);
    // The data hold u_min for 300 samples; sample 300 (CSV line 302) is the first excitation
    // sample.
    identify(&data, &["--hold", "400"]).clean_error(&["line 302", "hold"]);
}

#[test]
fn identify_rejects_bad_horizons() {
    let dir = Scratch::new("horizons");
    let e = noisy();
    let data = dir.write_uy("data.csv", &e.u, &e.y);
    identify(&data, &["--f", "1"]).clean_error(&["f = 1"]);
    identify(&data, &["--f", "90", "--p", "10"]).clean_error(&["f + p = 100", "f + p <= 96"]);
    identify(&data, &["--p", "0"]).clean_error(&["p >= 1"]);
    // Too few instrument rows (p·m = 2 < f = 3): the settings are named, not the data file.
    let line = identify(&data, &["--segments", "1", "--f", "3", "--p", "1"])
        .clean_error(&["settings:", "instrument"]);
    assert!(!line.contains("data.csv"), "{line}");
}

#[test]
fn identify_rejects_too_many_segments() {
    let dir = Scratch::new("segments");
    let e = noisy();
    let data = dir.write_uy("data.csv", &e.u, &e.y);
    // --quiet: on a loaded machine the run passes the 1-second mark and would print progress
    // lines besides the one error line checked.
    identify(&data, &["--segments", "40", "--quiet"])
        .clean_error(&["80 channels", "at most 64 channels"]);
}

// ---------------------------------------------------------------------------------------------
// validate: bad models and data
// ---------------------------------------------------------------------------------------------

/// Identifies the noisy experiment once into `dir` and returns `(data, model JSON text)`.
fn identified(dir: &Scratch) -> (PathBuf, String) {
    let e = noisy();
    let data = dir.write_uy("data.csv", &e.u, &e.y);
    let model = dir.join("model.json");
    identify(&data, &["--json", p(&model)]).success();
    (data, std::fs::read_to_string(&model).unwrap())
}

/// The model JSON text with `edit` applied to its object.
fn edit_model(text: &str, edit: impl FnOnce(&mut serde_json::Map<String, Value>)) -> String {
    let mut v: Value = serde_json::from_str(text).unwrap();
    edit(v.as_object_mut().unwrap());
    serde_json::to_string_pretty(&v).unwrap()
}

fn validate(model: &Path, data: &Path) -> Run {
    hsid(&[
        "validate",
        "--model",
        p(model),
        "--data",
        p(data),
        "--skip",
        "300",
    ])
}

#[test]
fn validate_names_a_missing_model_field() {
    let dir = Scratch::new("validate-missing-field");
    let (data, text) = identified(&dir);
    let bad = dir.write(
        "bad.json",
        &edit_model(&text, |m| {
            m.remove("border_desc");
        }),
    );
    validate(&bad, &data).clean_error(&["bad.json", "border_desc"]);
}

#[test]
fn validate_rejects_inconsistent_or_malformed_models() {
    let dir = Scratch::new("validate-bad-model");
    let (data, text) = identified(&dir);

    let bad = dir.write(
        "order.json",
        &edit_model(&text, |m| {
            m.insert("order".into(), Value::from(3));
        }),
    );
    validate(&bad, &data).clean_error(&["order.json", "\"A\""]);

    let bad = dir.write(
        "type.json",
        &edit_model(&text, |m| {
            m.insert("D".into(), Value::from("zero"));
        }),
    );
    validate(&bad, &data).clean_error(&["type.json", "field D"]);

    let bad = dir.write("truncated.json", &text[..text.len() / 2]);
    validate(&bad, &data).clean_error(&["truncated.json"]);

    validate(&dir.join("absent.json"), &data).clean_error(&["absent.json", "cannot read"]);
}

#[test]
fn validate_names_an_input_outside_the_model_interval() {
    let dir = Scratch::new("validate-range");
    let (_, text) = identified(&dir);
    let model = dir.write("model.json", &text);
    let e = noisy();
    let mut u = e.u.clone();
    u[998] = -4.0; // file line 1000
    let data = dir.write_uy("other.csv", &u, &e.y);
    let strict = hsid(&[
        "validate",
        "--model",
        p(&model),
        "--data",
        p(&data),
        "--skip",
        "300",
        "--strict-interval",
    ]);
    strict.clean_error(&["other.csv", "line 1000", "-4", "interval"]);
    // By default the borders are extended beyond the interval, and a line says so.
    let run = validate(&model, &data).success();
    let note = run
        .stdout
        .lines()
        .find(|l| l.starts_with("note: "))
        .unwrap_or_else(|| panic!("no note:\n{}", run.stdout));
    assert!(
        note.starts_with(&format!("note: 1 of {} samples", u.len()))
            && note.contains("lies outside the model's interval")
            && note.contains("lowest -4,")
            && note.ends_with("(--strict-interval refuses instead)"),
        "{note}"
    );
    assert!(run.stdout.contains("fit "), "{}", run.stdout);
}

#[test]
fn validate_rejects_a_skip_beyond_the_data() {
    let dir = Scratch::new("validate-skip");
    let (data, text) = identified(&dir);
    let model = dir.write("model.json", &text);
    let run = hsid(&[
        "validate",
        "--model",
        p(&model),
        "--data",
        p(&data),
        "--skip",
        "5000",
    ]);
    run.clean_error(&["--skip 5000", "4319"]);
}

// ---------------------------------------------------------------------------------------------
// Regression tests for problems found and fixed
// ---------------------------------------------------------------------------------------------

#[test]
fn validate_rejects_a_model_without_knots() {
    let dir = Scratch::new("validate-no-knots");
    let (data, text) = identified(&dir);
    let bad = dir.write(
        "bad.json",
        &edit_model(&text, |m| {
            m.insert("knots_asc".into(), Value::Array(Vec::new()));
            m.insert("border_asc".into(), Value::Array(Vec::new()));
        }),
    );
    validate(&bad, &data).clean_error(&["bad.json", "knots_asc"]);
}

#[test]
fn validate_rejects_a_model_with_unsorted_knots() {
    let dir = Scratch::new("validate-unsorted-knots");
    let (data, text) = identified(&dir);
    let bad = dir.write(
        "bad.json",
        &edit_model(&text, |m| {
            let k = [3.0, -3.0, 0.0, 1.0, 2.0, 2.5, 2.6, 2.7];
            m.insert("knots_asc".into(), Value::from(k.to_vec()));
        }),
    );
    validate(&bad, &data).clean_error(&["bad.json", "knots_asc"]);
}

#[test]
fn validate_names_the_version_of_an_old_model_file() {
    let dir = Scratch::new("validate-old-format");
    let (data, text) = identified(&dir);
    let old = dir.write(
        "old.json",
        &edit_model(&text, |m| {
            m.remove("format");
        }),
    );
    validate(&old, &data).clean_error(&["old.json", "no \"format\" key", "hsid-model/1"]);
    let newer = dir.write(
        "newer.json",
        &edit_model(&text, |m| {
            m.insert("format".into(), Value::from("hsid-model/2"));
        }),
    );
    validate(&newer, &data).clean_error(&["newer.json", "hsid-model/2", "hsid-model/1"]);
}

/// The record as text with `delimiter` between the fields and comment lines at the top and
/// after the 100th row.
fn delimited(u: &[f64], y: &[f64], delimiter: &str) -> String {
    let mut s = format!("# a comment\n# another\nu{delimiter}y\n");
    for (i, (u, y)) in u.iter().zip(y).enumerate() {
        if i == 100 {
            s.push_str("# half-way note\n");
        }
        s.push_str(&format!("{u}{delimiter}{y}\n"));
    }
    s
}

#[test]
fn identify_reads_semicolons_tabs_and_comments_to_the_same_model() {
    let dir = Scratch::new("delimiters");
    let e = noisy();
    let plain = dir.write_uy("plain.csv", &e.u, &e.y);
    let reference = identify(&plain, &[]).success().stdout;
    let fit = |out: &str| {
        out.lines()
            .filter(|l| l.contains("fit"))
            .map(str::to_string)
            .collect::<Vec<_>>()
    };
    for (name, delimiter, extra) in [
        ("semi.csv", ";", None),
        ("tab.tsv", "\t", None),
        ("tab-given.tsv", "\t", Some("tab")),
    ] {
        let path = dir.write(name, &delimited(&e.u, &e.y, delimiter));
        let mut args = vec![];
        if let Some(d) = extra {
            args.extend(["--delimiter", d]);
        }
        let out = identify(&path, &args).success().stdout;
        assert_eq!(fit(&out), fit(&reference), "{name}");
    }
    // A comment line shifts the lines of the errors: row 150 sits on line 154.
    let mut text = delimited(&e.u, &e.y, ";");
    let row = text.lines().nth(153).unwrap().to_string();
    text = text.replacen(&row, "0.5;1.2.3", 1);
    let bad = dir.write("bad.csv", &text);
    identify(&bad, &[]).clean_error(&["bad.csv line 154", "\"1.2.3\" is not a number"]);
    // Told the wrong delimiter: the header has no column "u".
    let semi = dir.write("semi2.csv", &delimited(&e.u, &e.y, ";"));
    identify(&semi, &["--delimiter", "comma"])
        .clean_error(&["semi2.csv line 3", "no column \"u\""]);
}

#[test]
fn identify_rejects_order_zero_clearly() {
    let dir = Scratch::new("order-zero");
    let e = noisy();
    let data = dir.write_uy("data.csv", &e.u, &e.y);
    let line = identify(&data, &["--order", "0"]).clean_error(&["order 0"]);
    assert!(!line.contains("f > 0"), "{line}");
}

#[test]
fn identify_rejects_zero_segments_clearly() {
    let dir = Scratch::new("segments-zero");
    let e = noisy();
    let data = dir.write_uy("data.csv", &e.u, &e.y);
    identify(&data, &["--segments", "0"]).clean_error(&["--segments"]);
}
