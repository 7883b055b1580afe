//! Friction on records written apart from the friction model: a rigid body `m v̇ = f − F_v v −
//! F_c sign(v) − F_0` that sticks while the force does not overcome the friction (the
//! stiction a continuous drive has and the fitted model, with its smoothed sign, does not),
//! integrated here with 20 semi-implicit Euler steps per sample, its position sampled with
//! white noise. The force is random levels held 150–400 samples, smoothed by a first-order
//! lag, so that the body reverses, stops and sticks.
//!
//! Truth: the body's parameters. The identified linear model without friction is the
//! reference the friction model has to beat on the held-out quarter.

#![allow(clippy::unwrap_used)]

use hsid_host::model::{Element, Record};
use hsid_host::refine::knots::SegmentCount;
use hsid_host::workflow::{IdentifyRequest, Syntax, identify_record};

/// The records' generator (xorshift, Box–Muller).
use crate::common::XorShift as Rng;

struct Body {
    mass: f64,
    viscous: f64,
    coulomb: f64,
    offset: f64,
}

/// `n` samples at `ts` of the body under a random-level force of amplitude `amp`: (force,
/// noisy position).
fn record(body: &Body, n: usize, ts: f64, amp: f64, noise: f64, seed: u64) -> (Vec<f64>, Vec<f64>) {
    let mut rng = Rng(seed);
    let (mut level, mut left, mut f) = (0.0, 0usize, 0.0);
    let (mut x, mut v) = (0.0f64, 0.0f64);
    let sub = 20;
    let h = ts / sub as f64;
    let mut u = Vec::with_capacity(n);
    let mut y = Vec::with_capacity(n);
    for _ in 0..n {
        if left == 0 {
            level = amp * (2.0 * rng.uniform() - 1.0);
            left = 150 + (rng.uniform() * 250.0) as usize;
        }
        left -= 1;
        f += (level - f) * 0.05;
        u.push(f);
        y.push(x + noise * rng.normal());
        for _ in 0..sub {
            let drive = f - body.offset;
            if v == 0.0 && drive.abs() <= body.coulomb {
                continue; // stuck
            }
            let sign = if v != 0.0 { v.signum() } else { drive.signum() };
            let v_next = v + h / body.mass * (drive - body.viscous * v - body.coulomb * sign);
            // Crossing zero velocity: the body stops there (and sticks unless the force wins).
            v = if v != 0.0 && v_next.signum() != v.signum() {
                0.0
            } else {
                v_next
            };
            x += v * h;
        }
    }
    (u, y)
}

fn request(lo: f64, hi: f64) -> IdentifyRequest {
    let mut r = IdentifyRequest::new(lo, hi, Syntax::Cli);
    r.integrating = true;
    r.detect_integrating = false;
    r.order = Some(1);
    r.element = Element::Static;
    r.segments = Some(SegmentCount::Fixed(1));
    r.friction = true;
    r
}

#[test]
fn a_body_with_coulomb_friction_and_stiction_is_read_back() {
    for (seed, body) in [
        (
            11u64,
            Body {
                mass: 2.0,
                viscous: 5.0,
                coulomb: 1.5,
                offset: 0.3,
            },
        ),
        (
            12,
            Body {
                mass: 40.0,
                viscous: 150.0,
                coulomb: 12.0,
                offset: -2.0,
            },
        ),
    ] {
        let ts = 1e-3;
        let amp = 4.0 * body.coulomb;
        let (u, y) = record(&body, 20_000, ts, amp, 1e-6, seed);
        let mut rec = Record::new(u, y).unwrap();
        rec.ts = Some(ts);
        let id = identify_record(&rec, &request(-amp, amp)).unwrap();
        let step = id.friction.as_ref().unwrap();
        let lines = id.lines().unwrap();
        assert!(step.reported, "{lines:#?}");
        // The identified linear model's equation error depends on the direction of motion.
        assert!(step.evidence.unwrap().fires(), "{lines:#?}");
        assert!(step.with < 0.5 * step.without, "{lines:#?}");
        let ph = step.physical.unwrap();
        for l in lines.iter().filter(|l| l.starts_with("--friction")) {
            eprintln!("seed {seed}: {l}");
        }
        let near = |v: f64, truth: f64, tol: f64, what: &str| {
            assert!(
                (v - truth).abs() <= tol,
                "{what} {v} vs {truth}: {lines:#?}"
            );
        };
        near(ph.mass, body.mass, 0.05 * body.mass, "mass");
        near(ph.viscous, body.viscous, 0.05 * body.viscous, "viscous");
        near(ph.coulomb, body.coulomb, 0.05 * body.coulomb, "Coulomb");
        near(ph.offset, body.offset, 0.05 * body.coulomb, "offset");
        // The file holds the model with friction.
        assert!(id.model_file().friction.is_some());
    }
}

#[test]
fn without_friction_the_step_finds_none_and_the_test_stays_quiet() {
    let body = Body {
        mass: 2.0,
        viscous: 5.0,
        coulomb: 0.0,
        offset: 0.0,
    };
    let ts = 1e-3;
    for seed in [21u64, 22, 23, 24] {
        let (u, y) = record(&body, 20_000, ts, 6.0, 1e-6, seed);
        let mut rec = Record::new(u, y).unwrap();
        rec.ts = Some(ts);
        let id = identify_record(&rec, &request(-6.0, 6.0)).unwrap();
        let step = id.friction.as_ref().unwrap();
        let lines = id.lines().unwrap();
        let ph = step.physical.unwrap();
        // A friction that is not there is read as (nearly) none.
        assert!(ph.coulomb.abs() < 0.05, "{lines:#?}");
        assert!(ph.offset.abs() < 0.05, "{lines:#?}");
        assert!((ph.mass - 2.0).abs() < 0.1, "{lines:#?}");
        let e = step.evidence.unwrap();
        eprintln!("no friction, seed {seed}: {e:?}");
        assert!(!e.fires(), "{e:?}: {lines:#?}");
    }
}

/// `hsid diagnose --integrating --nonlinearity static --segments 1 --order 1 --hold 0
/// --max-steps 0` of `(u, y)`: whether the base model gets the friction finding (the sign of
/// the model's increments, the body's velocity), and the verdict. With steps the diagnosis
/// adds an output map first (the friction, a function of the velocity, is one on the
/// increments), and the finding is not asked of a model with an output map.
fn diagnosed_friction(u: Vec<f64>, y: Vec<f64>, amp: f64) -> (bool, String) {
    use hsid_host::diagnose::{DiagnoseOptions, Finding, Validation, diagnose};
    use hsid_host::identify::IdentifyOptions;
    let id = IdentifyOptions {
        static_nonlinearity: true,
        order: Some(1),
        ..IdentifyOptions::uniform(-amp, amp, 1, 0)
    };
    let mut opts = DiagnoseOptions::new(
        hsid_host::integrating::increments_options(&id),
        Element::Static,
    );
    opts.increments = true;
    opts.max_steps = 0;
    let est = Record::new(u, y).unwrap().increments();
    let d = diagnose(&est, &Validation::Split(0.7), &opts).unwrap();
    let found = d.unexplained.iter().find_map(|f| match f {
        Finding::Friction { t, .. } => Some(*t),
        _ => None,
    });
    println!("friction finding: {found:?}; {}", d.verdict);
    (found.is_some(), d.verdict.to_string())
}

#[test]
fn the_diagnosis_of_the_increments_finds_the_friction_and_not_where_there_is_none() {
    let ts = 1e-3;
    let with = Body {
        mass: 2.0,
        viscous: 5.0,
        coulomb: 1.5,
        offset: 0.3,
    };
    let (u, y) = record(&with, 20_000, ts, 6.0, 1e-6, 11);
    let (found, verdict) = diagnosed_friction(u, y, 6.0);
    assert!(found, "{verdict}");
    let without = Body {
        coulomb: 0.0,
        offset: 0.0,
        ..with
    };
    let (u, y) = record(&without, 20_000, ts, 6.0, 1e-6, 21);
    let (found, verdict) = diagnosed_friction(u, y, 6.0);
    assert!(!found, "{verdict}");
}
