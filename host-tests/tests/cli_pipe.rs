//! Every verb of `hsid` ends quietly when the reader of its standard output goes away
//! (`hsid validate … | head -1`): exit code 0, nothing on stderr, no panic.
//!
//! Each verb runs with its standard output a pipe whose reading end is closed before the verb
//! writes, so its first write fails with a broken pipe.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::path::Path;
use std::process::{Command, Stdio};

use hsid::{Identifier, Knots, MuZero, Settings};
use hsid_host::io::write_columns;
use hsid_host::paper::{Case, PaperConfig, experiment};

use crate::common;

use common::{Scratch, p};

/// Runs `hsid args` with the reading end of its stdout closed; asserts a quiet exit 0.
fn closed_reader(args: &[&str]) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_hsid"))
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .env_remove("RUST_BACKTRACE")
        .spawn()
        .expect("cannot run the hsid binary");
    drop(child.stdout.take());
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    let cmd = args.join(" ");
    assert_eq!(
        out.status.code(),
        Some(0),
        "hsid {cmd}: {:?}\n{stderr}",
        out.status
    );
    // Nothing but the stages of a run longer than a second (`hsid: [1.2 s] …`).
    let said: Vec<&str> = stderr
        .lines()
        .filter(|l| !l.starts_with("hsid: ["))
        .collect();
    assert!(said.is_empty(), "hsid {cmd} wrote to stderr:\n{stderr}");
}

/// A noise-free run of the paper's backlash case in `dir/data.csv`, its model in
/// `dir/model.json` and its checkpoint in `dir/state.bin`.
fn files(dir: &Path) {
    let cfg = PaperConfig {
        snr_db: f64::INFINITY,
        ..PaperConfig::default()
    };
    let e = experiment(Case::Backlash, &cfg, 0).unwrap();
    let data = dir.join("data.csv");
    write_columns(&data, &["u", "y"], &[&e.u, &e.y]).unwrap();
    let model = dir.join("model.json");
    let run = common::identify(&data, &["--json", p(&model)]).success();
    assert!(run.stdout.contains("order"), "{}", run.stdout);
    let knots = Knots::<f64, 14>::uniform(-3.0, 3.0, 7, 7).unwrap();
    let settings = Settings::new(
        knots,
        10,
        10,
        MuZero::Hold {
            len: 300,
            settle: 150,
        },
    );
    let mut id = Box::new(Identifier::<f64, 14, 20>::new(settings).unwrap());
    for (&u, &y) in e.u.iter().zip(&e.y) {
        id.push(u, y);
    }
    let mut bytes = vec![0u8; hsid::checkpoint_capacity(14, 20, 8)];
    let len = id.save(&mut bytes).unwrap();
    std::fs::write(dir.join("state.bin"), &bytes[..len]).unwrap();
}

#[test]
fn every_verb_ends_quietly_when_its_reader_closes_the_pipe() {
    let scratch = Scratch::new("cli_pipe");
    let dir = scratch.join("");
    files(&dir);
    let data = dir.join("data.csv");
    let (data, model, state) = (p(&data), dir.join("model.json"), dir.join("state.bin"));
    let out = dir.join("out");
    closed_reader(&[
        "excite",
        "--umin",
        "-3",
        "--umax",
        "3",
        "--samples",
        "100000",
    ]);
    closed_reader(&["identify", "--data", data, "--umin", "-3", "--umax", "3"]);
    closed_reader(&["validate", "--model", p(&model), "--data", data]);
    closed_reader(&["solve", "--state", p(&state)]);
    closed_reader(&["simulate", "--model", p(&model), "--input", data]);
    closed_reader(&[
        "diagnose",
        "--data",
        data,
        "--umin",
        "-3",
        "--umax",
        "3",
        "--max-steps",
        "0",
    ]);
    closed_reader(&[
        "paper",
        "--case",
        "backlash",
        "--runs",
        "2",
        "--out",
        p(&out),
    ]);
}
