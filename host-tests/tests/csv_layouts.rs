//! CSV files as loggers write them, through the built binary: the bundled servo record
//! (`examples/data/servo.csv`, ts = 0.01 s, u in V, y in deg) rewritten with a `t_ms` time
//! column, `time [ms]`, a jittery clock, units in the column names, decimal commas with `;`,
//! and a hold logged with a little noise. Each must give the model of the clean file (the
//! same samples: the same model file, up to its sample time and units), with the sample
//! time and units read from the layout; each way it can go wrong is a one-line error naming
//! the option that fixes it.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::path::{Path, PathBuf};

use serde_json::Value;

use crate::common;

use common::{Scratch, hsid, p, servo};

/// The servo record's rows as written (`u` and `y` text, so every layout holds the same
/// numbers bit for bit).
fn rows() -> Vec<(String, String)> {
    std::fs::read_to_string(servo())
        .unwrap()
        .lines()
        .filter(|l| !l.starts_with('#') && !l.starts_with('u'))
        .map(|l| {
            let (u, y) = l.split_once(',').unwrap();
            (u.to_string(), y.to_string())
        })
        .collect()
}

/// Writes `header` and one line per row made by `line(k, u, y)`.
fn layout(
    s: &Scratch,
    name: &str,
    header: &str,
    line: &dyn Fn(usize, &str, &str) -> String,
) -> PathBuf {
    let mut text = format!("{header}\n");
    for (k, (u, y)) in rows().iter().enumerate() {
        text.push_str(&line(k, u, y));
        text.push('\n');
    }
    s.write(name, &text)
}

/// `hsid identify` of the servo record's settings on `data`, the paper's estimator (fast,
/// and the same model from the same samples), writing the model file `json`.
fn identify(data: &Path, json: &Path, extra: &[&str]) -> common::Run {
    let mut args = vec![
        "identify",
        "--data",
        p(data),
        "--umin",
        "-1",
        "--umax",
        "1",
        "--no-refine",
        "--segments",
        "7",
        "--f",
        "10",
        "--p",
        "10",
        "--quiet",
        "--json",
        p(json),
    ];
    args.extend_from_slice(extra);
    hsid(&args)
}

fn load(path: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

fn numbers(v: &Value) -> Vec<f64> {
    let mut out = Vec::new();
    match v {
        Value::Number(n) => out.push(n.as_f64().unwrap()),
        Value::Array(a) => a.iter().for_each(|x| out.extend(numbers(x))),
        _ => {}
    }
    out
}

/// The model of the clean servo record (its header comments give ts and units).
fn clean_model(s: &Scratch) -> Value {
    let json = s.join("clean.json");
    identify(&servo(), &json, &[]).success();
    load(&json)
}

/// Asserts that `m` is the model of `clean`: the same poles, μ0 and borders within `tol`.
fn same_model(m: &Value, clean: &Value, tol: f64) {
    for key in ["poles", "mu0", "border_asc", "border_desc", "A", "C"] {
        let (a, b) = (numbers(&m[key]), numbers(&clean[key]));
        assert_eq!(a.len(), b.len(), "{key}");
        assert!(!a.is_empty(), "{key}");
        for (x, y) in a.iter().zip(&b) {
            assert!((x - y).abs() <= tol, "{key}: {x} vs {y}");
        }
    }
}

fn units(m: &Value) -> (String, String) {
    (
        m["units"]["input"].as_str().unwrap_or("-").to_string(),
        m["units"]["output"].as_str().unwrap_or("-").to_string(),
    )
}

#[test]
fn a_time_column_in_milliseconds_gives_the_sample_time_in_seconds() {
    let s = Scratch::new("csv-t-ms");
    let clean = clean_model(&s);
    assert_eq!(clean["sample_time"].as_f64(), Some(0.01));
    let cases: [(&str, &str, f64, &[&str]); 5] = [
        ("t_ms", "t_ms,u,y", 10.0, &[]),
        ("time-ms", "time [ms],u,y", 10.0, &[]),
        ("t-us", "t_us,u,y", 10_000.0, &[]),
        ("time-s", "time (s),u,y", 0.01, &[]),
        // --time-unit wins over the name (a plain `t` holding milliseconds).
        ("flag", "t,u,y", 10.0, &["--time-unit", "ms"]),
    ];
    for (name, header, step, extra) in cases {
        let data = layout(&s, &format!("{name}.csv"), header, &|k, u, y| {
            format!("{},{u},{y}", step * k as f64)
        });
        let json = s.join(&format!("{name}.json"));
        let mut args = vec!["--input-unit", "V", "--output-unit", "deg"];
        args.extend_from_slice(extra);
        let run = identify(&data, &json, &args).success();
        assert!(
            run.stdout.contains("sample time 0.01 s (100 Hz)"),
            "{name}: {}",
            run.stdout
        );
        let m = load(&json);
        let ts = m["sample_time"].as_f64().unwrap();
        assert!((ts - 0.01).abs() < 1e-12, "{name}: ts {ts}");
        same_model(&m, &clean, 1e-12);
    }
    // Read as seconds, the t_ms column would be a sample time of 10 s: --time-unit s says so.
    let data = s.join("t_ms.csv");
    let run = identify(&data, &s.join("s.json"), &["--time-unit", "s"]).success();
    assert!(run.stdout.contains("sample time 10 s"), "{}", run.stdout);
    // A unit that is not one of time read is refused, naming the options.
    let min = layout(&s, "min.csv", "time [min],u,y", &|k, u, y| {
        format!("{k},{u},{y}")
    });
    identify(&min, &s.join("min.json"), &[]).clean_error(&[
        "the time column \"time [min]\" is in \"min\"",
        "--time-unit s|ms|us",
        "--ts",
    ]);
    // Two columns that read as time are refused rather than one picked.
    let two = layout(&s, "two.csv", "t,t_ms,u,y", &|k, u, y| {
        format!("{},{},{u},{y}", 0.01 * k as f64, 10 * k)
    });
    identify(&two, &s.join("two.json"), &[])
        .clean_error(&["\"t\" and \"t_ms\" both read as time", "--time-column"]);
}

#[test]
fn a_jittery_time_column_is_refused_and_ignored_with_ts() {
    let s = Scratch::new("csv-jitter");
    let clean = clean_model(&s);
    // A logger's clock at 100 Hz, ±0.5 ms around the ideal instant (a fixed pseudo-random
    // pattern): steps of 9–11 ms.
    let jitter = |k: usize| (k * 7919 % 1001) as f64 / 1000.0 - 0.5;
    let data = layout(&s, "jitter.csv", "time [ms],u [V],y [deg]", &|k, u, y| {
        format!("{:.3},{u},{y}", 10.0 * k as f64 + jitter(k))
    });
    let json = s.join("m.json");
    identify(&data, &json, &[]).clean_error(&[
        "jitter.csv line 3",
        "differs from the mean step",
        "give --ts to ignore the time column",
    ]);
    let run = identify(&data, &json, &["--ts", "0.01"]).success();
    let lines: Vec<&str> = run.stderr.lines().collect();
    assert_eq!(lines.len(), 1, "{}", run.stderr);
    assert!(
        lines[0].starts_with(&format!(
            "hsid: note: --ts 0.01 s is used; the time column \"time [ms]\" of {} is not \
             (mean step 10.0 ms, steps within ±",
            p(&data)
        )) && lines[0].ends_with("read in ms)"),
        "{}",
        lines[0]
    );
    // The largest deviation of the pattern is within 0.5 ms of the step either way: 0.9–1.0 ms.
    let within: f64 = lines[0]
        .split("within ±")
        .nth(1)
        .and_then(|r| r.split_whitespace().next())
        .unwrap()
        .parse()
        .unwrap();
    let unit = lines[0]
        .split("within ±")
        .nth(1)
        .unwrap()
        .split_whitespace()
        .nth(1)
        .unwrap();
    let ms = if unit == "µs" {
        within / 1000.0
    } else {
        within
    };
    assert!((0.9..=1.01).contains(&ms), "{}", lines[0]);
    let m = load(&json);
    assert_eq!(m["sample_time"].as_f64(), Some(0.01));
    assert_eq!(units(&m), ("V".into(), "deg".into()));
    same_model(&m, &clean, 1e-12);
}

#[test]
fn units_in_the_column_names_reach_the_model_file_and_the_reports() {
    let s = Scratch::new("csv-units");
    let clean = clean_model(&s);
    let data = layout(&s, "units.csv", "t,u [V],y [mm]", &|k, u, y| {
        format!("{},{u},{y}", 0.01 * k as f64)
    });
    let json = s.join("m.json");
    let run = identify(&data, &json, &[]).success();
    assert!(
        run.stdout.contains(" mm per V") && !run.stdout.contains("deg"),
        "{}",
        run.stdout
    );
    let m = load(&json);
    assert_eq!(units(&m), ("V".into(), "mm".into()));
    same_model(&m, &clean, 1e-12);
    // validate reads the same columns by their names, and its JSON carries the units.
    let report = s.join("v.json");
    hsid(&[
        "validate",
        "--model",
        p(&json),
        "--data",
        p(&data),
        "--json",
        p(&report),
    ])
    .success();
    let v = load(&report);
    assert_eq!(v["units"]["input"], "V");
    assert_eq!(v["units"]["output"], "mm");
    assert_eq!(v["reading"]["units"]["output"], "mm");
    // The flags must agree with the column names.
    identify(&data, &json, &["--input-unit", "V", "--output-unit", "deg"]).clean_error(&[
        "--input-unit/--output-unit give u in V and y in deg",
        "the column names of",
        "y in mm",
    ]);
    // One unit without the other is refused, naming the column to complete.
    let half = layout(&s, "half.csv", "u [V],y", &|_, u, y| format!("{u},{y}"));
    identify(&half, &json, &[]).clean_error(&[
        "the header states a unit for \"u\" but none for \"y\"",
        "`y [unit]`",
    ]);
    // The column asked for by its full name still states its unit.
    let run = identify(
        &data,
        &s.join("full.json"),
        &["--input-column", "u [V]", "--output-column", "y [mm]"],
    )
    .success();
    assert!(run.stdout.contains("mm per V"), "{}", run.stdout);
}

#[test]
fn decimal_commas_with_semicolons_read_as_the_clean_file() {
    let s = Scratch::new("csv-comma");
    let clean = clean_model(&s);
    let data = layout(&s, "comma.csv", "t;u [V];y [deg]", &|k, u, y| {
        format!("{:.2};{u};{y}", 0.01 * k as f64).replace('.', ",")
    });
    let json = s.join("m.json");
    identify(&data, &json, &[]).clean_error(&[
        "comma.csv line 2",
        "has a decimal comma",
        "--decimal comma",
    ]);
    identify(&data, &json, &["--decimal", "comma"]).success();
    let m = load(&json);
    assert!((m["sample_time"].as_f64().unwrap() - 0.01).abs() < 1e-12);
    assert_eq!(units(&m), ("V".into(), "deg".into()));
    same_model(&m, &clean, 1e-12);
    // `,` cannot separate fields whose numbers hold commas.
    identify(
        &data,
        &json,
        &["--decimal", "comma", "--delimiter", "comma"],
    )
    .clean_error(&["a decimal comma needs another field delimiter than `,`"]);
    // A decimal point under --decimal comma is refused, not guessed.
    let point = layout(&s, "point.csv", "u;y", &|_, u, y| format!("{u};{y}"));
    let line = rows()
        .iter()
        .position(|(u, y)| u.contains('.') || y.contains('.'))
        .unwrap()
        + 2;
    identify(&point, &json, &["--decimal", "comma"]).clean_error(&[
        &format!("point.csv line {line}"),
        "has a decimal point",
        "drop --decimal comma",
    ]);
}

/// The servo record with its hold (the first 300 inputs, at −1) logged with Gaussian noise of
/// σ = 1e-4 V (a fixed pseudo-random sequence).
fn noisy_hold(s: &Scratch) -> PathBuf {
    let mut state: u64 = 12345;
    let mut uniform = move || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((state >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    };
    let mut text = String::from("u,y\n");
    for (k, (u, y)) in rows().iter().enumerate() {
        let u = match k < 300 {
            true => {
                let (a, b) = (uniform(), uniform());
                let g = (-2.0 * a.ln()).sqrt() * (2.0 * std::f64::consts::PI * b).cos();
                format!("{}", -1.0 + 1e-4 * g)
            }
            false => u.clone(),
        };
        text.push_str(&format!("{u},{y}\n"));
    }
    s.write("noisy.csv", &text)
}

#[test]
fn a_noisy_hold_names_its_deviation_and_is_read_within_a_tolerance() {
    let s = Scratch::new("csv-hold");
    let clean = clean_model(&s);
    let data = noisy_hold(&s);
    let json = s.join("m.json");
    let extra = ["--ts", "0.01", "--input-unit", "V", "--output-unit", "deg"];
    let line = identify(&data, &json, &extra).clean_error(&[
        "noisy.csv line 2: u = ",
        "is not u_min = -1 but the hold (--hold 300) is not over",
        "the input is not exactly at its minimum during the hold",
        "the largest deviation in the hold is ",
        "give --hold-tolerance ",
    ]);
    assert!(!line.contains("hold length"), "{line}");
    // The largest deviation named is the file's.
    let text = std::fs::read_to_string(&data).unwrap();
    let largest = text
        .lines()
        .skip(1)
        .take(300)
        .map(|l| (l.split(',').next().unwrap().parse::<f64>().unwrap() + 1.0).abs())
        .fold(0.0f64, f64::max);
    assert!((2e-4..6e-4).contains(&largest), "{largest}");
    assert!(
        line.contains(&format!("is {largest:.2e} (line ")),
        "{line} / {largest:e}"
    );
    let offered = line.split("--hold-tolerance ").nth(1).unwrap();
    let offered = offered.split_whitespace().next().unwrap();
    assert!(offered.parse::<f64>().unwrap() >= largest, "{offered}");
    // Just below the largest deviation it is still refused; the tolerance offered reads it.
    let below = format!("{:e}", largest * 0.99);
    identify(
        &data,
        &json,
        &[&extra[..], &["--hold-tolerance", &below]].concat(),
    )
    .clean_error(&[&format!("(--hold-tolerance {})", largest * 0.99)]);
    let run = identify(
        &data,
        &json,
        &[&extra[..], &["--hold-tolerance", offered]].concat(),
    )
    .success();
    assert!(
        run.stderr.starts_with("hsid: note: ")
            && run
                .stderr
                .contains("inputs of the hold are within --hold-tolerance"),
        "{}",
        run.stderr
    );
    // Read as u_min, the hold's inputs are the clean file's: the same model, bit for bit.
    same_model(&load(&json), &clean, 0.0);
}

#[test]
fn a_hold_longer_than_the_rest_at_u_min_asks_for_a_shorter_hold() {
    let s = Scratch::new("csv-long-hold");
    let json = s.join("m.json");
    let line = identify(&servo(), &json, &["--hold", "400"]).clean_error(&[
        "servo.csv line 305: u = ",
        "the excitation starts before the hold ends: give --hold 300 or less",
    ]);
    assert!(!line.contains("--hold-tolerance"), "{line}");
}

#[test]
fn the_row_by_row_reader_reads_the_same_layouts() {
    let s = Scratch::new("csv-stream");
    let stream = ["--stream", "--ts", "0.01"];
    let clean_json = s.join("clean.json");
    identify(&servo(), &clean_json, &stream).success();
    let clean = load(&clean_json);
    // Units in the column names, decimal commas, a hold logged with noise.
    let data = noisy_hold(&s);
    let text = std::fs::read_to_string(&data).unwrap();
    let comma: String = text
        .replacen("u,y", "u [V];y [deg]", 1)
        .replace(',', ";")
        .replace('.', ",");
    let comma = s.write("comma.csv", &comma);
    let json = s.join("m.json");
    identify(
        &comma,
        &json,
        &[&stream[..], &["--decimal", "comma"]].concat(),
    )
    .clean_error(&[
        "comma.csv line 2: u = ",
        "is not u_min = -1 but the hold (--hold 300) is not over (--hold-tolerance 0)",
        "give --hold-tolerance",
    ]);
    identify(
        &comma,
        &json,
        &[
            &stream[..],
            &["--decimal", "comma", "--hold-tolerance", "1e-3"],
        ]
        .concat(),
    )
    .success();
    let m = load(&json);
    assert_eq!(units(&m), ("V".into(), "deg".into()));
    same_model(&m, &clean, 0.0);
}
