//! Friction on a motor whose speed is measured, written apart from the friction model: a
//! current loop `τ_i i̇ = u − i` (τ_i = 0.03 s) drives a motor `J ω̇ = K i − b ω − F_c
//! tanh(ω / ε)` with `J = 0.002`, `K = 0.1`, `b = 0.01` (mechanical time constant 0.2 s,
//! static gain 10 rad/s per unit of `u`), `F_c = 0.012` (12 % of the torque at full command)
//! and `ε = 0.01` rad/s; RK4 at 20 steps a sample (`ts = 0.01 s`). The command is smoothed
//! random levels in `[−1, 1]` after a hold at −1, so that the motor turns both ways and
//! stops; white noise at 30 dB.
//!
//! The velocity the friction acts on is the output itself, not its change (a position's):
//! the diagnosis tries both readings and keeps the one that simulates the hold-out better.
//! With the default static element of six segments, fitted without friction, the element
//! takes up part of the friction (in the steady state, Coulomb friction on a speed is a jump
//! of the static characteristic at zero speed); the friction fit also starts from the
//! element's best straight line.
//!
//! Truth in the element's output's units: with `G(1) = 1` those are the output's, and the
//! force is the speed it costs in the steady state, `F_c / b = 1.2` rad/s. `hsid diagnose`
//! adds friction on the speed, reads that force within 20 %, takes the validation error to
//! within 20 % of the noise (the model feeds the friction back at `G`'s input, ahead of the
//! current loop's lag, where the motor's acts behind it: 12 % over the noise on seed 1), and
//! adds no friction to the same motor without it.

#![allow(clippy::panic, clippy::unwrap_used)]

use crate::common::{hsid, p};
use hsid_host::diagnose::{Effect, Validation, diagnose};
use hsid_host::model::Record;

/// Half the command range.
const RANGE: f64 = 1.0;
/// Samples of the hold at `−RANGE` opening every record.
const HOLD: usize = 100;
/// Samples after the hold.
const LEN: usize = 3000;
/// Output SNR in dB.
const SNR_DB: f64 = 30.0;
/// The Coulomb torque, N m.
const COULOMB: f64 = 0.012;
/// Torque per command unit.
const TORQUE: f64 = 0.1;
/// The motor's viscous friction, N m s.
const VISCOUS: f64 = 0.01;

/// The records' own generator (SplitMix64, Box–Muller).
use crate::common::SplitMix as Rng;

/// `(u, measured speed, the noise's standard deviation)`: the hold, then levels held 30–120 samples through a first-order
/// low-pass; the current and the motor integrated by RK4 with the command held over each
/// sample.
fn simulate(seed: u64, coulomb: f64) -> (Vec<f64>, Vec<f64>, f64) {
    let mut rng = Rng(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ 0x5BEED);
    let mut u = vec![-RANGE; HOLD];
    let mut s = -RANGE;
    while u.len() < HOLD + LEN {
        let level = -RANGE + 2.0 * RANGE * rng.uniform();
        let hold = 30 + (rng.uniform() * 91.0) as usize;
        for _ in 0..hold {
            s = 0.7 * s + 0.3 * level;
            u.push(s);
        }
    }
    u.truncate(HOLD + LEN);
    let (tau, j, b, eps) = (0.03, 0.002, VISCOUS, 0.01);
    let deriv = |i: f64, w: f64, c: f64| {
        (
            (c - i) / tau,
            (TORQUE * i - b * w - coulomb * (w / eps).tanh()) / j,
        )
    };
    let steps = 20;
    let h = 0.01 / steps as f64;
    // At rest under the hold's command: the current −1, the speed where the torques balance
    // (found by bisection: K i − b ω − F_c tanh(ω/ε) = 0 is decreasing in ω).
    let mut i = -RANGE;
    let (mut lo, mut hi) = (-100.0, 100.0);
    for _ in 0..200 {
        let mid: f64 = 0.5 * (lo + hi);
        if TORQUE * i - b * mid - coulomb * (mid / eps).tanh() > 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let mut w = 0.5 * (lo + hi);
    let clean: Vec<f64> = u
        .iter()
        .map(|&c| {
            let y = w;
            for _ in 0..steps {
                let k1 = deriv(i, w, c);
                let k2 = deriv(i + 0.5 * h * k1.0, w + 0.5 * h * k1.1, c);
                let k3 = deriv(i + 0.5 * h * k2.0, w + 0.5 * h * k2.1, c);
                let k4 = deriv(i + h * k3.0, w + h * k3.1, c);
                i += h / 6.0 * (k1.0 + 2.0 * k2.0 + 2.0 * k3.0 + k4.0);
                w += h / 6.0 * (k1.1 + 2.0 * k2.1 + 2.0 * k3.1 + k4.1);
            }
            y
        })
        .collect();
    let n = clean.len() as f64;
    let mean = clean.iter().sum::<f64>() / n;
    let var = clean.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n;
    let sd = (var / 10f64.powf(SNR_DB / 10.0)).sqrt();
    let y = clean.iter().map(|v| v + sd * rng.normal()).collect();
    (u, y, sd)
}

/// The diagnosis (static element of six segments, order 2) of the record from `seed`,
/// validated on the one from `seed + 1000`: the friction step's Coulomb force (element units)
/// and whether it acts on the speed, the validation RMSE before and after the friction step
/// (simulation), the validation record's noise, the verdict.
fn diagnosed(seed: u64, coulomb: f64) -> (Option<(f64, bool)>, f64, f64, f64, String) {
    let (u, y, _) = simulate(seed, coulomb);
    let (uv, yv, floor) = simulate(seed + 1000, coulomb);
    let validation = Validation::Separate {
        record: Record::new(uv, yv).unwrap(),
        skip: HOLD,
    };
    let opts = crate::common::static_order_two(RANGE, HOLD);
    let d = diagnose(&Record::new(u, y).unwrap(), &validation, &opts).unwrap();
    let friction = d
        .steps
        .iter()
        .any(|s| s.effect == Effect::Friction)
        .then(|| {
            d.model
                .friction
                .as_ref()
                .map(|f| (f.friction.coulomb, f.friction.speed))
        })
        .flatten();
    // The simulation error after the friction step (a later noise model predicts).
    let after = d
        .steps
        .iter()
        .find(|s| s.effect == Effect::Friction)
        .map_or(d.after.rmse, |s| s.error_after);
    (friction, d.before.rmse, after, floor, d.verdict.to_string())
}

#[test]
fn the_diagnosis_adds_friction_on_a_motors_speed_and_not_where_there_is_none() {
    let truth = COULOMB / VISCOUS;
    for seed in [1, 2] {
        let (friction, before, after, floor, verdict) = diagnosed(seed, COULOMB);
        println!(
            "seed {seed}, friction {truth}: {friction:?}, validation RMSE {before:.5} -> {after:.5} (noise {floor:.5}): {verdict}"
        );
        let (fc, speed) = friction.unwrap_or_else(|| panic!("seed {seed}: {verdict}"));
        assert!(
            speed,
            "seed {seed}: friction on the output's change: {verdict}"
        );
        assert!((fc - truth).abs() < 0.2 * truth, "seed {seed}: {fc}");
        assert!(
            after < 1.2 * floor && after < before,
            "seed {seed}: {verdict}"
        );
    }
    for seed in [3, 4] {
        let (friction, .., verdict) = diagnosed(seed, 0.0);
        println!("seed {seed}, no friction: {verdict}");
        assert!(friction.is_none(), "seed {seed}: {verdict}");
    }
}

/// `hsid diagnose --model-out` writes the friction on the speed (`"speed": true`, as the
/// format's schema has it) and `hsid validate` simulates that file to the diagnosis's own validation error.
#[test]
fn the_model_file_keeps_the_friction_on_the_speed() {
    let dir = crate::common::Scratch::new("friction_speed_cli");
    let (u, y, _) = simulate(1, COULOMB);
    let (uv, yv, _) = simulate(1001, COULOMB);
    let est = dir.write_uy("est.csv", &u, &y);
    let val = dir.write_uy("val.csv", &uv, &yv);
    let (model, json) = (dir.join("model.json"), dir.join("diagnosis.json"));
    let hold = HOLD.to_string();
    crate::common::diagnose_static_six(
        &est,
        &val,
        HOLD,
        &["--model-out", p(&model), "--json", p(&json)],
    )
    .success();
    let file: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&model).unwrap()).unwrap();
    assert_eq!(file["friction"]["speed"].as_bool(), Some(true), "{file}");
    assert_eq!(
        crate::common::schema_errors(&file),
        Vec::<String>::new(),
        "{file}"
    );
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let after = report["error_after"].as_f64().unwrap();
    let run = hsid(&[
        "validate",
        "--model",
        p(&model),
        "--data",
        p(&val),
        "--skip",
        &hold,
    ])
    .success();
    let rmse = crate::common::validate_rmse(&run.stdout, "simulation fit on");
    println!("diagnosis {after:.5}");
    assert!((rmse - after).abs() < 0.05 * after, "{rmse} vs {after}");
}
