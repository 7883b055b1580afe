//! `hsid simulate` through the built binary: the pipe `excite | simulate --plant | identify`
//! recovers the simulated servo, a model identified from noise-free data reproduces them, the
//! output noise meets its SNR, and every bad input is a one-line error with exit code 1.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::f64::consts::PI;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use hsid_host::io::parse_columns;
use serde_json::Value;

use crate::common;

use common::{Scratch, hsid, p};

/// The shipped servo example: backlash of gap 0.2, 3 Hz, ζ = 0.4, ts = 0.01 s, 20 dB.
fn servo_spec() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/data/servo-backlash.json")
}

fn bin() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_hsid"));
    c.env_remove("RUST_BACKTRACE");
    c
}

/// Runs `excite | simulate | identify` as three processes joined by pipes; returns
/// identify's stdout.
fn pipe(excite: &[&str], simulate: &[&str], identify: &[&str]) -> String {
    let mut a = bin()
        .arg("excite")
        .args(excite)
        .stdout(Stdio::piped())
        .spawn()
        .unwrap();
    let mut b = bin()
        .arg("simulate")
        .args(simulate)
        .stdin(Stdio::from(a.stdout.take().unwrap()))
        .stdout(Stdio::piped())
        .spawn()
        .unwrap();
    let c = bin()
        .arg("identify")
        .args(identify)
        .stdin(Stdio::from(b.stdout.take().unwrap()))
        .output()
        .unwrap();
    assert!(a.wait().unwrap().success(), "excite failed");
    assert!(b.wait().unwrap().success(), "simulate failed");
    let out = String::from_utf8(c.stdout).unwrap();
    let err = String::from_utf8(c.stderr).unwrap();
    assert!(c.status.success(), "identify failed:\n{out}\n{err}");
    out
}

/// Column `name` of CSV text (comment lines skipped).
fn column(text: &str, name: &str) -> Vec<f64> {
    parse_columns("<stdout>", text, &[name]).unwrap().remove(0)
}

fn variance(x: &[f64]) -> f64 {
    let m = x.iter().sum::<f64>() / x.len() as f64;
    x.iter().map(|v| (v - m) * (v - m)).sum::<f64>() / x.len() as f64
}

#[test]
fn the_pipe_recovers_the_servo_poles_and_gap() {
    let s = Scratch::new("sim-pipe");
    let model = s.join("servo.json");
    // Knots at the kinks of the true paths (u_min + gap, u_max − gap), so the paths are exactly
    // piecewise linear on them.
    let knots = "-1,-0.8,-0.4,0,0.4,0.8,1";
    let spec = servo_spec();
    pipe(
        &[
            "--umin",
            "-1",
            "--umax",
            "1",
            "--samples",
            "6300",
            "--hold",
            "300",
        ],
        &["--plant", p(&spec), "--input", "-"],
        &[
            "--data",
            "-",
            "--umin",
            "-1",
            "--umax",
            "1",
            "--hold",
            "300",
            &format!("--knots-asc={knots}"),
            &format!("--knots-desc={knots}"),
            "--refine",
            "--json",
            p(&model),
        ],
    );
    let m: Value = serde_json::from_str(&std::fs::read_to_string(&model).unwrap()).unwrap();
    // Truth, analytically: poles of wn²/(s² + 2ζwn s + wn²) sampled at ts lie at radius
    // exp(−ζ wn ts) and angle ±wn √(1 − ζ²) ts.
    let (wn, zeta, ts) = (2.0 * PI * 3.0, 0.4, 0.01);
    let (r, th) = (
        (-zeta * wn * ts).exp(),
        wn * (1.0 - zeta * zeta).sqrt() * ts,
    );
    let poles = m["poles"].as_array().unwrap();
    assert_eq!(poles.len(), 2, "{poles:?}");
    for pole in poles {
        let (re, im) = (pole[0].as_f64().unwrap(), pole[1].as_f64().unwrap());
        assert!(
            (re.hypot(im) - r).abs() < 0.005,
            "radius {} vs {r}",
            re.hypot(im)
        );
        assert!((im.abs().atan2(re) - th).abs() < 0.005, "angle vs {th}");
    }
    // The gap P_d − P_a at the knots where neither path is flat ([−0.8, 0.8]).
    let f = |k: &str| -> Vec<f64> {
        m[k].as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_f64().unwrap())
            .collect()
    };
    let (k, a, d) = (f("knots_asc"), f("border_asc"), f("border_desc"));
    let gaps: Vec<f64> = (0..k.len())
        .filter(|&i| k[i].abs() < 0.9)
        .map(|i| d[i] - a[i])
        .collect();
    let gap = gaps.iter().sum::<f64>() / gaps.len() as f64;
    assert!((gap - 0.2).abs() < 0.02, "gap {gap} ({gaps:?})");
}

/// A switch whose borders are piecewise linear on the identification's knots and meet at the
/// interval's ends, with a second-order plant: the two-path model is exact.
const SWITCH: &str = r#"{
  "ts": 0.01,
  "element": {"kind": "switch",
              "ascending": {"u": [-1, 0, 1], "y": [-1, -0.3, 1]},
              "descending": {"u": [-1, 0, 1], "y": [-1, 0.3, 1]}},
  "plant": {"fn_hz": 3, "zeta": 0.4}
}"#;

#[test]
fn a_model_from_noise_free_data_reproduces_them() {
    let s = Scratch::new("sim-model");
    let spec = s.write("switch.json", SWITCH);
    let u = hsid(&[
        "excite",
        "--umin",
        "-1",
        "--umax",
        "1",
        "--samples",
        "2300",
        "--hold",
        "300",
    ])
    .success();
    let u_csv = s.write("u.csv", &u.stdout);
    let plant = hsid(&["simulate", "--plant", p(&spec), "--input", p(&u_csv)]).success();
    assert!(
        plant.stdout.starts_with("# ts = 0.01 s\n"),
        "{}",
        &plant.stdout[..40]
    );
    let data = s.write("y.csv", &plant.stdout);
    let model = s.join("m.json");
    hsid(&[
        "identify",
        "--data",
        p(&data),
        "--umin",
        "-1",
        "--umax",
        "1",
        "--hold",
        "300",
        "--segments",
        "2",
        "--nonlinearity",
        "switch",
        "--order",
        "2",
        "--json",
        p(&model),
    ])
    .success();
    let sim = hsid(&["simulate", "--model", p(&model), "--input", p(&data)]).success();
    let (y, ys) = (column(&plant.stdout, "y"), column(&sim.stdout, "y"));
    assert_eq!(y.len(), 2300);
    let worst = y
        .iter()
        .zip(&ys)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(worst < 1e-9, "largest difference {worst}");
    assert_eq!(column(&sim.stdout, "u"), column(&plant.stdout, "u"));
}

#[test]
fn the_noise_meets_its_snr_and_the_time_column_passes_through() {
    let s = Scratch::new("sim-snr");
    let rows: String = (0..400)
        .map(|i| format!("{},{}\n", i as f64 * 0.01, (i as f64 * 0.05).sin()))
        .collect();
    let u = s.write("u.csv", &format!("t,u\n{rows}"));
    let run = hsid(&[
        "simulate",
        "--plant",
        p(&servo_spec()),
        "--input",
        p(&u),
        "--clean",
    ])
    .success();
    let (y, yc) = (column(&run.stdout, "y"), column(&run.stdout, "y_clean"));
    let v: Vec<f64> = y.iter().zip(&yc).map(|(a, b)| a - b).collect();
    let snr = 10.0 * (variance(&yc) / variance(&v)).log10();
    assert!((snr - 20.0).abs() < 1e-9, "SNR {snr}");
    assert_eq!(column(&run.stdout, "t")[399], 3.99);
    // Another seed gives another record with the same SNR.
    let other = hsid(&[
        "simulate",
        "--plant",
        p(&servo_spec()),
        "--input",
        p(&u),
        "--seed",
        "7",
    ])
    .success();
    assert_ne!(column(&other.stdout, "y"), y);
}

/// Writes a spec and returns the error line of simulating it.
fn spec_error(s: &Scratch, json: &str, needles: &[&str]) -> String {
    let spec = s.write("bad.json", json);
    let u = s.write("u.csv", "u\n0\n0.5\n-0.5\n");
    hsid(&["simulate", "--plant", p(&spec), "--input", p(&u)]).clean_error(needles)
}

const EL: &str = r#""element": {"kind": "backlash", "shape": "backlash", "gap": 0.2}"#;

#[test]
fn bad_specifications_are_one_line_errors_naming_the_field() {
    let s = Scratch::new("sim-bad-spec");
    let unknown = r#"{"element": {"kind": "backlash", "shape": "backlash", "gapp": 0.2},
        "plant": {"num": [0, 1], "den": [1, -0.5]}}"#;
    spec_error(&s, unknown, &["element", "gapp"]);
    for ts in ["-0.01", "0"] {
        let j = format!(r#"{{"ts": {ts}, {EL}, "plant": {{"tau": 0.1}}}}"#);
        spec_error(&s, &j, &["\"ts\"", ts, "> 0"]);
    }
    let j = format!(r#"{{"ts": 0.01, {EL}, "plant": {{"wn": 10, "zeta": -0.1}}}}"#);
    spec_error(&s, &j, &["plant.zeta", "-0.1", ">= 0"]);
    let j = format!(r#"{{{EL}, "plant": {{"num": [0, 1], "den": [1, -1.1]}}}}"#);
    spec_error(&s, &j, &["plant.den", "unstable", "1.1"]);
    let j = r#"{"element": {"kind": "switch", "ascending": {"u": [-1, 0, 0], "y": [0, 0, 1]},
        "descending": {"u": [-1, 1], "y": [0, 1]}}, "plant": {"num": [0, 1], "den": [1, -0.5]}}"#;
    spec_error(&s, j, &["element.ascending", "increase", "u[2]"]);
    let j = format!(r#"{{{EL}, "plant": {{"tau": 0.1}}}}"#);
    spec_error(&s, &j, &["\"ts\"", "missing"]);
}

#[test]
fn a_model_extends_its_borders_beyond_its_interval_unless_told_to_be_strict() {
    let s = Scratch::new("sim-range");
    let spec = s.write("switch.json", SWITCH);
    let u = hsid(&[
        "excite",
        "--umin",
        "-1",
        "--umax",
        "1",
        "--samples",
        "1300",
        "--hold",
        "300",
    ])
    .success();
    let u_csv = s.write("u.csv", &u.stdout);
    let data = s.write(
        "y.csv",
        &hsid(&["simulate", "--plant", p(&spec), "--input", p(&u_csv)])
            .success()
            .stdout,
    );
    let model = s.join("m.json");
    hsid(&[
        "identify",
        "--data",
        p(&data),
        "--umin",
        "-1",
        "--umax",
        "1",
        "--hold",
        "300",
        "--segments",
        "2",
        "--nonlinearity",
        "switch",
        "--order",
        "2",
        "--json",
        p(&model),
    ])
    .success();
    // `validate --data -` reads the record from standard input.
    let out = bin()
        .args([
            "validate",
            "--model",
            p(&model),
            "--data",
            "-",
            "--skip",
            "300",
        ])
        .stdin(Stdio::from(std::fs::File::open(&data).unwrap()))
        .output()
        .unwrap();
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(
        out.status.success() && text.contains("fit 100.00 %"),
        "{text}"
    );
    let wide = s.write("wide.csv", "u\n-1\n0.5\n1.5\n-1\n");
    hsid(&[
        "simulate",
        "--model",
        p(&model),
        "--input",
        p(&wide),
        "--strict-interval",
    ])
    .clean_error(&["line 4", "1.5", "--extrapolate"]);
    // By default (and with --extrapolate, which names the default) the borders are extended.
    let default = hsid(&["simulate", "--model", p(&model), "--input", p(&wide)]).success();
    assert!(
        default
            .stdout
            .contains("# note: 1 of 4 samples (25.00 %) lies outside"),
        "{}",
        default.stdout
    );
    let run = hsid(&[
        "simulate",
        "--model",
        p(&model),
        "--input",
        p(&wide),
        "--extrapolate",
    ])
    .success();
    assert_eq!(column(&run.stdout, "y").len(), 4);
    assert_eq!(run.stdout, default.stdout);
    let both = hsid(&[
        "simulate",
        "--model",
        p(&model),
        "--input",
        p(&wide),
        "--extrapolate",
        "--strict-interval",
    ]);
    assert!(
        !both.ok && both.stderr.contains("cannot be used with"),
        "{}",
        both.stderr
    );
    let t = s.write("t.csv", "t,u\n0,-1\n0.01,0\n0.01,0.5\n");
    hsid(&["simulate", "--model", p(&model), "--input", p(&t)])
        .clean_error(&["t.csv line 4", "does not increase"]);
}
