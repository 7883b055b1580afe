//! Sample time, units and several experiments through the built binary: a continuous-time
//! servo with a known backlash, made by `hsid excite` and `hsid simulate --plant`, identified
//! with `--ts`, reports its natural frequency, damping and gap in seconds and volts; two
//! experiments identified together beat each alone on fresh data; every bad sample time or
//! unit is a one-line error with exit code 1.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::f64::consts::PI;
use std::path::{Path, PathBuf};

use hsid_host::io::parse_columns;
use serde_json::Value;

use crate::common;

use common::{Scratch, hsid, p};

/// The true servo: backlash of gap 0.2 V (unit slope), ωn = 2π·1.5 rad/s, ζ = 0.3,
/// ts = 0.01 s, white output noise at 20 dB.
const GAP: f64 = 0.2;
const FN_HZ: f64 = 1.5;
const ZETA: f64 = 0.3;
const SPEC: &str = r#"{
  "ts": 0.01,
  "units": { "input": "V", "output": "deg" },
  "element": { "kind": "backlash", "shape": "backlash", "gap": 0.2, "slope": 1.0 },
  "plant": { "fn_hz": 1.5, "zeta": 0.3 },
  "noise": { "snr_db": 20, "colour": "white", "seed": 1 }
}"#;
/// Knots at the kinks of the true paths under the Table I excitation.
const KNOTS: [&str; 2] = [
    "--knots-asc=-1,-0.8,-0.4,0,0.4,0.8,1",
    "--knots-desc=-1,-0.8,-0.4,0,0.4,0.8,1",
];

/// Writes `hsid excite` output (`samples`, hold 300, `seed`) to `name`, plus `tail` rows at
/// u_min (a final hold).
fn excite(s: &Scratch, name: &str, samples: usize, seed: u64, tail: usize) -> PathBuf {
    let n = samples.to_string();
    let seed = seed.to_string();
    let r = hsid(&[
        "excite",
        "--umin",
        "-1",
        "--umax",
        "1",
        "--samples",
        &n,
        "--hold",
        "300",
        "--seed",
        &seed,
    ])
    .success();
    let mut text = r.stdout;
    text.push_str(&"-1\n".repeat(tail));
    s.write(name, &text)
}

/// Simulates the servo on `input` (noise seed `seed`) into `name`; `clean` adds `y_clean`.
fn servo(s: &Scratch, input: &Path, name: &str, seed: u64, clean: bool) -> PathBuf {
    let spec = s.write("servo.json", SPEC);
    let seed = seed.to_string();
    let mut args = vec![
        "simulate",
        "--plant",
        p(&spec),
        "--input",
        p(input),
        "--seed",
        &seed,
    ];
    if clean {
        args.push("--clean");
    }
    s.write(name, &hsid(&args).success().stdout)
}

fn identify(data: &[&Path], extra: &[&str]) -> common::Run {
    let mut args = vec!["identify"];
    for d in data {
        args.extend(["--data", p(d)]);
    }
    args.extend(["--umin", "-1", "--umax", "1", "--hold", "300"]);
    args.extend(KNOTS);
    args.extend_from_slice(extra);
    hsid(&args)
}

fn json(path: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

fn floats(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

/// `x` where the piecewise-linear border `(k, b)` (increasing) takes the value `v`.
fn inverse(k: &[f64], b: &[f64], v: f64) -> f64 {
    let i = (0..k.len() - 1)
        .find(|&i| b[i] <= v && v <= b[i + 1])
        .unwrap();
    k[i] + (k[i + 1] - k[i]) * (v - b[i]) / (b[i + 1] - b[i])
}

fn interp(k: &[f64], b: &[f64], x: f64) -> f64 {
    let i = (0..k.len() - 1).find(|&i| x <= k[i + 1]).unwrap();
    b[i] + (b[i + 1] - b[i]) * (x - k[i]) / (k[i + 1] - k[i])
}

/// The number after `key` on the first line of `text` that contains it.
fn number_after(text: &str, key: &str) -> f64 {
    let line = text
        .lines()
        .find(|l| l.contains(key))
        .unwrap_or_else(|| panic!("{key}: {text}"));
    let rest = &line[line.find(key).unwrap() + key.len()..];
    rest.split_whitespace().next().unwrap().parse().unwrap()
}

#[test]
fn a_servo_identified_with_ts_reports_wn_zeta_and_gap_in_units() {
    let s = Scratch::new("units-servo");
    // 12,000 samples after the hold: at 6,000 the gap of seeds 1 to 3 spreads 0.21 to 0.24.
    let u = excite(&s, "u.csv", 12_300, 1, 0);
    let data = servo(&s, &u, "r.csv", 1, false);
    let model = s.join("m.json");
    let run = identify(
        &[&data],
        &[
            "--ts",
            "0.01",
            "--input-unit",
            "V",
            "--output-unit",
            "deg",
            "--json",
            p(&model),
        ],
    )
    .success();
    let m = json(&model);
    assert_eq!(m["sample_time"].as_f64(), Some(0.01));
    assert_eq!(m["units"]["input"], "V");
    assert_eq!(m["units"]["output"], "deg");
    // The pole pair read independently of the report: s = ln(z)/ts.
    let pole = m["poles"]
        .as_array()
        .unwrap()
        .iter()
        .map(floats)
        .find(|z| z[1] > 0.0)
        .unwrap();
    let (sigma, omega) = (
        0.5 * (pole[0].powi(2) + pole[1].powi(2)).ln() / 0.01,
        pole[1].atan2(pole[0]) / 0.01,
    );
    let (wn, zeta) = (sigma.hypot(omega), -sigma / sigma.hypot(omega));
    let wn_true = 2.0 * PI * FN_HZ;
    assert!((wn / wn_true - 1.0).abs() < 0.05, "wn {wn} vs {wn_true}");
    assert!((zeta / ZETA - 1.0).abs() < 0.05, "zeta {zeta} vs {ZETA}");
    // The report gives the same numbers.
    let text = &run.stdout;
    let wn_text = number_after(text, "natural frequency");
    let zeta_text = number_after(text, "damping");
    assert!(
        (wn_text / wn - 1.0).abs() < 1e-4,
        "{wn_text} vs {wn}\n{text}"
    );
    assert!(
        (zeta_text - zeta).abs() < 1e-4,
        "{zeta_text} vs {zeta}\n{text}"
    );
    assert!(
        text.contains("rad/s") && text.contains("deg per V"),
        "{text}"
    );
    // Refined by default: standard deviations are printed.
    assert!(
        text.contains("std of mu0") && text.contains(" ± "),
        "{text}"
    );
    // The gap read independently from the border values: at each inner knot, how far u must
    // travel back after a descent before P_a reaches P_d(u).
    let (k, pa, pd) = (
        floats(&m["knots_asc"]),
        floats(&m["border_asc"]),
        floats(&m["border_desc"]),
    );
    let gaps: Vec<f64> = [-0.4, 0.0, 0.4]
        .iter()
        .map(|&x| inverse(&k, &pa, interp(&k, &pd, x)) - x)
        .collect();
    let mean = gaps.iter().sum::<f64>() / 3.0;
    assert!((mean / GAP - 1.0).abs() < 0.10, "gap {gaps:?} vs {GAP}");
    // validate reads the sample time and units from the model file and reports the same.
    let val = hsid(&[
        "validate",
        "--model",
        p(&model),
        "--data",
        p(&data),
        "--skip",
        "300",
    ])
    .success()
    .stdout;
    assert!(
        val.contains("sample time 0.01 s") && val.contains("deg per V"),
        "{val}"
    );
    assert!(
        (number_after(&val, "natural frequency") / wn_text - 1.0).abs() < 1e-9,
        "{val}"
    );
    let reported = number_after(text, "mean gap");
    assert!(
        (reported / GAP - 1.0).abs() < 0.10,
        "reported gap {reported}\n{text}"
    );
}

/// RMSE of the model in `model` against the noise-free output of `clean` after its hold.
fn model_error(model: &Path, input: &Path, clean: &Path) -> f64 {
    let sim = hsid(&["simulate", "--model", p(model), "--input", p(input)])
        .success()
        .stdout;
    let y = parse_columns("sim", &sim, &["y"]).unwrap().remove(0);
    let text = std::fs::read_to_string(clean).unwrap();
    let truth = parse_columns("clean", &text, &["y_clean"])
        .unwrap()
        .remove(0);
    let e: f64 = y[300..]
        .iter()
        .zip(&truth[300..])
        .map(|(a, b)| (a - b).powi(2))
        .sum();
    (e / (y.len() - 300) as f64).sqrt()
}

fn error_of(s: &Scratch, data: &[&Path], hold: &str, val: (&Path, &Path)) -> f64 {
    let model = s.join("joint.json");
    let mut args = vec!["identify"];
    for d in data {
        args.extend(["--data", p(d)]);
    }
    args.extend([
        "--umin",
        "-1",
        "--umax",
        "1",
        "--hold",
        hold,
        "--json",
        p(&model),
    ]);
    args.extend(KNOTS);
    hsid(&args).success();
    model_error(&model, val.0, val.1)
}

#[test]
fn two_experiments_together_beat_each_alone_on_fresh_data() {
    let s = Scratch::new("units-two");
    let uv = excite(&s, "uv.csv", 6_300, 7, 0);
    let val = servo(&s, &uv, "val.csv", 7, true);
    let val = (uv.as_path(), val.as_path());
    // One long experiment split into two files: the second continues the first.
    let u = excite(&s, "u.csv", 12_300, 1, 0);
    let text = std::fs::read_to_string(servo(&s, &u, "long.csv", 1, false)).unwrap();
    let rows: Vec<&str> = text.lines().filter(|l| !l.starts_with('#')).collect();
    let a = s.write("a.csv", &(rows[..6151].join("\n") + "\n"));
    let b = s.write(
        "b.csv",
        &(format!("{}\n", rows[0]) + &rows[6151..].join("\n") + "\n"),
    );
    let ea = error_of(&s, &[&a], "300", val);
    let eb = error_of(&s, &[&b], "0", val);
    let eab = error_of(&s, &[&a, &b], "300", val);
    assert!(eab <= ea.min(eb), "halves {ea}, {eb}; together {eab}");
    // Two separate experiments, the first ending with a hold of 300 samples at u_min.
    let u2 = excite(&s, "u2.csv", 6_300, 2, 300);
    let u3 = excite(&s, "u3.csv", 6_300, 3, 0);
    let (e2, e3) = (
        servo(&s, &u2, "e2.csv", 2, false),
        servo(&s, &u3, "e3.csv", 3, false),
    );
    let (x2, x3) = (
        error_of(&s, &[&e2], "300", val),
        error_of(&s, &[&e3], "300", val),
    );
    let x23 = error_of(&s, &[&e2, &e3], "300", val);
    assert!(x23 <= x2.min(x3), "alone {x2}, {x3}; together {x23}");
    // Without the final hold the junction would mix the experiments: refused.
    let u4 = excite(&s, "u4.csv", 6_300, 4, 0);
    let e4 = servo(&s, &u4, "e4.csv", 4, false);
    identify(&[&e4, &e3], &[]).clean_error(&["e3.csv starts at rest", "e4.csv does not end"]);
}

#[test]
fn detrend_removes_the_output_mean_for_data_without_a_hold() {
    let s = Scratch::new("units-detrend");
    let u = excite(&s, "u.csv", 6_300, 1, 0);
    let text = std::fs::read_to_string(servo(&s, &u, "r.csv", 1, false)).unwrap();
    // Drop the hold and add an offset of 5 to y.
    let cols = parse_columns("r", &text, &["u", "y"]).unwrap();
    let y: Vec<f64> = cols[1][300..].iter().map(|v| v + 5.0).collect();
    let data = s.write_uy("off.csv", &cols[0][300..], &y);
    let mean = y.iter().sum::<f64>() / y.len() as f64;
    let mut args = vec![
        "identify",
        "--data",
        p(&data),
        "--umin",
        "-1",
        "--umax",
        "1",
        "--hold",
        "0",
        "--detrend",
    ];
    args.extend(KNOTS);
    let out = hsid(&args).success().stdout;
    let removed = number_after(&out, "subtracted the mean output");
    assert!((removed - mean).abs() < 1e-5, "{removed} vs {mean}");
    // With a hold, --detrend is refused.
    identify(&[&data], &["--detrend"]).clean_error(&["--detrend applies to data without a hold"]);
}

#[test]
fn bad_sample_times_and_units_are_one_line_errors() {
    let s = Scratch::new("units-bad");
    let rows = |t: &dyn Fn(usize) -> f64| {
        let mut text = String::from("t,u,y\n");
        for i in 0..400 {
            let u = if i < 300 {
                -1.0
            } else {
                ((i as f64) * 0.1).sin()
            };
            text.push_str(&format!("{},{u},{}\n", t(i), 0.5 * u));
        }
        text
    };
    let uniform = s.write("t.csv", &rows(&|i| 0.01 * i as f64));
    for ts in ["-0.01", "0"] {
        identify(&[&uniform], &["--ts", ts]).clean_error(&["--ts", ts, "positive"]);
    }
    // --ts wins over the time column, which is not used: a note says how it differs.
    let first_line = |r: common::Run| r.stderr.lines().next().unwrap_or_default().to_string();
    let note = first_line(identify(&[&uniform], &["--ts", "0.02", "--quiet"]));
    assert!(
        note.starts_with("hsid: note: --ts 0.02 s is used; the time column \"t\" of")
            && note.contains("mean step 10.0 ms")
            && note.contains("its mean step differs from --ts by 50.0 %"),
        "{note}"
    );
    // Line 352 (row 351, i = 350) comes 5 ms late.
    let late = s.write(
        "late.csv",
        &rows(&|i| 0.01 * i as f64 + if i == 350 { 0.005 } else { 0.0 }),
    );
    identify(&[&late], &[]).clean_error(&["late.csv line 352", "time step", "uniform"]);
    // diagnose checks the same before it diagnoses.
    hsid(&["diagnose", "--data", p(&uniform), "--ts", "-1"]).clean_error(&["--ts", "positive"]);
    let note = first_line(hsid(&[
        "diagnose",
        "--data",
        p(&uniform),
        "--ts",
        "0.02",
        "--quiet",
    ]));
    assert!(note.contains("the time column \"t\""), "{note}");
    let back = s.write(
        "back.csv",
        &rows(&|i| if i == 200 { 0.0 } else { 0.01 * i as f64 }),
    );
    identify(&[&back], &[]).clean_error(&["back.csv line 202", "does not increase"]);
    identify(&[&uniform], &["--input-unit", "", "--output-unit", "deg"])
        .clean_error(&["--input-unit is empty"]);
    // A model file with ts = 0.01 and units V, deg.
    let model = s.join("m.json");
    let u = excite(&s, "u.csv", 6_300, 1, 0);
    let servo = servo(&s, &u, "r.csv", 1, false);
    identify(
        &[&servo],
        &[
            "--ts",
            "0.01",
            "--no-refine",
            "--f",
            "10",
            "--p",
            "10",
            "--json",
            p(&model),
            "--input-unit",
            "V",
            "--output-unit",
            "deg",
        ],
    )
    .success();
    // The simulated record's header comment `# ts = 0.01 s` is its sample time: the model
    // has it without --ts, and a --ts that disagrees is refused naming the comment.
    let from_comment = s.join("c.json");
    identify(
        &[&servo],
        &[
            "--no-refine",
            "--f",
            "10",
            "--p",
            "10",
            "--json",
            p(&from_comment),
        ],
    )
    .success();
    assert_eq!(json(&from_comment)["sample_time"], 0.01);
    // Its comments `# input unit = V`, `# output unit = deg` are its units, and flags that
    // disagree are refused naming the comments.
    assert_eq!(json(&from_comment)["units"]["input"], "V");
    assert_eq!(json(&from_comment)["units"]["output"], "deg");
    identify(
        &[&servo],
        &["--input-unit", "mV", "--output-unit", "deg", "--no-refine"],
    )
    .clean_error(&[
        "--input-unit/--output-unit give u in mV and y in deg",
        "the unit comments of",
        "give u in V and y in deg",
    ]);
    let half = s.write("half.csv", "# output unit = deg\nu,y\n-1,0\n");
    identify(&[&half], &[]).clean_error(&["half.csv line 1", "# input unit = …"]);
    identify(&[&servo], &["--ts", "0.02", "--no-refine"]).clean_error(&[
        "--ts gives a sample time of 0.02 s",
        "the `# ts` comment of",
        "0.01 s",
    ]);
    let bad = s.write("bad.csv", "# ts = 10 ms\nu,y\n-1,0\n");
    identify(&[&bad], &[]).clean_error(&["bad.csv line 1", "# ts = 0.01 s"]);
    let plain = s.write_uy("plain.csv", &[-1.0; 50], &[-0.5; 50]);
    hsid(&[
        "validate",
        "--model",
        p(&model),
        "--data",
        p(&plain),
        "--ts",
        "0.02",
    ])
    .clean_error(&["--ts gives a sample time of 0.02 s", "m.json gives 0.01 s"]);
    hsid(&[
        "validate",
        "--model",
        p(&model),
        "--data",
        p(&plain),
        "--input-unit",
        "mV",
        "--output-unit",
        "deg",
    ])
    .clean_error(&[
        "--input-unit/--output-unit give u in mV and y in deg",
        "m.json give u in V and y in deg",
    ]);
    let input = s.write("in.csv", "u\n-1\n0\n");
    hsid(&[
        "simulate",
        "--model",
        p(&model),
        "--input",
        p(&input),
        "--ts",
        "0.5",
    ])
    .clean_error(&["--ts gives a sample time of 0.5 s", "m.json gives 0.01 s"]);
    let spec = s.write("servo.json", SPEC);
    hsid(&[
        "simulate",
        "--plant",
        p(&spec),
        "--input",
        p(&input),
        "--ts",
        "0.02",
    ])
    .clean_error(&["servo.json gives 0.01 s"]);
}
