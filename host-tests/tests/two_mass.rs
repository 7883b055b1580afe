//! Play between motor and load: two-mass drives with gear play, written here apart from the
//! model's simulator,
//!
//! ```text
//! J_m ω̇_m = K u − T_s − b_m ω_m,   J_l ω̇_l = T_s − b_l ω_l,
//! T_s = k dz(θ_m − θ_l) + c (ω_m − ω_l) [|θ_m − θ_l| > α],
//! ```
//!
//! `dz` the dead zone of half-width `α` (the gear play is `2α`), integrated by classical
//! Runge–Kutta on the four states `(θ_m, ω_m, θ_l, ω_l)` with 20 steps per sample, the input
//! held over each sample, the motor's speed sampled at `T_s = 1 ms` with white noise at 30 dB.
//! Inputs: random levels held 100–300 samples through a first-order lag, and white noise
//! through two first-order lags (pole 0.99 each).
//!
//! The gear contact is well damped (`ζ` from 0.35 to 0.5 in contact): a lightly damped contact
//! rattles, and its record then depends on where the integration steps fall (with `ζ ≈ 0.1`
//! the truth itself at 10 and 40 steps per sample differs from its 20-step record by 4–50
//! times the noise's energy), which no model fitted by simulation error can follow.
//!
//! **Units of the play.** The model's angle is the sum of the measured speed over samples
//! (output unit × sample), so a play of `2α` rad with the speed in rad/s is `2α / T_s` there;
//! the fitted gap times `T_s` is compared with the truth's `2α` in rad. Neither `K` nor the
//! inertias enter this mapping: the motor's angle is fixed by its measured speed alone.
//!
//! Baselines on the same estimation record: the linear output-error model
//! (`choose::linear_model`) and the input backlash
//! (`fit_hysteresis`: the play operator with straight borders in front of the linear model's
//! `G`, started from the linear model). The two-mass model is
//! started from the linear model's poles, and again from the input backlash's. Validation on a
//! fresh input and noise.

#![allow(clippy::unwrap_used, clippy::panic)]

use hsid_host::choose::Choices;
use hsid_host::choose::linear_model;
use hsid_host::hysteresis::{ElementFitOptions, Start, fit_hysteresis};
use hsid_host::identify::IdentifyOptions;
use hsid_host::model::MemoryElement;
use hsid_host::report::fit;
use hsid_host::sandwich::{TwoMassFit, TwoMassOptions, fit_two_mass, fit_two_mass_from_poles};

/// Sample time, s.
const TS: f64 = 1e-3;
/// Samples per record.
const LEN: usize = 4000;
/// Runge–Kutta steps per sample of the truth.
const SUB: usize = 20;

/// The records' generator (xorshift, Box–Muller).
use crate::common::XorShift as Rng;

/// The true drive, SI units.
#[derive(Clone, Copy, Debug)]
struct Drive {
    jm: f64,
    jl: f64,
    k_motor: f64,
    bm: f64,
    bl: f64,
    stiffness: f64,
    damping: f64,
    /// Half the gear play, rad.
    alpha: f64,
}

#[derive(Clone, Copy, Debug)]
enum Input {
    Levels,
    FilteredNoise,
}

struct Rec {
    u: Vec<f64>,
    y: Vec<f64>,
    clean: Vec<f64>,
    /// The motor angle's range, rad.
    angle_range: f64,
}

fn input(kind: Input, rng: &mut Rng) -> Vec<f64> {
    let mut u = Vec::with_capacity(LEN);
    match kind {
        Input::Levels => {
            let (mut level, mut left, mut f) = (0.0, 0usize, 0.0);
            for _ in 0..LEN {
                if left == 0 {
                    level = 2.0 * rng.uniform() - 1.0;
                    left = 100 + (rng.uniform() * 200.0) as usize;
                }
                left -= 1;
                f += (level - f) * 0.05;
                u.push(f);
            }
        }
        Input::FilteredNoise => {
            let (mut a, mut b) = (0.0, 0.0);
            for _ in 0..LEN {
                a += (rng.normal() - a) * 0.01;
                b += (a - b) * 0.01;
                u.push(12.0 * b);
            }
        }
    }
    u
}

impl Drive {
    /// `(θ_m, ω_m, θ_l, ω_l)'`.
    fn derivative(&self, x: [f64; 4], u: f64) -> [f64; 4] {
        let [tm, wm, tl, wl] = x;
        let d = tm - tl;
        let ts = if d.abs() > self.alpha {
            self.stiffness * (d - self.alpha * d.signum()) + self.damping * (wm - wl)
        } else {
            0.0
        };
        [
            wm,
            (self.k_motor * u - ts - self.bm * wm) / self.jm,
            wl,
            (ts - self.bl * wl) / self.jl,
        ]
    }

    fn record(&self, kind: Input, seed: u64) -> Rec {
        let mut rng = Rng(seed);
        let u = input(kind, &mut rng);
        let h = TS / SUB as f64;
        let mut x = [0.0f64; 4];
        let mut clean = Vec::with_capacity(LEN);
        let (mut lo, mut hi) = (0.0f64, 0.0f64);
        let step = |x: [f64; 4], k: [f64; 4], s: f64| {
            [
                x[0] + s * k[0],
                x[1] + s * k[1],
                x[2] + s * k[2],
                x[3] + s * k[3],
            ]
        };
        for &ut in &u {
            clean.push(x[1]);
            lo = lo.min(x[0]);
            hi = hi.max(x[0]);
            for _ in 0..SUB {
                let k1 = self.derivative(x, ut);
                let k2 = self.derivative(step(x, k1, h / 2.0), ut);
                let k3 = self.derivative(step(x, k2, h / 2.0), ut);
                let k4 = self.derivative(step(x, k3, h), ut);
                for i in 0..4 {
                    x[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
                }
            }
        }
        let rms = (clean.iter().map(|v| v * v).sum::<f64>() / LEN as f64).sqrt();
        let sigma = rms * 10f64.powf(-30.0 / 20.0);
        let y = clean.iter().map(|v| v + sigma * rng.normal()).collect();
        Rec {
            u,
            y,
            clean,
            angle_range: hi - lo,
        }
    }
}

/// What one drive gives: the fit, the NRMSEs on validation (two-mass, linear, backlash,
/// floor) and the estimation record's motor angle range.
struct Outcome {
    fit: TwoMassFit,
    /// The fit started from the input backlash's poles instead.
    from_backlash: TwoMassFit,
    two_mass: f64,
    linear: f64,
    backlash: f64,
    floor: f64,
    angle_range: f64,
    validation_u: Vec<f64>,
    validation_y: Vec<f64>,
}

fn run(drive: &Drive, kind: Input, seed: u64) -> Outcome {
    let est = drive.record(kind, seed);
    let val = drive.record(kind, seed + 1000);
    let lo = 1.2
        * est
            .u
            .iter()
            .chain(&val.u)
            .fold(0.0f64, |m, v| m.max(v.abs()));
    let base = IdentifyOptions::uniform(-lo, lo, 1, 0);
    let linear = linear_model(&est.u, &est.y, &base, &Choices::default()).unwrap();
    let backlash = fit_hysteresis(
        &est.u,
        &est.y,
        &linear.model,
        Start::Static,
        &ElementFitOptions::new(MemoryElement::Play),
    )
    .unwrap();
    let two = fit_two_mass(&est.u, &est.y, &linear.model, &TwoMassOptions::default()).unwrap();
    let from_backlash = fit_two_mass_from_poles(
        &est.u,
        &est.y,
        &backlash.model.poles(),
        &TwoMassOptions::default(),
    )
    .unwrap();
    let nrmse = |sim: &[f64]| fit(&val.y, sim).nrmse;
    Outcome {
        two_mass: nrmse(&two.simulate(&val.u)),
        linear: nrmse(&at_rest(&linear.model, &val.u)),
        backlash: nrmse(&backlash.simulate(&val.u)),
        floor: nrmse(&val.clean),
        angle_range: est.angle_range,
        validation_u: val.u.clone(),
        validation_y: val.y.clone(),
        fit: two,
        from_backlash,
    }
}

/// The linear model's output for `u` from rest at `u = 0`, as the drive starts (its own
/// simulation starts at rest at its offset `μ0`): a run-in of zeros, dropped.
fn at_rest(model: &hsid_host::identify::HostModel, u: &[f64]) -> Vec<f64> {
    let run_in = 10_000;
    let mut padded = vec![0.0; run_in];
    padded.extend_from_slice(u);
    model.simulate_from(&padded, 0.0).split_off(run_in)
}

fn report(name: &str, drive: &Drive, o: &Outcome) {
    let m = &o.fit.model;
    eprintln!(
        "{name}: gap {:.4e} rad (true {:.4e}, std {:.1e}), r {:.3} (true {:.3}), resonance {:.1} rad/s; validation NRMSE two-mass {:.4}, linear {:.4}, input backlash {:.4}, floor {:.4} ({:.3}x floor); {} starts, {} it",
        o.fit.gap() * TS,
        2.0 * drive.alpha,
        o.fit.gap_std().unwrap_or(f64::NAN) * TS,
        m.inertia_ratio,
        drive.jl / drive.jm,
        m.resonance() / TS,
        o.two_mass,
        o.linear,
        o.backlash,
        o.floor,
        o.two_mass / o.floor,
        o.fit.starts,
        o.fit.iterations,
    );
    eprintln!(
        "{name}: from the input backlash's poles: gap {:.4e} rad (std {:.1e}), validation NRMSE {:.4}",
        o.from_backlash.gap() * TS,
        o.from_backlash.gap_std().unwrap_or(f64::NAN) * TS,
        fit(&o.validation_y, &o.from_backlash.simulate(&o.validation_u)).nrmse,
    );
}

const DRIVES: [(&str, Drive, Input, u64); 2] = [
    (
        "equal inertias, levels",
        Drive {
            jm: 1.0,
            jl: 1.0,
            k_motor: 1.0,
            bm: 2.0,
            bl: 2.0,
            stiffness: 2e4,
            damping: 100.0,
            alpha: 0.005,
        },
        Input::Levels,
        1,
    ),
    (
        "load 3x motor, filtered noise",
        Drive {
            jm: 1.0,
            jl: 3.0,
            k_motor: 1.0,
            bm: 1.0,
            bl: 4.0,
            stiffness: 4e4,
            damping: 200.0,
            alpha: 0.005,
        },
        Input::FilteredNoise,
        2,
    ),
];

#[test]
fn the_play_between_motor_and_load_is_read_back_within_ten_percent() {
    for (name, drive, kind, seed) in DRIVES {
        let o = run(&drive, kind, seed);
        report(name, &drive, &o);
        let truth = 2.0 * drive.alpha;
        let gap = o.fit.gap() * TS;
        assert!(
            (gap - truth).abs() <= 0.1 * truth,
            "{name}: gap {gap} vs {truth}"
        );
        assert!(
            o.two_mass < o.linear,
            "{name}: {} vs linear {}",
            o.two_mass,
            o.linear
        );
        assert!(
            o.two_mass < o.backlash,
            "{name}: {} vs backlash {}",
            o.two_mass,
            o.backlash
        );
    }
}

#[test]
fn a_drive_without_play_gets_a_small_gap() {
    let drive = Drive {
        jm: 1.0,
        jl: 2.0,
        k_motor: 1.0,
        bm: 2.0,
        bl: 2.0,
        stiffness: 3e4,
        damping: 100.0,
        alpha: 0.0,
    };
    let o = run(&drive, Input::Levels, 3);
    report("no play", &drive, &o);
    let gap = o.fit.gap() * TS;
    let std = o.fit.gap_std().unwrap_or(f64::INFINITY) * TS;
    for (from, gap, std) in [
        ("linear", gap, std),
        (
            "input backlash",
            o.from_backlash.gap() * TS,
            o.from_backlash.gap_std().unwrap_or(f64::INFINITY) * TS,
        ),
    ] {
        assert!(
            gap <= 2.0 * std || gap < 0.01 * o.angle_range,
            "from the {from} model: gap {gap} rad, std {std}, angle range {}",
            o.angle_range
        );
    }
}

/// `hsid diagnose` on the drives' records with the defaults a user would give (a static
/// element, one segment on the inputs' range, no order): the diagnosis itself proposes the
/// play between motor and load, and the step's play is the truth's within 10 %; on the drive
/// without play it does not add it.
#[test]
fn the_diagnosis_adds_the_play_between_motor_and_load() {
    use hsid_host::diagnose::{DiagnoseOptions, Effect, Validation, diagnose};
    use hsid_host::model::{Element, Record};
    let no_play = Drive {
        alpha: 0.0,
        ..DRIVES[0].1
    };
    for (name, drive, kind, seed, play) in [
        (DRIVES[0].0, DRIVES[0].1, DRIVES[0].2, DRIVES[0].3, true),
        ("no play", no_play, Input::Levels, 3, false),
    ] {
        let est = drive.record(kind, seed);
        let val = drive.record(kind, seed + 1000);
        let (lo, hi) = est
            .u
            .iter()
            .chain(&val.u)
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
                (a.min(v), b.max(v))
            });
        let opts = DiagnoseOptions::new(IdentifyOptions::uniform(lo, hi, 1, 0), Element::Static);
        let record = Record::from_samples(est.u.iter().copied().zip(est.y.iter().copied()));
        let validation = Validation::Separate {
            record: Record::from_samples(val.u.iter().copied().zip(val.y.iter().copied())),
            skip: 0,
        };
        let d = diagnose(&record, &validation, &opts).unwrap();
        if std::env::var_os("HSID_TWO_MASS_REPORT").is_some() {
            eprintln!("{}", hsid_host::diagnose::report::text(&d));
        }
        let named: Vec<&str> = d.steps.iter().map(|s| s.effect.name()).collect();
        let floor = fit(&val.y, &val.clean).rmse;
        eprintln!(
            "{name}: diagnosis {named:?}, validation RMSE {:.4e} → {:.4e} (floor {floor:.4e})",
            d.before.rmse,
            d.steps.last().map_or(d.before.rmse, |s| s.error_after),
        );
        let step = d.steps.iter().find(|s| s.effect == Effect::PlayBetween);
        if !play {
            assert!(step.is_none(), "{name}: {named:?}");
            continue;
        }
        let step = step.unwrap_or_else(|| panic!("{name}: {named:?}"));
        let tm = d.model.two_mass.as_ref().unwrap();
        let gap = tm.gap() * TS;
        eprintln!(
            "{name}: step {:.4e} → {:.4e}; gap {gap:.4e} rad (true {:.4e}, std {:.1e})",
            step.error_before,
            step.error_after,
            2.0 * drive.alpha,
            tm.gap_std().unwrap_or(f64::NAN) * TS
        );
        assert!(
            (gap - 2.0 * drive.alpha).abs() <= 0.1 * 2.0 * drive.alpha,
            "{name}: gap {gap}"
        );
        assert!(
            step.error_after < 1.2 * floor,
            "{name}: {}",
            step.error_after
        );
    }
}

/// The command line's face of the step: `hsid diagnose` on the first drive's records with its
/// sample time and units names the play between motor and load, the page reads the drive in
/// rad/s and rad, the JSON report carries it, and `--model-out` says the file holds the
/// Hammerstein part only.
#[test]
fn the_command_line_reports_the_play_between_motor_and_load() {
    use crate::common::{Scratch, hsid, p};
    let dir = Scratch::new("two_mass_cli");
    let (_, drive, kind, seed) = DRIVES[0];
    let (est, val) = (drive.record(kind, seed), drive.record(kind, seed + 1000));
    let est_csv = dir.write_uy("est.csv", &est.u, &est.y);
    let val_csv = dir.write_uy("val.csv", &val.u, &val.y);
    let (json, page, model) = (
        dir.join("diagnosis.json"),
        dir.join("diagnosis.html"),
        dir.join("model.json"),
    );
    let lo = est
        .u
        .iter()
        .chain(&val.u)
        .fold(f64::INFINITY, |m, &v| m.min(v));
    let hi = est
        .u
        .iter()
        .chain(&val.u)
        .fold(f64::NEG_INFINITY, |m, &v| m.max(v));
    let (lo, hi) = (lo.to_string(), hi.to_string());
    let run = hsid(&[
        "diagnose",
        "--data",
        p(&est_csv),
        "--validation",
        p(&val_csv),
        "--umin",
        &lo,
        "--umax",
        &hi,
        "--hold",
        "0",
        "--nonlinearity",
        "static",
        "--segments",
        "1",
        "--ts",
        "0.001",
        "--input-unit",
        "V",
        "--output-unit",
        "rad/s",
        "--json",
        p(&json),
        "--html",
        p(&page),
        "--model-out",
        p(&model),
    ])
    .success();
    assert!(
        run.stdout.contains("step 1: play_between"),
        "{}",
        run.stdout
    );
    assert!(
        run.stdout
            .contains("holds the Hammerstein part; play_between only in the JSON report"),
        "{}",
        run.stdout
    );
    let html = std::fs::read_to_string(&page).unwrap();
    let lead = "A two-mass drive with play between motor and load replaces the linear part";
    let at = html
        .find(lead)
        .unwrap_or_else(|| panic!("no two-mass lead"));
    let sentence = &html[at..(at + 400).min(html.len())];
    println!("page: {sentence}");
    assert!(
        sentence.contains("rad/s × s between motor and load"),
        "{sentence}"
    );
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let gap = report["model_after"]["two_mass"]["gap"].as_f64().unwrap();
    // The gap in the model's units (rad/s × samples) is the truth's 0.01 rad / 1 ms.
    assert!(
        (gap * TS - 2.0 * drive.alpha).abs() < 0.1 * 2.0 * drive.alpha,
        "{gap}"
    );
}
