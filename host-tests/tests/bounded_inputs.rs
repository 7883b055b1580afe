//! Every input path read whole is bounded: a device that never ends, a FIFO that would wait for
//! a writer and a folder are refused before they are opened, and a file larger than its kind
//! can be is refused before it is read; in a fleet's folder such an entry costs that entry.
#![allow(clippy::unwrap_used, clippy::panic)]

use crate::common;

use std::fs;
use std::path::PathBuf;
use std::process::Command;

use common::{Scratch, hsid, p, servo, servo_model};

/// A small fleet of `devices` × 1 week in `dir`: the states folder and the truth table.
fn fleet(dir: &Scratch, devices: usize) -> (PathBuf, PathBuf) {
    common::simulate_fleet(dir, devices, 1)
}

#[cfg(unix)]
#[test]
fn a_device_or_folder_is_refused_on_every_input_path() {
    let dir = Scratch::new("bounded-devices");
    let (states, truth) = fleet(&dir, 3);
    let models = dir.join("models.jsonl");
    hsid(&["fleet", "--states", p(&states), "--out", p(&models)]).success();
    let json = servo_model(&dir, &[]);
    let servo = servo();
    let folder = dir.join("");
    let cases: Vec<(&str, Vec<&str>)> = vec![
        ("solve --state", vec!["solve", "--state", "/dev/zero"]),
        (
            "fleet --like",
            vec![
                "fleet",
                "--states",
                p(&states),
                "--out",
                "/dev/null",
                "--like",
                "/dev/zero",
            ],
        ),
        (
            "fleet report --models",
            vec![
                "fleet",
                "report",
                "--models",
                "/dev/zero",
                "--truth",
                p(&truth),
            ],
        ),
        (
            "fleet report --truth",
            vec![
                "fleet",
                "report",
                "--models",
                p(&models),
                "--truth",
                "/dev/zero",
            ],
        ),
        (
            "validate --noise",
            vec![
                "validate",
                "--model",
                p(&json),
                "--data",
                p(&servo),
                "--noise",
                "/dev/zero",
            ],
        ),
        (
            "validate --model",
            vec!["validate", "--model", "/dev/zero", "--data", p(&servo)],
        ),
        (
            "simulate --plant",
            vec!["simulate", "--plant", "/dev/zero", "--input", p(&servo)],
        ),
        (
            "solve --state (a folder)",
            vec!["solve", "--state", p(&folder)],
        ),
    ];
    for (name, args) in cases {
        let run = hsid(&args);
        assert_eq!(run.code, Some(1), "{name}: {}", run.stderr);
        assert_eq!(run.stderr.lines().count(), 1, "{name}: {}", run.stderr);
        assert!(
            run.stderr.contains("it is a device") || run.stderr.contains("it is a folder"),
            "{name}: {}",
            run.stderr
        );
    }
}

/// A sparse 2 GiB file is refused by its size, before a byte of it is read.
#[test]
fn a_file_larger_than_any_checkpoint_is_refused_unread() {
    let dir = Scratch::new("bounded-size");
    let big = dir.join("big.bin");
    fs::File::create(&big).unwrap().set_len(2 << 30).unwrap();
    let run = hsid(&["solve", "--state", p(&big)]);
    assert_eq!(run.code, Some(1), "{}", run.stderr);
    assert!(
        run.stderr.contains("2147483648 bytes, larger than the"),
        "{}",
        run.stderr
    );
}

/// A FIFO among the checkpoints is that device's error: the batch does not wait for a writer,
/// and every good checkpoint gets its model.
#[cfg(unix)]
#[test]
fn a_fifo_in_a_fleet_costs_that_entry() {
    let dir = Scratch::new("bounded-fifo");
    let (states, _) = fleet(&dir, 4);
    let fifo = states.join("zz-fifo.bin");
    assert!(
        Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .unwrap()
            .success()
    );
    let out = dir.join("models.jsonl");
    let run = hsid(&["fleet", "--states", p(&states), "--out", p(&out)]).success();
    assert!(run.stdout.contains("4 models, 1 errors"), "{}", run.stdout);
    let text = fs::read_to_string(&out).unwrap();
    let lines: Vec<serde_json::Value> = text
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(lines.len(), 5);
    let bad = &lines[4];
    assert_eq!(bad["device"], "zz-fifo.bin");
    assert!(
        bad["error"]["message"]
            .as_str()
            .is_some_and(|m| m.contains("FIFO")),
        "{bad}"
    );
}

/// Sizes are checked before any work, with the same check for identify and diagnose: a
/// segment count beyond the largest capacity, a delay, a step count, a thread count.
#[test]
fn sizes_beyond_the_bounds_are_refused_before_work() {
    let servo = servo();
    let data = ["--data", p(&servo), "--umin", "-1", "--umax", "1"];
    let cases: [(&[&str], &str); 7] = [
        (
            &["identify", "--segments", "100000"],
            "--segments 100000: at most 1024 segments per path",
        ),
        (
            &["diagnose", "--segments", "100000"],
            "--segments 100000: at most 1024 segments per path",
        ),
        (
            &["identify", "--nonlinearity", "static", "--segments", "2000"],
            "--segments 2000: at most 1024 segments per path",
        ),
        (
            &["diagnose", "--segments", "100"],
            "--segments 100: at most 32",
        ),
        (
            &["diagnose", "--max-delay", "10000"],
            "--max-delay 10000: at most 50",
        ),
        (
            &["diagnose", "--max-steps", "1000"],
            "--max-steps 1000: at most 16",
        ),
        (
            &["diagnose", "--select-segments", "2..100"],
            "--select-segments 2..100",
        ),
    ];
    for (args, expected) in cases {
        let run = hsid(&[&args[..1], &data[..], &args[1..]].concat());
        assert_eq!(run.code, Some(1), "{args:?}: {}", run.stderr);
        assert!(run.stderr.contains(expected), "{args:?}: {}", run.stderr);
    }
    let dir = Scratch::new("bounded-threads");
    let (states, _) = fleet(&dir, 2);
    let out = dir.join("models.jsonl");
    let run = hsid(&[
        "fleet",
        "--states",
        p(&states),
        "--out",
        p(&out),
        "--threads",
        "10000",
    ]);
    assert_eq!(run.code, Some(1), "{}", run.stderr);
    assert!(
        run.stderr.contains("at most 512 worker threads"),
        "{}",
        run.stderr
    );
    assert!(!out.exists());
}

/// `excite` streams: the largest sample count prints its first rows at once and stops when
/// the reader does, in memory that does not grow.
#[test]
fn excite_streams_and_stops_with_its_reader() {
    use std::io::{BufRead, BufReader};
    let mut child = Command::new(env!("CARGO_BIN_EXE_hsid"))
        .args([
            "excite",
            "--umin",
            "-1",
            "--umax",
            "1",
            "--samples",
            "18446744073709551615",
        ])
        .stdout(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let mut lines = BufReader::new(child.stdout.take().unwrap()).lines();
    let first: Vec<String> = lines.by_ref().take(3).map(Result::unwrap).collect();
    assert_eq!(first, ["u", "-1", "-1"]);
    drop(lines);
    // The run ends on the closed pipe (a hang here is the failure; 60 s is far beyond it).
    let mut status = None;
    for _ in 0..600 {
        if let Some(s) = child.try_wait().unwrap() {
            status = Some(s);
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(100));
    }
    let Some(status) = status else {
        child.kill().unwrap();
        panic!("excite kept running after its reader closed the pipe");
    };
    assert!(status.success(), "{status}");
}

/// A header of 100,000 columns is refused before its names are copied.
#[test]
fn a_header_wider_than_the_limit_is_refused() {
    let dir = Scratch::new("bounded-columns");
    let names: Vec<String> = (0..100_000).map(|i| format!("c{i}")).collect();
    let ones = vec!["1"; 100_000];
    let data = dir.write(
        "wide.csv",
        &format!("{}\n{}\n", names.join(","), ones.join(",")),
    );
    let run = hsid(&[
        "identify",
        "--data",
        p(&data),
        "--umin",
        "-1",
        "--umax",
        "1",
        "--input-column",
        "c0",
        "--output-column",
        "c1",
    ]);
    assert_eq!(run.code, Some(1), "{}", run.stderr);
    assert!(
        run.stderr
            .contains("line 1: the header has 100000 columns, more than the 65536 read"),
        "{}",
        run.stderr
    );
}

/// A small file that states a model of order 300, or 2,001 knots, is refused on reading,
/// before anything is computed from it (the work would grow with the cube of the order).
#[test]
fn a_model_file_beyond_the_sizes_is_refused_on_reading() {
    let dir = Scratch::new("bounded-model");
    let json = servo_model(&dir, &[]);
    let servo = servo();
    let text = fs::read_to_string(&json).unwrap();
    let base: serde_json::Value = serde_json::from_str(&text).unwrap();
    let n = 300;
    let mut order = base.clone();
    order["order"] = n.into();
    order["A"] = (0..n)
        .map(|i| {
            (0..n)
                .map(|j| if i == j { 0.5 } else { 0.0 })
                .collect::<Vec<f64>>()
        })
        .collect::<Vec<_>>()
        .into();
    order["B"] = vec![0.1; n].into();
    order["C"] = vec![0.1; n].into();
    order["poles"] = vec![[0.5, 0.0]; n].into();
    order["std"] = serde_json::Value::Null;
    let (lo, hi) = (-1.0, 1.0);
    let k = 2000;
    let knots: Vec<f64> = (0..=k)
        .map(|i| {
            if i == k {
                hi
            } else {
                lo + (hi - lo) * i as f64 / k as f64
            }
        })
        .collect();
    let mut knotted = base.clone();
    for key in ["knots_asc", "knots_desc"] {
        knotted[key] = knots.clone().into();
    }
    for key in ["border_asc", "border_desc"] {
        knotted[key] = vec![0.0; k + 1].into();
    }
    knotted["std"] = serde_json::Value::Null;
    for (name, model, expected) in [
        (
            "order.json",
            order,
            "field \"order\": 300 is above the largest order a model file holds (128)",
        ),
        (
            "knots.json",
            knotted,
            "field \"knots_asc\": has 2001 values, more than the 1024",
        ),
    ] {
        let path = dir.write(name, &model.to_string());
        let run = hsid(&["validate", "--model", p(&path), "--data", p(&servo)]);
        assert_eq!(run.code, Some(1), "{name}: {}", run.stderr);
        assert!(run.stderr.contains(expected), "{name}: {}", run.stderr);
    }
}
