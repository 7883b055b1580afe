//! Integrating plants: a motor-position servo (voltage → position) with gearbox backlash on
//! the voltage, Table I on the voltage, identified with the integrator fixed at `z = 1` (the
//! stable part from the differenced position) against the simulator's truth.

#![allow(clippy::panic)]

use crate::common;

use hsid_host::choose::{self, Choices, Segments, best_model};
use hsid_host::identify::{HostModel, IdentifyError, IdentifyOptions, identify};
use hsid_host::integrating::{self, identify_integrating};
use hsid_host::model_file::ModelFile;
use hsid_host::sim::{Backlash, Lti, simulate, table1_excitation, variance, with_hold};
use rand::SeedableRng;
use rand_distr::{Distribution, StandardNormal};
use rand_pcg::Pcg64;

use common::{Scratch, hsid, p, schema_errors};

const U_MIN: f64 = -3.0;
const U_MAX: f64 = 3.0;
const HOLD: usize = 300;
/// Gap of the gearbox backlash, volts: `H_a(u) = u − GAP/2`, `H_d(u) = u + GAP/2`.
const GAP: f64 = 1.0;
/// Poles of the motor's stable part (electrical and mechanical).
const POLES: [f64; 2] = [0.85, 0.5];

/// The servo's position for a voltage record: backlash, `G₀`, then the integrator (the
/// simulator's transfer function with the pole at 1 in its denominator), with white position
/// noise at 20 dB of the clean position increments (`var Δy / var Δv = 100`). Returns the
/// position measured and the clean one.
fn servo(u: &[f64], seed: u64) -> (Vec<f64>, Vec<f64>) {
    let (p1, p2) = (POLES[0], POLES[1]);
    // (1 − p1 q⁻¹)(1 − p2 q⁻¹)(1 − q⁻¹).
    let den2 = [1.0, -(p1 + p2), p1 * p2];
    let den = vec![den2[0], den2[1] - den2[0], den2[2] - den2[1], -den2[2]];
    let Ok(plant) = Lti::new(vec![0.0, 0.04, 0.02], den) else {
        panic!("valid plant");
    };
    let Ok(one) = Lti::new(vec![1.0], vec![1.0]) else {
        panic!("valid noise model");
    };
    let mut element = Backlash::from_fns(|u| u - 0.5 * GAP, |u| u + 0.5 * GAP);
    let mut rng = Pcg64::seed_from_u64(seed);
    let Ok(sim) = simulate(u, &mut element, &plant, &one, None, 0..u.len(), &mut rng) else {
        panic!("noise-free simulation");
    };
    let clean = sim.y_clean;
    let dv = variance(&integrating::difference(&clean[HOLD..]));
    let sd = (dv / 100.0 / 2.0).sqrt();
    let y = clean
        .iter()
        .map(|c| {
            let e: f64 = StandardNormal.sample(&mut rng);
            c + sd * e
        })
        .collect();
    (y, clean)
}

fn record(seed: u64) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let mut rng = Pcg64::seed_from_u64(1000 + seed);
    let Ok(ex) = table1_excitation(5000, U_MIN, U_MAX, &mut rng) else {
        panic!("valid excitation");
    };
    let u = with_hold(HOLD, U_MIN, &ex);
    let (y, clean) = servo(&u, seed);
    (u, y, clean)
}

fn options() -> IdentifyOptions {
    let mut o = IdentifyOptions::uniform(U_MIN, U_MAX, 8, HOLD);
    o.order = Some(2);
    o
}

/// Where the piecewise-linear border `(knots, values)` first reaches `level`.
fn crossing(knots: &[f64], values: &[f64], level: f64) -> Option<f64> {
    (0..knots.len() - 1).find_map(|j| {
        let (a, b) = (values[j], values[j + 1]);
        ((a - level) * (b - level) <= 0.0 && a != b)
            .then(|| knots[j] + (level - a) / (b - a) * (knots[j + 1] - knots[j]))
    })
}

/// The horizontal distance between the borders at the level halfway between them at the
/// middle of the interval, input units.
fn gap(m: &HostModel) -> f64 {
    let mid = 0.5 * (U_MIN + U_MAX);
    let level = 0.5 * (m.border_asc_at(mid) + m.border_desc_at(mid));
    match (
        crossing(&m.knots_asc, &m.border_asc, level),
        crossing(&m.knots_desc, &m.border_desc, level),
    ) {
        (Some(a), Some(d)) => a - d,
        _ => f64::NAN,
    }
}

/// The paper's normalisation is refused on the position, and the refusal says how to
/// identify an integrating plant.
#[test]
fn refusal_names_the_route_for_an_integrating_plant() {
    let (u, y, _) = record(1);
    match identify(&u, &y, &options()) {
        Err(e @ IdentifyError::Core(_)) => {
            let text = e.to_string();
            assert!(
                text.contains("increments")
                    && text.contains("z = 1")
                    && text.contains("--integrating"),
                "{text}"
            );
        }
        Err(e) => panic!("unexpected refusal: {e}"),
        Ok(m) => panic!(
            "the position was identified as stable: poles {:?}",
            m.poles()
        ),
    }
}

/// With the integrator fixed and the stable part refined (the default of `hsid identify`), on
/// five seeds: the gap within 10 %, the poles of the stable part within 0.01, and the simulated increments of a fresh record closer to the truth than
/// the measured ones.
#[test]
fn motor_position_servo_with_gearbox_backlash() {
    for seed in 1..=5u64 {
        let (u, y, _) = record(seed);
        let m = match refined(&u, &y) {
            Ok(m) => m,
            Err(e) => panic!("seed {seed}: {e}"),
        };
        let g = gap(&m);
        assert!(
            (g - GAP).abs() <= 0.1 * GAP,
            "seed {seed}: gap {g:.4} (true {GAP})"
        );
        let mut p: Vec<f64> = m.poles().iter().map(|&(re, im)| re.hypot(im)).collect();
        p.sort_by(|a, b| b.total_cmp(a));
        for (est, truth) in p.iter().zip(POLES) {
            assert!(
                (est - truth).abs() <= 0.01,
                "seed {seed}: poles {:?} (true {POLES:?})",
                m.poles()
            );
        }
        let all = m.integrating_poles();
        assert_eq!(all.last(), Some(&(1.0, 0.0)), "seed {seed}");
        // A fresh record: the simulated increments closer to the clean ones than the
        // measured increments are (the position itself, simulated open loop, integrates any
        // error of the steady rate into a drift, and is no measure of the model).
        let (uv, yv, clean) = record(100 + seed);
        let sim = m.simulate(&uv[1..]);
        let rms = |a: &[f64], b: &[f64]| {
            (a.iter().zip(b).map(|(x, y)| (x - y) * (x - y)).sum::<f64>() / a.len() as f64).sqrt()
        };
        let truth = integrating::difference(&clean);
        let err = rms(&sim[HOLD..], &truth[HOLD..]);
        let noise = rms(&integrating::difference(&yv)[HOLD..], &truth[HOLD..]);
        eprintln!(
            "seed {seed}: gap {g:.4}, poles {:?}, increments RMS error {err:.5} (measurement {noise:.5})",
            m.poles()
        );
        assert!(
            err < noise,
            "seed {seed}: increments RMS error {err:.5}, measurement noise {noise:.5}"
        );
    }
}

/// The magnitudes of the stable part's poles, largest first.
fn pole_moduli(m: &HostModel) -> Vec<f64> {
    let mut p: Vec<f64> = m.poles().iter().map(|&(re, im)| re.hypot(im)).collect();
    p.sort_by(|a, b| b.total_cmp(a));
    p
}

/// Mean and sample standard deviation.
fn mean_sd(v: &[f64]) -> (f64, f64) {
    let n = v.len() as f64;
    let mean = v.iter().sum::<f64>() / n;
    let var = v.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / (n - 1.0);
    (mean, var.sqrt())
}

/// The stable part refined by the prediction-error method (the default of `hsid identify`),
/// at the given knots, horizons and order, from the increments of `(u, y)`.
fn refined(u: &[f64], y: &[f64]) -> Result<HostModel, String> {
    let choices = Choices {
        segments: Segments::Given,
        horizons: choose::Horizons::Given,
        ..Choices::default()
    };
    let (u1, dy, o) =
        integrating::increments_record(u, y, &options()).map_err(|e| e.to_string())?;
    let best = best_model(&u1, &dy, &o, &choices).map_err(|e| e.to_string())?;
    best.fit
        .map(|f| f.model)
        .ok_or_else(|| "not refined".to_string())
}

/// The spread of the stable part's estimate over twelve seeds, subspace and refined: each
/// pole's mean within 0.01 of the truth (no bias beyond the goal), the refined poles within
/// 0.01 on every seed (the subspace estimate's spread is too wide for that: its fast pole's
/// standard deviation over seeds is 0.0034 and seed 4 lands 0.0104 off), and the gap's mean
/// within 10 %.
#[test]
fn spread_of_the_stable_part_over_seeds() {
    let (mut sub, mut fine) = (Vec::new(), Vec::new());
    for seed in 1..=12u64 {
        let (u, y, _) = record(seed);
        let (s, r) = match (identify_integrating(&u, &y, &options()), refined(&u, &y)) {
            (Ok(s), Ok(r)) => (s, r),
            (Err(e), _) => panic!("seed {seed}: {e}"),
            (_, Err(e)) => panic!("seed {seed}: {e}"),
        };
        eprintln!(
            "seed {seed:>2}: subspace poles {:.4?} gap {:.4} | refined poles {:.4?} gap {:.4}",
            pole_moduli(&s),
            gap(&s),
            pole_moduli(&r),
            gap(&r)
        );
        sub.push(s);
        fine.push(r);
    }
    for (name, models) in [("subspace", &sub), ("refined", &fine)] {
        for (i, truth) in POLES.iter().enumerate() {
            let est: Vec<f64> = models.iter().map(|m| pole_moduli(m)[i]).collect();
            let (mean, sd) = mean_sd(&est);
            let worst = est.iter().map(|e| (e - truth).abs()).fold(0.0, f64::max);
            let se = sd / (est.len() as f64).sqrt();
            eprintln!(
                "{name}: pole {truth}: mean {mean:.5}, sd over seeds {sd:.5}, largest error {worst:.5}"
            );
            eprintln!("{name}: pole {truth}: standard error of the mean {se:.5}");
            assert!(
                (mean - truth).abs() <= 0.01,
                "{name}: pole {truth}: mean {mean:.5}"
            );
            // The goal, on every seed, for the estimate `hsid identify` gives by default.
            assert!(
                name == "subspace" || worst <= 0.01,
                "{name}: pole {truth}: largest error {worst:.5}"
            );
        }
        let gaps: Vec<f64> = models.iter().map(gap).collect();
        let (mean, sd) = mean_sd(&gaps);
        eprintln!("{name}: gap mean {mean:.4}, sd over seeds {sd:.4} (true {GAP})");
        assert!(
            (mean - GAP).abs() <= 0.1 * GAP,
            "{name}: gap mean {mean:.4}"
        );
    }
}

/// The `fit … %` figure of the simulation fit line of `hsid validate`'s output.
fn simulation_fit(stdout: &str) -> f64 {
    stdout
        .lines()
        .find(|l| l.starts_with("simulation fit on "))
        .and_then(|l| l.rsplit_once("fit "))
        .and_then(|(_, tail)| tail.trim_end_matches('%').trim().parse().ok())
        .unwrap_or(f64::NAN)
}

/// `hsid identify --integrating` on the servo's position: the stable part's poles within
/// 0.01 and the gap within 10 %; the model file records the integrator (the schema accepts
/// it) and `hsid validate` reads it on a fresh record's increments; a file without the key,
/// as every other model writes it, reads as not integrating.
#[test]
fn identify_integrating_writes_a_model_file_validate_reads() {
    let dir = Scratch::new("integrating");
    let (u, y, _) = record(1);
    let data = dir.write_uy("servo.csv", &u, &y);
    let json = dir.join("servo.json");
    let args = ["--segments", "8", "--order", "2", "--integrating"];
    let run = common::identify(&data, &[&args[..], &["--json", p(&json)]].concat()).success();
    assert!(run.stdout.contains("z = 1"), "{}", run.stdout);
    let file = match ModelFile::load(&json) {
        Ok(f) => f,
        Err(e) => panic!("{e}"),
    };
    assert!(file.integrating);
    let m = HostModel::from_json(&file);
    for (est, truth) in pole_moduli(&m).iter().zip(POLES) {
        assert!((est - truth).abs() <= 0.01, "poles {:?}", m.poles());
    }
    assert!((gap(&m) - GAP).abs() <= 0.1 * GAP, "gap {}", gap(&m));
    let text = std::fs::read_to_string(&json).unwrap_or_default();
    let mut value: serde_json::Value = serde_json::from_str(&text).unwrap_or_default();
    assert_eq!(value["integrating"], serde_json::json!(true), "{text}");
    assert_eq!(schema_errors(&value), Vec::<String>::new());
    // A fresh record, validated on its increments: the fit of the noise at 20 dB (≈ 90 %).
    let (uv, yv, _) = record(101);
    let fresh = dir.write_uy("fresh.csv", &uv, &yv);
    let v = hsid(&[
        "validate",
        "--model",
        p(&json),
        "--data",
        p(&fresh),
        "--skip",
        "300",
    ])
    .success();
    let fit = simulation_fit(&v.stdout);
    assert!(
        v.stdout.contains("increments") && fit > 85.0,
        "{}",
        v.stdout
    );
    // Without the key: not integrating, and the other models are written without it.
    if let Some(o) = value.as_object_mut() {
        o.remove("integrating");
    }
    let plain = ModelFile::from_json_str("plain.json", &value.to_string());
    assert!(matches!(&plain, Ok(f) if !f.integrating), "{plain:?}");
    let written = serde_json::to_value(m.to_json(None)).unwrap_or_default();
    assert!(written.get("integrating").is_none(), "{written}");
}

/// The `base model: order n, poles …` line of `hsid diagnose`'s report, as moduli.
fn base_pole_moduli(stdout: &str) -> Vec<f64> {
    let line = stdout
        .lines()
        .find(|l| l.starts_with("base model: "))
        .unwrap_or_default();
    let list = line.split_once("poles ").map_or("", |(_, t)| t);
    let mut m: Vec<f64> = list
        .split(", ")
        .filter_map(|p| {
            // `re` or `re±imj`.
            let p = p.trim().trim_end_matches('j');
            let cut = p.rfind(['+', '-']).filter(|&i| i > 0);
            let (re, im) = match cut {
                Some(i) => (p[..i].parse::<f64>().ok()?, p[i..].parse::<f64>().ok()?),
                None => (p.parse::<f64>().ok()?, 0.0),
            };
            Some(re.hypot(im))
        })
        .collect();
    m.sort_by(|a, b| b.total_cmp(a));
    m
}

/// `hsid diagnose` on the servo's position: without `--integrating` the data checks warn of
/// the integrating plant and name the route; with it, the stable part's poles within 0.01 of the truth, the report
/// saying its errors are of the increments, and the model file recording the integrator.
#[test]
fn diagnose_integrating_diagnoses_the_stable_part() {
    let dir = Scratch::new("diagnose-integrating");
    let (u, y, _) = record(2);
    let data = dir.write_uy("servo.csv", &u, &y);
    let base = [
        "diagnose",
        "--data",
        p(&data),
        "--nonlinearity",
        "backlash",
        "--umin",
        "-3",
        "--umax",
        "3",
        "--segments",
        "8",
        "--order",
        "2",
        "--hold",
        "300",
    ];
    // The warning comes from the base model: no step is needed to see it.
    let plain = hsid(&[&base[..], &["--max-steps", "0"]].concat()).success();
    assert!(
        plain.stdout.contains("warning [integrating]")
            && plain.stdout.contains("hsid diagnose --integrating"),
        "{}",
        plain.stdout
    );
    let json = dir.join("model.json");
    let run = hsid(&[&base[..], &["--integrating", "--model-out", p(&json)]].concat()).success();
    assert!(
        run.stdout.contains("--integrating: the stable part G0"),
        "{}",
        run.stdout
    );
    let moduli = base_pole_moduli(&run.stdout);
    assert_eq!(moduli.len(), 2, "{}", run.stdout);
    for (est, truth) in moduli.iter().zip(POLES) {
        assert!((est - truth).abs() <= 0.01, "poles {moduli:?}");
    }
    let file = match ModelFile::load(&json) {
        Ok(f) => f,
        Err(e) => panic!("{e}"),
    };
    assert!(file.integrating);
}

/// Without `--integrating`, the record is tested for a unit root first: the motor position is
/// found to integrate and identified as with the flag, with a line that says why; `--integrating
/// no` identifies it as given (the paper's normalisation then fails on it, as above). A stable
/// plant's record (the same servo's increments) is not routed.
#[test]
fn identify_finds_an_integrating_record_without_the_flag() {
    let dir = Scratch::new("integrating-found");
    let (u, y, _) = record(1);
    let data = dir.write_uy("servo.csv", &u, &y);
    let args = ["--segments", "8", "--order", "2"];
    let found = common::identify(&data, &args).success();
    let line = found.stdout.lines().next().unwrap_or_default().to_string();
    assert!(
        line.starts_with("the output integrates") && line.contains("--integrating no"),
        "{}",
        found.stdout
    );
    let flagged = common::identify(&data, &[&args[..], &["--integrating"]].concat()).success();
    let model = |out: &str| -> Vec<String> {
        out.lines()
            .filter(|l| l.starts_with("poles:") || l.starts_with("mu0 ="))
            .map(str::to_string)
            .collect()
    };
    assert_eq!(model(&found.stdout), model(&flagged.stdout));
    assert!(!model(&found.stdout).is_empty());
    let given = common::identify(&data, &[&args[..], &["--integrating", "no"]].concat());
    assert!(
        !given.stdout.contains("the output integrates"),
        "{}",
        given.stdout
    );
    // A detrended request keeps the record as given: detrending and the integrating route
    // exclude each other, so the route must not make the request contradict itself.
    let detrended = common::identify(&data, &[&args[..], &["--hold", "0", "--detrend"]].concat());
    assert!(
        !detrended.stdout.contains("the output integrates")
            && !detrended.stderr.contains("integrating plant"),
        "{}\n{}",
        detrended.stdout,
        detrended.stderr
    );
    // The increments of the same record are a stable plant's output: not routed.
    let dy: Vec<f64> = integrating::difference(&y);
    let stable = dir.write_uy("increments.csv", &u[1..], &dy);
    let run = common::identify(
        &stable,
        &["--segments", "8", "--order", "2", "--hold", "299"],
    );
    assert!(
        !run.stdout.contains("the output integrates"),
        "{}",
        run.stdout
    );
}
