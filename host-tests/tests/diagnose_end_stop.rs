//! An end stop the data check cannot see: a mass on a spring driven against a mechanical stop
//! (inelastic: the position held at the stop while the force pushes it there), read by a
//! sensor with white noise. No sample sits exactly at an extreme, so the data check finds no
//! saturation; the diagnosis finds the stop where the model's simulation goes beyond the level
//! the output stays at (the evidence of an output nonlinearity), and scores the end stop at
//! that level (the output clamped, or the state held at rest there, the level fitted to the
//! simulation of the model fitted without the inner hold-out) beside the output maps.
//! Measured (seed: stop, level found, setting, validation NRMSE / noise floor before → after):
//! 1: 2.585, evidence 2.528, the 8-segment map, 2.53 → 1.65; 2: 1.737, 1.711, the end stop,
//! 3.78 → 1.37.
//!
//! The records come from this file's own simulation: `ẍ = ω² (u − x) − 2ζω ẋ` (unit static
//! gain) by semi-implicit Euler with 20 substeps per sample, the stop at the 93 % quantile of
//! the estimation record's free position, smoothed random levels after a hold at `−RANGE`
//! (not Table I), white noise at 30 dB after the stop. The same mass without the stop is the
//! control: there the diagnosis adds no end stop. About 30 s in release.

#![allow(clippy::panic)]

use hsid_host::diagnose::{DiagnoseOptions, Diagnosis, Effect, Evidence, Validation, diagnose};
use hsid_host::model::Record;
use hsid_host::report::fit;

use crate::common::SplitMix as Rng;

/// Half the input range.
const RANGE: f64 = 3.0;
/// Samples of the hold at `−RANGE` opening every record.
const HOLD: usize = 100;
/// Samples after the hold.
const LEN: usize = 3000;
/// Natural frequency (rad/s), damping ratio, sample time (s).
const OMEGA: f64 = 3.0;
const ZETA: f64 = 0.3;
const TS: f64 = 0.05;
/// Output SNR in dB.
const SNR_DB: f64 = 30.0;

/// The hold, then random levels in `[−RANGE, RANGE]` held 20 to 79 samples, smoothed by a
/// first-order low-pass.
fn command(rng: &mut Rng) -> Vec<f64> {
    let mut u = vec![-RANGE; HOLD];
    let mut s = -RANGE;
    while u.len() < HOLD + LEN {
        let level = -RANGE + 2.0 * RANGE * rng.uniform();
        let hold = 20 + (rng.uniform() * 60.0) as usize;
        for _ in 0..hold {
            s = 0.8 * s + 0.2 * level;
            u.push(s);
        }
    }
    u.truncate(HOLD + LEN);
    u
}

/// The position sampled every `TS`, at rest at `u[0]`, against the stop at `stop` (if any).
fn position(u: &[f64], stop: Option<f64>) -> Vec<f64> {
    let h = TS / 20.0;
    let (mut x, mut v) = (u[0], 0.0);
    u.iter()
        .map(|&f| {
            let y = x;
            for _ in 0..20 {
                v += h * (OMEGA * OMEGA * (f - x) - 2.0 * ZETA * OMEGA * v);
                x += h * v;
                if let Some(l) = stop
                    && x >= l
                {
                    x = l;
                    v = v.min(0.0);
                }
            }
            y
        })
        .collect()
}

/// A record: the command, the measured position, the noise-free position.
struct Simulated {
    u: Vec<f64>,
    y: Vec<f64>,
    y_clean: Vec<f64>,
}

/// The record of `seed` against the stop at `stop`, its noise's level `sd`.
fn simulate(seed: u64, stop: Option<f64>, sd: f64) -> Simulated {
    let mut rng = Rng(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ 0x0E5D_0F57);
    let u = command(&mut rng);
    let y_clean = position(&u, stop);
    let y = y_clean.iter().map(|v| v + sd * rng.normal()).collect();
    Simulated { u, y, y_clean }
}

/// The stop (the 93 % quantile of the free position after the hold) and the noise's level
/// (30 dB below the free position's variance), both from the estimation seed.
fn stop_and_noise(seed: u64) -> (f64, f64) {
    let mut rng = Rng(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ 0x0E5D_0F57);
    let free = position(&command(&mut rng), None);
    let mut after = free[HOLD..].to_vec();
    after.sort_by(f64::total_cmp);
    let stop = after[(0.93 * (after.len() - 1) as f64) as usize];
    let n = after.len() as f64;
    let mean = after.iter().sum::<f64>() / n;
    let var = after.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n;
    (stop, (var / 10f64.powf(SNR_DB / 10.0)).sqrt())
}

fn options() -> DiagnoseOptions {
    crate::common::static_order_two(RANGE, HOLD)
}

/// The diagnosis of the record of `seed` (with the stop or without) validated on the one of
/// `seed + 1000`, with the validation's noise floor (NRMSE of the noise-free position).
fn run(seed: u64, with_stop: bool) -> (Diagnosis, f64, f64) {
    let (stop, sd) = stop_and_noise(seed);
    let stop = with_stop.then_some(stop);
    let est = simulate(seed, stop, sd);
    let val = simulate(seed + 1000, stop, sd);
    let floor = fit(&val.y[HOLD..], &val.y_clean[HOLD..]).nrmse;
    let records = Record::new(val.u, val.y).and_then(|v| Ok((Record::new(est.u, est.y)?, v)));
    let (est, val) = match records {
        Ok(r) => r,
        Err(e) => panic!("seed {seed}: {e}"),
    };
    let validation = Validation::Separate {
        record: val,
        skip: HOLD,
    };
    match diagnose(&est, &validation, &options()) {
        Ok(d) => (d, floor, stop.unwrap_or(f64::NAN)),
        Err(e) => panic!("seed {seed}: {e}"),
    }
}

#[test]
fn a_mechanical_stop_under_noise_is_found_and_the_output_nonlinearity_added() {
    for seed in [1, 2] {
        let (d, floor, stop) = run(seed, true);
        if std::env::var_os("HSID_SHOW").is_some() {
            println!("{}", hsid_host::diagnose::report::text(&d));
        }
        let named: Vec<&str> = d.steps.iter().map(|s| s.effect.name()).collect();
        let stop_fit = d.model.structure.end_stop;
        let level = stop_fit.and_then(|s| s.levels.ceiling);
        println!(
            "seed {seed}: stop {stop:.4}, found {level:?} (held: {:?}); steps {named:?}; validation NRMSE {:.4} -> {:.4} (noise floor {floor:.4}: {:.2}x -> {:.2}x)",
            stop_fit.map(|s| s.held),
            d.before.nrmse,
            d.after.nrmse,
            d.before.nrmse / floor,
            d.after.nrmse / floor,
        );
        // The output nonlinearity is the first step, on the end stop's evidence: the level
        // the base model's simulation goes beyond within 2 % of the input range of the stop.
        let Some(first) = d.steps.first() else {
            panic!("seed {seed}: no step");
        };
        assert_eq!(
            first.effect,
            Effect::OutputNonlinearity,
            "seed {seed}: {named:?}"
        );
        let evidence = first.evidence.iter().find_map(|e| match e {
            Evidence::EndStop(s) => s.levels.ceiling,
            _ => None,
        });
        let Some(seen) = evidence else {
            panic!(
                "seed {seed}: no end stop in the evidence {:?}",
                first.evidence
            );
        };
        assert!(
            (seen - stop).abs() < 0.02 * 2.0 * RANGE,
            "seed {seed}: {seen} against {stop}"
        );
        // Where the end stop is the setting chosen (not an output map), its level likewise.
        if let Some(level) = level {
            assert!(
                (level - stop).abs() < 0.02 * 2.0 * RANGE,
                "seed {seed}: {level} against {stop}"
            );
        }
        // The model with the stop simulates the validation record closer to the noise floor
        // than the linear model did.
        assert!(
            d.after.nrmse < 0.8 * d.before.nrmse,
            "seed {seed}: {} -> {}",
            d.before.nrmse,
            d.after.nrmse
        );
    }
}

#[test]
fn the_same_mass_without_the_stop_gets_no_end_stop() {
    for seed in [1, 2] {
        let (d, floor, _) = run(seed, false);
        let named: Vec<&str> = d.steps.iter().map(|s| s.effect.name()).collect();
        println!(
            "seed {seed} without the stop: steps {named:?}; validation NRMSE {:.4} (floor {floor:.4})",
            d.after.nrmse
        );
        assert_eq!(d.model.structure.end_stop, None, "seed {seed}: {named:?}");
        assert!(
            !named.contains(&"output_nonlinearity"),
            "seed {seed}: {named:?}"
        );
    }
}
