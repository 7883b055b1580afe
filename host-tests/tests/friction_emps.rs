//! Friction on a measured positioning drive (EMPS: a DC motor and ball screw with Coulomb and
//! viscous friction and an offset, force → position, logged in closed loop). The benchmark's
//! protocol: identify on the training record, simulate the test record's position from its
//! input (the motor force), the first 20 samples for the initial state. Read from
//! `../shared/data/` (the benchmark's own files; never copied into the project).
//!
//! Independent truth: the benchmark's rigid-body reference model, identified by its authors
//! by inverse dynamics and least squares (M = 95.1089 kg, F_v = 203.5034 N s/m, F_c = 20.3935
//! N, offset −3.1648 N), and its own simulation of the test record (R² 0.9896 from the force,
//! by forward Euler at 1 ms, measured with a script outside the project).

#![allow(clippy::unwrap_used, clippy::panic)]

use crate::common::{Scratch, hsid, p};

use crate::common::{EMPS_TEST as TEST, EMPS_TRAIN as TRAIN};

/// The number after `label` in `line`.
fn number_after(line: &str, label: &str) -> f64 {
    let rest = &line[line.find(label).unwrap() + label.len()..];
    let word = rest
        .split_whitespace()
        .next()
        .unwrap()
        .trim_end_matches(',');
    word.parse()
        .unwrap_or_else(|e| panic!("{label:?} then {word:?} ({e}) in {line}"))
}

#[test]
fn emps_with_friction_reads_the_reference_model_and_simulates_the_test_record() {
    let dir = Scratch::new("friction_emps");
    let model = dir.join("emps.json");
    let columns = [
        "--input-column",
        "force_N",
        "--output-column",
        "qm",
        "--input-unit",
        "N",
        "--output-unit",
        "m",
    ];
    let mut args = vec![
        "identify", "--data", TRAIN, "--umin", "-160", "--umax", "150",
    ];
    args.extend(columns);
    args.extend([
        "--hold",
        "0",
        "--integrating",
        "--nonlinearity",
        "static",
        "--segments",
        "1",
        "--order",
        "1",
        "--friction",
        "--json",
        p(&model),
    ]);
    let run = hsid(&args).success();
    let said = |start: &str| {
        run.stdout
            .lines()
            .find(|l| l.starts_with(start))
            .unwrap_or_else(|| panic!("no line {start:?} in\n{}", run.stdout))
            .to_string()
    };
    // The identified linear model drifts on the held-out quarter; with friction it follows.
    let holdout = said("--friction: the position simulated on the last 25 %");
    assert!(
        holdout.ends_with("the model with friction is reported"),
        "{holdout}"
    );
    let without = number_after(&holdout, "fit ");
    let with = number_after(&holdout, "without friction, ");
    assert!(without < 0.0 && with > 90.0, "{holdout}");
    // The rigid body, against the benchmark's reference model.
    let body = said("--friction: as a rigid body");
    let close = |label: &str, truth: f64, tol: f64| {
        let v = number_after(&body, label);
        assert!(
            (v - truth).abs() <= tol * truth.abs(),
            "{label} {v} vs {truth}: {body}"
        );
    };
    // Two estimators: the reference model's from the measured acceleration (inverse
    // dynamics), this one's from the simulated position. They read 91.16, 187.4, 22.57 and
    // −3.354 against 95.11, 203.5, 20.39 and −3.165, and this one simulates both records
    // better: fit 96.55 % and 92.07 % on the training and test records by the protocol below,
    // the reference model 93.39 % and 89.71 % (by a script outside the project, its sign
    // smoothed as this one's, the start from a parabola through the first 20 samples).
    close("mass ", 95.1089, 0.05);
    close("viscous friction ", 203.5034, 0.10);
    close("Coulomb friction ", 20.3935, 0.12);
    close("offset ", -3.1648, 0.08);
    let file = std::fs::read_to_string(&model).unwrap();
    assert!(file.contains("\"friction\""), "{file}");
    // The test record simulated from its force, the first 20 samples for the initial state.
    let mut args = vec!["validate", "--model", p(&model), "--data", TEST];
    args.extend(columns);
    args.extend(["--skip", "0", "--initial-samples", "20"]);
    let run = hsid(&args).success();
    let fit = run
        .stdout
        .lines()
        .find(|l| l.starts_with("simulation fit on 24841 samples"))
        .unwrap_or_else(|| panic!("{}", run.stdout));
    let nrmse = number_after(fit, "NRMSE ");
    let r2 = 1.0 - nrmse * nrmse;
    eprintln!("EMPS test record: {fit} (R² {r2:.4})");
    // The reference model's own simulation reaches R² 0.9896; the goal is 0.99.
    assert!(r2 >= 0.99, "R² {r2:.4}: {fit}");
}
