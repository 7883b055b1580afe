//! The diagnose effect `hysteresis`: a backlash servo driven by an ordinary input (smoothed
//! random, many reversals inside the range, no Table I sweeps) at 20 dB, diagnosed with a
//! static nonlinearity. The residual's direction correlation points at an element with
//! memory; the play operator is added first and the validation error after is at most 0.7×
//! the static model's, with the gap within 10 %. On the same servo without backlash the
//! effect is not added. Fixed seeds; about 10 s in release.

#![allow(clippy::panic)]

use hsid_host::diagnose::{DiagnoseOptions, Effect, Nonlinearity, Record, Validation, diagnose};
use hsid_host::hysteresis::ElementKind;
use hsid_host::hysteresis::servo::{HOLD, RANGE, Servo};
use hsid_host::identify::IdentifyOptions;

const LEN: usize = 3000;

fn options() -> DiagnoseOptions {
    let id = IdentifyOptions {
        static_nonlinearity: true,
        order: Some(2),
        ..IdentifyOptions::uniform(-RANGE, RANGE, 6, HOLD)
    };
    DiagnoseOptions::new(id, Nonlinearity::Static)
}

fn run(width: f64, seed: u64) -> hsid_host::diagnose::Diagnosis {
    let servo = Servo {
        kind: ElementKind::Backlash,
        width,
        snr_db: 20.0,
    };
    let est = servo.record(LEN, seed);
    let val = servo.record(LEN, seed + 1000);
    let validation = Validation::Separate {
        record: Record::new(val.u, val.y),
        skip: HOLD,
    };
    match diagnose(&Record::new(est.u, est.y), &validation, &options()) {
        Ok(d) => d,
        Err(e) => panic!("width {width} seed {seed}: {e}"),
    }
}

#[test]
fn a_static_model_of_a_backlash_servo_gains_the_play_operator_first() {
    for seed in [1, 2] {
        let d = run(0.6, seed);
        if std::env::var_os("HSID_SHOW").is_some() {
            println!("{}", hsid_host::diagnose::report::text(&d));
        }
        let named: Vec<&str> = d.steps.iter().map(|s| s.effect.name()).collect();
        let ratio = d.after.rmse / d.before.rmse;
        let gap = d
            .model
            .hysteresis
            .as_ref()
            .and_then(|h| h.gap())
            .unwrap_or(f64::NAN);
        println!(
            "seed {seed}: steps {named:?}, validation RMSE {:.4} -> {:.4} ({ratio:.3}×), gap {gap:.4}",
            d.before.rmse, d.after.rmse
        );
        assert_eq!(
            d.steps.first().map(|s| s.effect),
            Some(Effect::Hysteresis),
            "seed {seed}: {named:?}"
        );
        assert!(ratio <= 0.7, "seed {seed}: after/before {ratio}");
        assert!((gap - 0.6).abs() <= 0.06, "seed {seed}: gap {gap}");
    }
}

#[test]
fn without_backlash_no_element_is_added() {
    let d = run(0.0, 3);
    let named: Vec<&str> = d.steps.iter().map(|s| s.effect.name()).collect();
    println!("no play: steps {named:?}");
    assert!(
        d.steps.iter().all(|s| s.effect != Effect::Hysteresis),
        "{named:?}"
    );
}
