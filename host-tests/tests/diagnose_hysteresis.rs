//! The diagnose effect `hysteresis`: servos driven by an ordinary input (smoothed random,
//! many reversals inside the range, no Table I sweeps) at 20 dB, diagnosed with a static
//! nonlinearity. The static model's residual is not white (and may follow the input's
//! direction); the element with memory is added first — the play operator for a backlash
//! servo, the relay for a switch servo — with the validation error after at most 0.7× the
//! static model's and within 1.3× the noise floor, and a backlash gap within 10 %. On the same
//! servo without backlash the effect is not added. Fixed seeds; about 35 s in release.

#![allow(clippy::panic)]

use hsid_host::diagnose::{DiagnoseOptions, Effect, Validation, diagnose};
use hsid_host::hysteresis::servo::{HOLD, RANGE, Servo};
use hsid_host::model::{MemoryElement, Record};
use hsid_host::report::fit;

const LEN: usize = 3000;

fn options() -> DiagnoseOptions {
    crate::common::static_order_two(RANGE, HOLD)
}

/// The diagnosis and the validation record's noise floor (RMSE of the noise itself after the
/// hold).
fn run(kind: MemoryElement, width: f64, seed: u64) -> (hsid_host::diagnose::Diagnosis, f64) {
    let servo = Servo {
        kind,
        width,
        snr_db: 20.0,
    };
    let est = servo.record(LEN, seed);
    let val = servo.record(LEN, seed + 1000);
    let floor = fit(&val.y[HOLD..], &val.y_clean[HOLD..]).rmse;
    let records = Record::new(val.u, val.y).and_then(|v| Ok((Record::new(est.u, est.y)?, v)));
    let (est, val) = match records {
        Ok(records) => records,
        Err(e) => panic!("width {width} seed {seed}: {e}"),
    };
    let validation = Validation::Separate {
        record: val,
        skip: HOLD,
    };
    match diagnose(&est, &validation, &options()) {
        Ok(d) => (d, floor),
        Err(e) => panic!("width {width} seed {seed}: {e}"),
    }
}

#[test]
fn a_static_model_of_a_backlash_servo_gains_the_play_operator_first() {
    for seed in [1, 2] {
        let (d, floor) = run(MemoryElement::Play, 0.6, seed);
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
            "seed {seed}: steps {named:?}, validation RMSE {:.4} -> {:.4} ({ratio:.3}×; noise floor {floor:.4}, {:.3}×), gap {gap:.4}",
            d.before.rmse,
            d.after.rmse,
            d.after.rmse / floor
        );
        assert_eq!(
            d.steps.first().map(|s| s.effect),
            Some(Effect::Hysteresis),
            "seed {seed}: {named:?}"
        );
        assert!(ratio <= 0.7, "seed {seed}: after/before {ratio}");
        assert!((gap - 0.6).abs() <= 0.06, "seed {seed}: gap {gap}");
        assert!(
            d.after.rmse <= 1.3 * floor,
            "seed {seed}: {} against floor {floor}",
            d.after.rmse
        );
    }
}

#[test]
fn without_backlash_no_element_is_added() {
    let (d, _) = run(MemoryElement::Play, 0.0, 3);
    let named: Vec<&str> = d.steps.iter().map(|s| s.effect.name()).collect();
    println!("no play: steps {named:?}");
    assert!(
        d.steps.iter().all(|s| s.effect != Effect::Hysteresis),
        "{named:?}"
    );
}

#[test]
fn a_static_model_of_a_switch_servo_gains_the_relay_first() {
    let (d, floor) = run(MemoryElement::Relay, 0.5, 1);
    let named: Vec<&str> = d.steps.iter().map(|s| s.effect.name()).collect();
    let kind = d.model.hysteresis.as_ref().map(|h| h.kind);
    println!(
        "switch: steps {named:?}, element {kind:?}, validation RMSE {:.4} -> {:.4} (noise floor {floor:.4})",
        d.before.rmse, d.after.rmse
    );
    assert_eq!(
        d.steps.first().map(|s| s.effect),
        Some(Effect::Hysteresis),
        "{named:?}"
    );
    assert_eq!(kind, Some(MemoryElement::Relay));
    assert!(d.after.rmse <= 0.7 * d.before.rmse && d.after.rmse <= 1.3 * floor);
}
