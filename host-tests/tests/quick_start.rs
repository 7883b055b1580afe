//! The README's quick start, run as a user would: the example records are what their committed
//! command makes, and the tour's command lines (read from the README itself) identify the
//! simulated servo's poles, natural frequency, damping and gap, validate at the noise floor and
//! write figures that parse with their series.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use crate::common;

use std::path::{Path, PathBuf};
use std::process::Command;

use common::{Scratch, classes, has};
use hsid_host::model_file::ModelFile;

/// The servo of `examples/data/servo-backlash.json`.
const TS: f64 = 0.01;
const WN: f64 = 2.0 * std::f64::consts::PI * 3.0;
const ZETA: f64 = 0.4;
const GAP: f64 = 0.2;

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn bin_dir() -> PathBuf {
    Path::new(env!("CARGO_BIN_EXE_hsid"))
        .parent()
        .unwrap()
        .to_path_buf()
}

/// `sh -c line` in `dir` with the built `hsid` first on the PATH; its stdout.
fn shell(dir: &Path, line: &str, env: &[(&str, &str)]) -> String {
    let path = format!(
        "{}:{}",
        bin_dir().display(),
        std::env::var("PATH").unwrap_or_default()
    );
    let out = Command::new("sh")
        .arg("-c")
        .arg(line)
        .current_dir(dir)
        .env("PATH", path)
        .envs(env.iter().copied())
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{line}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).unwrap()
}

/// The command lines of the README's tour: the shell block after the `<!-- tour` marker.
fn tour() -> Vec<String> {
    let readme = std::fs::read_to_string(repo().join("README.md")).unwrap();
    let at = readme.find("<!-- tour").expect("README has a tour marker");
    let block = readme[at..].split("```sh\n").nth(1).unwrap();
    let block = &block[..block.find("```").unwrap()];
    block.lines().map(str::to_string).collect()
}

/// The number after `key` in `text`, e.g. `number(out, "mean gap ")`.
fn number(text: &str, key: &str) -> f64 {
    let at = text
        .find(key)
        .unwrap_or_else(|| panic!("no {key:?} in\n{text}"));
    let rest = &text[at + key.len()..];
    let end = rest
        .find(|c: char| !(c.is_ascii_digit() || c == '.' || c == '-' || c == 'e'))
        .unwrap_or(rest.len());
    rest[..end].parse().unwrap()
}

#[test]
fn the_example_records_are_what_their_command_makes() {
    let dir = Scratch::new("quick-start-records");
    let script = repo().join("examples/data/make-servo-records.sh");
    let out = dir.join("");
    shell(
        &repo(),
        &format!("sh {} {}", script.display(), out.display()),
        &[("HSID", "hsid")],
    );
    for name in ["servo.csv", "servo-check.csv"] {
        let made = std::fs::read(dir.join(name)).unwrap();
        let shipped = std::fs::read(repo().join("examples/data").join(name)).unwrap();
        assert!(
            made == shipped,
            "examples/data/{name} differs from what its command makes"
        );
    }
}

#[test]
fn the_tour_identifies_the_servo_and_draws_it() {
    let dir = Scratch::new("quick-start-tour");
    std::os::unix::fs::symlink(repo().join("examples"), dir.join("examples")).unwrap();
    let lines = tour();
    assert_eq!(lines.len(), 5, "the tour has five commands: {lines:?}");
    let has_rsvg = Command::new("rsvg-convert")
        .arg("--version")
        .output()
        .is_ok();
    let mut outputs = Vec::new();
    for line in &lines {
        if line.starts_with("rsvg-convert") && !has_rsvg {
            eprintln!("skipped (rsvg-convert not installed): {line}");
            continue;
        }
        assert!(line.starts_with("hsid ") || line.starts_with("rsvg-convert "));
        outputs.push(shell(&dir.join(""), line, &[]));
    }
    let identify = &outputs[0];

    // Natural frequency, damping and gap in units, from the printed report.
    let wn = number(identify, "natural frequency ");
    let zeta = number(identify, "damping ");
    let gap = number(identify, "mean gap ");
    assert!((wn / WN - 1.0).abs() < 0.05, "wn {wn} against {WN}");
    assert!(
        (zeta / ZETA - 1.0).abs() < 0.05,
        "zeta {zeta} against {ZETA}"
    );
    assert!((gap / GAP - 1.0).abs() < 0.10, "gap {gap} against {GAP}");

    // The model file's poles against the servo's discretised pair.
    let file = ModelFile::load(dir.join("servo.json")).unwrap();
    assert_eq!(file.sample_time, Some(TS));
    let units = file.units.as_ref().unwrap();
    assert_eq!((units.input.as_str(), units.output.as_str()), ("V", "deg"));
    let (r, th) = (
        (-ZETA * WN * TS).exp(),
        WN * (1.0 - ZETA * ZETA).sqrt() * TS,
    );
    let [re, im] = file.poles[0];
    let dist = (re - r * th.cos()).hypot(im.abs() - r * th.sin());
    assert!(dist < 0.005, "pole {re}+{im}j is {dist} from the truth");

    // Out of sample at the noise floor: the noise's standard deviation on the check record is
    // 0.0233 (docs: README quick start).
    let rmse = number(&outputs[1], "RMSE ");
    assert!(rmse < 1.1 * 0.0233, "validation RMSE {rmse}");

    // The simulated output has the check record's length and the header of a record.
    let sim = std::fs::read_to_string(dir.join("servo-sim.csv")).unwrap();
    let rows = sim.lines().filter(|l| !l.starts_with('#')).count();
    assert_eq!(rows, 6301, "header and 6300 samples");

    // diagnose finds nothing to add on data the model explains.
    assert!(outputs[3].contains("nothing is added"), "{}", outputs[3]);

    // Every figure is an SVG with its series.
    for out in ["out/servo", "out/servo-check"] {
        for entry in std::fs::read_dir(dir.join(out)).unwrap() {
            let path = entry.unwrap().path();
            if path.extension().is_some_and(|e| e == "svg") {
                classes(&path);
            }
        }
    }
    let fig = dir.join("out/servo");
    has(
        &fig.join("borders.svg"),
        &[
            "border-asc",
            "border-desc",
            "points-asc",
            "points-desc",
            "band-asc",
            "true-asc",
            "true-desc",
        ],
    );
    has(&fig.join("bode-magnitude.svg"), &["magnitude", "band"]);
    has(&fig.join("bode-phase.svg"), &["phase", "band"]);
    has(&fig.join("poles.svg"), &["poles", "ellipse"]);
    has(&fig.join("output.svg"), &["measured", "simulated"]);
    has(&fig.join("residual-acf.svg"), &["acf"]);
    if has_rsvg {
        let png = std::fs::read(dir.join("borders.png")).unwrap();
        assert_eq!(&png[1..4], b"PNG");
    }
}
