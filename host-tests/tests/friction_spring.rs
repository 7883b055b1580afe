//! Friction on a plant that does not integrate, written apart from the friction model: a mass
//! on a spring with viscous damping and Coulomb friction, its position measured, `m ẍ = u − k x
//! − c ẋ − F_c tanh(ẋ / ε)` with `m = 0.01`, `k = 1`, `c = 0.06` (10 rad/s, damping 0.3; unit
//! static gain), `F_c = 0.15` (15 % of the input's half-range) and `ε = 0.02` (under 1 % of
//! the typical speed: the mass sticks while the spring and the input do not overcome the
//! friction), integrated here by RK4 at 20 steps a sample (`ts = 0.01 s`). The input is
//! smoothed random levels in `[−1, 1]` after a hold at −1; white noise at 30 dB.
//!
//! Truth: `F_c / k`, the force in the element's output's units (`G(1) = 1`). The sampled
//! model's sign is smoothed over at least the velocity one sample of the force gives, so it
//! creeps where the mass sticks, and reads the force 3 % low on the noise-free records
//! (0.146, 0.155); on the noisy records the fit must land where the noise-free one does (at 30
//! dB the regressions that start the fit read half the force, and a fit from them alone
//! stopped at 0.074).
//!
//! `hsid diagnose` of the same records (static element, order 2) adds friction as a step
//! and reads the force, and does neither on the same mass without friction (seeds 3, 4).

#![allow(clippy::panic, clippy::unwrap_used)]

use crate::common::{hsid, p};
use hsid_host::diagnose::{Effect, Finding, Validation, diagnose};
use hsid_host::model::{Element, Record};
use hsid_host::workflow::{IdentifyRequest, Syntax, identify_record};

/// Half the input range.
const RANGE: f64 = 1.0;
/// Samples of the hold at `−RANGE` opening every record.
const HOLD: usize = 100;
/// Samples after the hold.
const LEN: usize = 3000;
/// Output SNR in dB.
const SNR_DB: f64 = 30.0;
/// The Coulomb force.
const COULOMB: f64 = 0.15;

/// The records' own generator (SplitMix64, Box–Muller).
use crate::common::SplitMix as Rng;

/// `(u, measured y, clean y)`: the hold, then levels held 20–80 samples through a first-order
/// low-pass; the mass integrated by RK4 with the input held over each sample.
fn simulate(seed: u64, coulomb: f64) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let mut rng = Rng(seed.wrapping_mul(0x2545_F491_4F6C_DD1D) ^ 0xF1C7);
    let mut u = vec![-RANGE; HOLD];
    let mut s = -RANGE;
    while u.len() < HOLD + LEN {
        let level = -RANGE + 2.0 * RANGE * rng.uniform();
        let hold = 20 + (rng.uniform() * 61.0) as usize;
        for _ in 0..hold {
            s = 0.8 * s + 0.2 * level;
            u.push(s);
        }
    }
    u.truncate(HOLD + LEN);
    let (m, k, c, eps) = (0.01, 1.0, 0.06, 0.02);
    let accel = |x: f64, v: f64, f: f64| (f - k * x - c * v - coulomb * (v / eps).tanh()) / m;
    let steps = 20;
    let h = 0.01 / steps as f64;
    // At rest at the hold's input (the friction band around it is where the mass sits).
    let (mut x, mut v) = (-RANGE / k, 0.0);
    let clean: Vec<f64> = u
        .iter()
        .map(|&f| {
            let y = x;
            for _ in 0..steps {
                let (k1x, k1v) = (v, accel(x, v, f));
                let (k2x, k2v) = (
                    v + 0.5 * h * k1v,
                    accel(x + 0.5 * h * k1x, v + 0.5 * h * k1v, f),
                );
                let (k3x, k3v) = (
                    v + 0.5 * h * k2v,
                    accel(x + 0.5 * h * k2x, v + 0.5 * h * k2v, f),
                );
                let (k4x, k4v) = (v + h * k3v, accel(x + h * k3x, v + h * k3v, f));
                x += h / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x);
                v += h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
            }
            y
        })
        .collect();
    let n = clean.len() as f64;
    let mean = clean.iter().sum::<f64>() / n;
    let var = clean.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n;
    let sd = (var / 10f64.powf(SNR_DB / 10.0)).sqrt();
    let y = clean.iter().map(|v| v + sd * rng.normal()).collect();
    (u, y, clean)
}

/// `identify --nonlinearity static --order 2 --hold 100 --friction` on `(u, y)`: the
/// friction step's Coulomb force and its held-out NRMSE without and with friction.
fn friction_of(u: Vec<f64>, y: Vec<f64>) -> (f64, f64, f64, Vec<String>) {
    let mut r = IdentifyRequest::new(-RANGE, RANGE, Syntax::Cli);
    r.element = Element::Static;
    r.choose_element = false;
    r.order = Some(2);
    r.friction = true;
    let rec = Record::new(u, y).unwrap().with_hold(HOLD);
    let id = identify_record(&rec, &r).unwrap();
    let lines = id.lines().unwrap();
    let step = id.friction.as_ref().unwrap();
    assert!(step.reported, "{lines:#?}");
    let fc = step.fit.model.friction.coulomb;
    (fc, step.without, step.with, lines)
}

#[test]
fn a_mass_on_a_spring_with_coulomb_friction_reads_its_force_through_the_noise() {
    for seed in [1, 2] {
        let (u, y, clean) = simulate(seed, COULOMB);
        let (fc_clean, ..) = friction_of(u.clone(), clean);
        let (fc, without, with, lines) = friction_of(u, y);
        println!(
            "seed {seed}: Coulomb {fc:.4} (noise-free record {fc_clean:.4}, true {COULOMB}); held-out NRMSE {without:.4} -> {with:.4}"
        );
        assert!((fc_clean - COULOMB).abs() < 0.05 * COULOMB, "{fc_clean}");
        assert!((fc - COULOMB).abs() < 0.2 * COULOMB, "{fc}: {lines:#?}");
        assert!(with < 0.6 * without, "{without} -> {with}: {lines:#?}");
    }
}

/// What the diagnosis of a record did about friction.
struct Diagnosed {
    /// The Coulomb force of its friction step, if it took one.
    coulomb: Option<f64>,
    /// The validation RMSE before and after its steps.
    before: f64,
    after: f64,
    /// It ended with the friction finding outside the catalog.
    found: bool,
    verdict: String,
}

/// `hsid diagnose --nonlinearity static --order 2` of the record from `seed`, validated on
/// the one from `seed + 1000`.
fn diagnosed(seed: u64, coulomb: f64) -> Diagnosed {
    let (u, y, _) = simulate(seed, coulomb);
    let (uv, yv, _) = simulate(seed + 1000, coulomb);
    let validation = Validation::Separate {
        record: Record::new(uv, yv).unwrap(),
        skip: HOLD,
    };
    let opts = crate::common::static_order_two(RANGE, HOLD);
    let d = diagnose(&Record::new(u, y).unwrap(), &validation, &opts).unwrap();
    let stepped = d.steps.iter().any(|s| s.effect == Effect::Friction);
    Diagnosed {
        coulomb: stepped
            .then(|| d.model.friction.as_ref().map(|f| f.friction.coulomb))
            .flatten(),
        before: d.before.rmse,
        after: d.after.rmse,
        found: d
            .unexplained
            .iter()
            .any(|f| matches!(f, Finding::Friction { .. })),
        verdict: d.verdict.to_string(),
    }
}

#[test]
fn the_diagnosis_adds_the_friction_and_not_where_there_is_none() {
    for seed in [1, 2] {
        let d = diagnosed(seed, COULOMB);
        println!(
            "seed {seed}, friction {COULOMB}: Coulomb {:?}, validation RMSE {:.4} -> {:.4}: {}",
            d.coulomb, d.before, d.after, d.verdict
        );
        let fc = d
            .coulomb
            .unwrap_or_else(|| panic!("seed {seed}: {}", d.verdict));
        assert!((fc - COULOMB).abs() < 0.2 * COULOMB, "seed {seed}: {fc}");
        assert!(d.after < 0.8 * d.before, "seed {seed}: {}", d.verdict);
        assert!(!d.found, "seed {seed}: {}", d.verdict);
    }
    for seed in [3, 4] {
        let d = diagnosed(seed, 0.0);
        println!("seed {seed}, no friction: {}", d.verdict);
        assert!(
            d.coulomb.is_none() && !d.found,
            "seed {seed}: {}",
            d.verdict
        );
    }
}

/// The command line's face of the step: `hsid diagnose --model-out` writes the model with its
/// friction, and `hsid validate` simulates that file to the diagnosis's own validation error.
#[test]
fn the_diagnosed_model_file_holds_the_friction_and_validates_as_diagnosed() {
    let dir = crate::common::Scratch::new("friction_spring_cli");
    let (u, y, _) = simulate(1, COULOMB);
    let (uv, yv, _) = simulate(1001, COULOMB);
    let est = dir.write_uy("est.csv", &u, &y);
    let val = dir.write_uy("val.csv", &uv, &yv);
    let (model, json) = (dir.join("model.json"), dir.join("diagnosis.json"));
    let page = dir.join("diagnosis.html");
    let hold = HOLD.to_string();
    crate::common::diagnose_static_six(
        &est,
        &val,
        HOLD,
        &[
            "--model-out",
            p(&model),
            "--json",
            p(&json),
            "--html",
            p(&page),
        ],
    )
    .success();
    // The page says the friction is part of the final model, and reads that model's `G`.
    let html = std::fs::read_to_string(&page).unwrap();
    assert!(
        html.contains("Coulomb friction and an offset on its velocity are fed back"),
        "the page does not name the friction"
    );
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let added: Vec<&str> = report["effects"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|e| e["added"].as_bool() == Some(true))
        .filter_map(|e| e["name"].as_str())
        .collect();
    assert!(added.contains(&"friction"), "{added:?}");
    let file: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&model).unwrap()).unwrap();
    let coulomb = file["friction"]["coulomb"].as_f64().unwrap();
    assert!((coulomb - COULOMB).abs() < 0.2 * COULOMB, "{coulomb}");
    let validate = ["validate", "--model", p(&model), "--data", p(&val)];
    let run = hsid(&[&validate[..], &["--skip", &hold]].concat()).success();
    let rmse_of = |start: &str| crate::common::validate_rmse(&run.stdout, start);
    let after = report["error_after"].as_f64().unwrap();
    println!("diagnosis: friction {coulomb:.4}, validation RMSE {after:.4}");
    let rmse = rmse_of("simulation fit on");
    assert!((rmse - after).abs() < 0.05 * after, "{rmse} vs {after}");
    // The noise model the diagnosis added last predicts the residual of that simulation.
    if let Some(predicted) = report["prediction_error_after"].as_f64() {
        let rmse = rmse_of("one-step prediction fit on");
        println!("diagnosis: one-step prediction RMSE {predicted:.4}");
        assert!(
            (rmse - predicted).abs() < 0.05 * predicted,
            "{rmse} vs {predicted}"
        );
    }
}
