//! Outputs that are whole or untouched, and error lines that are one line: a reader of standard
//! output that goes away, a file-size limit (a full disk), concurrent writers, a signal in the
//! middle of a batch or of the figures, and inputs that carry control characters.
#![allow(clippy::unwrap_used, clippy::panic)]

use crate::common;

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::Duration;

use common::{Scratch, p, servo};

/// `identify` on the servo record, quickly (the subspace model), with `extra`.
fn servo_args(extra: &[&str]) -> Vec<String> {
    common::servo_args("identify", &[&["--no-refine"], extra].concat())
}

fn is_model_file(path: &Path) -> bool {
    fs::read_to_string(path)
        .ok()
        .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok())
        .is_some_and(|v| v.get("format").is_some())
}

/// Names in `dir` that are not `keep` (temporaries left behind).
fn leftovers(dir: &Path, keep: &[&str]) -> Vec<String> {
    fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| !keep.contains(&n.as_str()))
        .collect()
}

/// `hsid identify … --json m.json | head -0`: the reader is gone before the first line, and
/// the model file is written all the same (exit 0, as `head` expects).
#[test]
fn a_closed_standard_output_does_not_stop_the_files() {
    let dir = Scratch::new("closed-stdout");
    let json = dir.join("m.json");
    let figures = dir.join("figures");
    let args = servo_args(&["--json", p(&json), "--out", p(&figures)]);
    let mut child = Command::new(env!("CARGO_BIN_EXE_hsid"))
        .args(&args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(is_model_file(&json), "m.json missing or not whole");
    let svgs = fs::read_dir(&figures)
        .unwrap()
        .filter(|e| e.as_ref().unwrap().path().extension() == Some("svg".as_ref()))
        .count();
    assert!(svgs >= 5, "{svgs} figures");
}

/// A file-size limit stands in for a full disk: the write fails, the command says so and exits
/// 1, and the previous model file is left as it was, with no temporary beside it.
#[cfg(unix)]
#[test]
fn a_failed_write_leaves_the_previous_file() {
    let dir = Scratch::new("full-disk");
    let json = dir.join("m.json");
    fs::write(&json, "previous").unwrap();
    // 1 KiB: less than a model file. SIGXFSZ ignored, so the write returns EFBIG.
    let script = "trap '' XFSZ; ulimit -f 2; exec \"$0\" \"$@\"";
    let args = servo_args(&["--json", p(&json)]);
    let out = Command::new("sh")
        .arg("-c")
        .arg(script)
        .arg(env!("CARGO_BIN_EXE_hsid"))
        .args(&args)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.starts_with("hsid: ") && stderr.contains("m.json"),
        "{stderr}"
    );
    assert_eq!(fs::read_to_string(&json).unwrap(), "previous");
    assert_eq!(leftovers(&dir.join(""), &["m.json"]), Vec::<String>::new());
}

/// Two runs writing the same model file at once: the file is always one whole model file.
#[test]
fn concurrent_writers_leave_a_whole_file() {
    let dir = Scratch::new("concurrent");
    let json = dir.join("m.json");
    for round in 0..8 {
        let spawn = || {
            Command::new(env!("CARGO_BIN_EXE_hsid"))
                .args(servo_args(&["--json", p(&json)]))
                .stdout(Stdio::null())
                .stderr(Stdio::null())
                .spawn()
                .unwrap()
        };
        let (mut a, mut b) = (spawn(), spawn());
        assert!(a.wait().unwrap().success() && b.wait().unwrap().success());
        assert!(
            is_model_file(&json),
            "round {round}: not a whole model file"
        );
    }
    assert_eq!(leftovers(&dir.join(""), &["m.json"]), Vec::<String>::new());
}

/// SIGINT while `fleet` solves a folder of checkpoints: the previous `--out` file stays as it
/// was (or, if the batch finished first, it is the whole new one): never a cut line.
#[cfg(unix)]
#[test]
fn an_interrupted_fleet_leaves_the_previous_results() {
    let dir = Scratch::new("fleet-sigint");
    let (states, _) = common::simulate_fleet(&dir, 150, 2);
    let out = dir.join("prev.jsonl");
    let previous = "{\"previous\": true}\n";
    fs::write(&out, previous).unwrap();
    for wait_ms in [50u64, 300, 700] {
        let child = Command::new(env!("CARGO_BIN_EXE_hsid"))
            .args(["fleet", "--states", p(&states), "--out", p(&out)])
            .arg("--threads")
            .arg("1")
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        std::thread::sleep(Duration::from_millis(wait_ms));
        let _ = Command::new("kill")
            .args(["-INT", &child.id().to_string()])
            .status();
        let mut child = child;
        let _ = child.wait();
        let text = fs::read_to_string(&out).unwrap();
        let whole_new = text.lines().count() == 300
            && text
                .lines()
                .all(|l| serde_json::from_str::<serde_json::Value>(l).is_ok());
        assert!(
            text == previous || whole_new,
            "after {wait_ms} ms: neither the previous file nor a whole new one:\n{text}"
        );
        // The interrupted run removed its temporary file.
        let left: Vec<String> = leftovers(&dir.join(""), &[])
            .into_iter()
            .filter(|n| n.starts_with(".hsid-"))
            .collect();
        assert_eq!(left, Vec::<String>::new(), "after {wait_ms} ms");
        fs::write(&out, previous).unwrap();
    }
}

/// SIGTERM while the figures are written: the folder holds the previous figures or the new
/// ones, never a mixture.
#[cfg(unix)]
#[test]
fn an_interrupted_run_leaves_the_previous_figures() {
    let dir = Scratch::new("figures-sigterm");
    let figures = dir.join("figures");
    common::hsid(&servo_args(&["--out", p(&figures)])).success();
    // Mark the previous set, then interrupt new runs at different moments.
    let names: Vec<PathBuf> = fs::read_dir(&figures)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.is_file())
        .collect();
    assert!(names.len() >= 10, "{} files", names.len());
    for wait_ms in [20u64, 60, 150, 300] {
        for f in &names {
            fs::write(f, "previous").unwrap();
        }
        let mut child = Command::new(env!("CARGO_BIN_EXE_hsid"))
            .args(servo_args(&["--out", p(&figures)]))
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        std::thread::sleep(Duration::from_millis(wait_ms));
        let _ = Command::new("kill")
            .args(["-TERM", &child.id().to_string()])
            .status();
        let _ = child.wait();
        let previous = names
            .iter()
            .filter(|f| fs::read_to_string(f).is_ok_and(|t| t == "previous"))
            .count();
        assert!(
            previous == 0 || previous == names.len(),
            "after {wait_ms} ms: {previous} of {} figure files are the previous ones",
            names.len()
        );
        // The stopped run removed its staging folder and temporary files.
        let left: Vec<String> = leftovers(&figures, &[])
            .into_iter()
            .filter(|n| n.starts_with(".hsid-"))
            .collect();
        assert_eq!(left, Vec::<String>::new(), "after {wait_ms} ms");
    }
}

/// A figure that cannot be placed (its name is taken by a folder, the last figure written)
/// fails the run before any figure is replaced: the previous ones are all kept.
#[test]
fn a_figure_that_cannot_be_placed_replaces_none() {
    let dir = Scratch::new("figures-blocked");
    let figures = dir.join("figures");
    common::hsid(&servo_args(&["--out", p(&figures)])).success();
    let names: Vec<PathBuf> = fs::read_dir(&figures)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.is_file() && !p.ends_with("residual-acf.svg"))
        .collect();
    for f in &names {
        fs::write(f, "previous").unwrap();
    }
    fs::remove_file(figures.join("residual-acf.svg")).unwrap();
    fs::create_dir(figures.join("residual-acf.svg")).unwrap();
    let run = common::hsid(&servo_args(&["--out", p(&figures)]));
    assert_eq!(run.code, Some(1), "{}", run.stderr);
    assert!(run.stderr.contains("residual-acf.svg"), "{}", run.stderr);
    assert!(!run.stderr.contains(".hsid-staging"), "{}", run.stderr);
    for f in &names {
        assert_eq!(
            fs::read_to_string(f).unwrap(),
            "previous",
            "{}",
            f.display()
        );
    }
    let mut left = leftovers(&figures, &[]);
    left.retain(|n| n.starts_with(".hsid"));
    assert_eq!(left, Vec::<String>::new());
}

/// A CSV field with a line break and an ESC, and a header with a BEL: the error is one line,
/// and no control character reaches the terminal.
#[test]
fn an_error_is_one_line_whatever_the_input() {
    let dir = Scratch::new("one-line");
    let cases = [
        ("newline.csv", "u,y\n1,\"2\nhsid: spoofed\"\n3,4\n"),
        ("escape.csv", "u,y\n1,2\u{1b}[31mred\n3,4\n"),
        ("bell.csv", "u\u{7},y\0\n1,2\n"),
    ];
    for (name, text) in cases {
        let data = dir.write(name, text);
        let run = common::identify(&data, &[]);
        assert!(!run.ok, "{name}: accepted");
        assert_eq!(run.stderr.lines().count(), 1, "{name}: {:?}", run.stderr);
        assert!(
            !run.stderr.trim_end().chars().any(char::is_control),
            "{name}: {:?}",
            run.stderr
        );
    }
}

/// `diagnose --prefix` is the start of a file name: a path that leaves `--out` is refused
/// before any work.
#[test]
fn a_prefix_cannot_leave_the_figure_folder() {
    let dir = Scratch::new("prefix");
    let out = dir.join("inj").join("dout");
    let run = common::hsid(&[
        "diagnose",
        "--data",
        p(&servo()),
        "--umin",
        "-1",
        "--umax",
        "1",
        "--out",
        p(&out),
        "--prefix",
        "../escaped-",
    ]);
    assert_eq!(run.code, Some(2), "{}", run.stderr);
    assert!(run.stderr.contains("--prefix"), "{}", run.stderr);
    assert!(
        run.stderr.contains("not a file-name prefix"),
        "{}",
        run.stderr
    );
    assert!(!dir.join("inj").exists());
}
