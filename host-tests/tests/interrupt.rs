//! Ctrl-C and SIGTERM stop a long run within a second, with the shell's exit codes (130,
//! 143), the previous outputs untouched and no temporary left; the stages of a run longer
//! than a second show on standard error unless `--quiet`. Each run is a child process that
//! gets a real signal.
#![cfg(unix)]
#![allow(clippy::unwrap_used, clippy::panic)]

use crate::common;

use std::fs;
use std::io::{BufRead, BufReader};
use std::process::{Command, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use common::{Scratch, p, servo_args};

/// What one interrupted run gave.
struct Stopped {
    code: Option<i32>,
    /// From the signal to the exit.
    latency: Duration,
    stderr: Vec<String>,
}

/// Runs `hsid args`, waits for its first stage line on standard error (the run is then more
/// than a second in, in the middle of its work), sends `signal` and waits for the exit.
fn stop_when_busy(args: &[String], signal: &str) -> Stopped {
    let mut child = Command::new(env!("CARGO_BIN_EXE_hsid"))
        .args(args)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let (tx, rx) = mpsc::channel();
    let stderr = child.stderr.take().unwrap();
    let reader = std::thread::spawn(move || {
        let mut lines = Vec::new();
        for line in BufReader::new(stderr).lines() {
            let line = line.unwrap();
            let _ = tx.send(line.clone());
            lines.push(line);
        }
        lines
    });
    let first = rx.recv_timeout(Duration::from_secs(120)).unwrap();
    assert!(first.starts_with("hsid: ["), "not a stage: {first}");
    assert!(
        child.try_wait().unwrap().is_none(),
        "the run ended before the signal"
    );
    let sent = Instant::now();
    let status = Command::new("kill")
        .args([signal, &child.id().to_string()])
        .status()
        .unwrap();
    assert!(status.success());
    let code = child.wait().unwrap().code();
    let latency = sent.elapsed();
    Stopped {
        code,
        latency,
        stderr: reader.join().unwrap(),
    }
}

/// Entries of `dir` that an output in progress leaves (`.hsid-*.partial`, `.hsid-staging-*`).
fn temporaries(dir: &std::path::Path) -> Vec<String> {
    fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with(".hsid-"))
        .collect()
}

#[test]
fn ctrl_c_stops_identify_within_a_second_with_130_and_the_old_files_kept() {
    let dir = Scratch::new("sigint-identify");
    let (json, html) = (dir.join("m.json"), dir.join("r.html"));
    fs::write(&json, "previous model").unwrap();
    fs::write(&html, "previous report").unwrap();
    let run = stop_when_busy(
        &servo_args(
            "identify",
            &[
                "--json",
                p(&json),
                "--html",
                p(&html),
                "--out",
                p(&dir.join("fig")),
            ],
        ),
        "-INT",
    );
    assert_eq!(run.code, Some(130), "{:?}", run.stderr);
    assert!(run.latency < Duration::from_secs(1), "{:?}", run.latency);
    assert_eq!(fs::read_to_string(&json).unwrap(), "previous model");
    assert_eq!(fs::read_to_string(&html).unwrap(), "previous report");
    assert_eq!(temporaries(&dir.join("")), Vec::<String>::new());
    let last = run.stderr.last().unwrap();
    assert!(last.contains("stopped by SIGINT"), "{last}");
    eprintln!("SIGINT to exit: {:?}", run.latency);
}

#[test]
fn sigterm_stops_diagnose_within_a_second_with_143() {
    let dir = Scratch::new("sigterm-diagnose");
    let json = dir.join("d.json");
    fs::write(&json, "previous diagnosis").unwrap();
    let run = stop_when_busy(
        &servo_args(
            "diagnose",
            &["--json", p(&json), "--out", p(&dir.join("fig"))],
        ),
        "-TERM",
    );
    assert_eq!(run.code, Some(143), "{:?}", run.stderr);
    assert!(run.latency < Duration::from_secs(1), "{:?}", run.latency);
    assert_eq!(fs::read_to_string(&json).unwrap(), "previous diagnosis");
    assert_eq!(temporaries(&dir.join("")), Vec::<String>::new());
    assert!(run.stderr.last().unwrap().contains("stopped by SIGTERM"));
    eprintln!("SIGTERM to exit: {:?}", run.latency);
}

/// The stages of the default identify on the servo record (several seconds) show one line
/// each on a standard error that is not a terminal; `--quiet` removes them and nothing else.
#[test]
fn a_long_run_shows_its_stages_and_quiet_silences_them() {
    let dir = Scratch::new("stages");
    let (a, b) = (dir.join("a.json"), dir.join("b.json"));
    let shown = common::hsid(&servo_args("identify", &["--json", p(&a)])).success();
    let quiet = common::hsid(&servo_args("identify", &["--json", p(&b), "--quiet"])).success();
    let stages: Vec<&str> = shown
        .stderr
        .lines()
        .filter(|l| l.starts_with("hsid: ["))
        .collect();
    assert!(
        stages.iter().any(|l| l.contains("refining order")),
        "{}",
        shown.stderr
    );
    // Each stage line carries the time since the start, from a second on, in order.
    let times: Vec<f64> = stages
        .iter()
        .map(|l| {
            let t = &l["hsid: [".len()..l.find(" s]").unwrap()];
            t.parse().unwrap()
        })
        .collect();
    assert!(times[0] >= 1.0, "{stages:?}");
    assert!(times.windows(2).all(|w| w[0] <= w[1]), "{stages:?}");
    assert!(!quiet.stderr.contains("hsid: ["), "{}", quiet.stderr);
    // The same report, but for the file each run wrote.
    assert_eq!(shown.stdout.replace("a.json", "b.json"), quiet.stdout);
    assert_eq!(fs::read(&a).unwrap(), fs::read(&b).unwrap());
}
