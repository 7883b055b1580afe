//! Closed-loop records: the feedback check on simulated backlash servos.

#![allow(clippy::unwrap_used)]

use hsid_host::closed_loop::{ServoSpec, simulate_servo};
use hsid_host::diagnose::checks::feedback::{FeedbackTest, feedback_in_record};
use hsid_host::identify::IdentifyOptions;

const SEEDS: u64 = 20;

fn options(spec: &ServoSpec) -> IdentifyOptions {
    IdentifyOptions::uniform(-3.0, 3.0, spec.knots.len() - 1, spec.hold)
}

/// The feedback test on the record of `spec` with `seed`.
fn test_record(spec: &ServoSpec, seed: u64) -> FeedbackTest {
    let servo = simulate_servo(spec, seed).unwrap();
    feedback_in_record(&servo.u, &servo.y, &options(spec))
        .unwrap()
        .unwrap()
}

#[test]
fn the_feedback_check_separates_closed_from_open_loop_servos() {
    // The same reference and noise draws per seed, with and without the controller's feedback.
    let closed = ServoSpec::paper();
    let open = closed.open_loop();
    let (mut fired_closed, mut fired_open, mut sum_open) = (0, 0, 0.0);
    for seed in 0..SEEDS {
        let (c, o) = (test_record(&closed, seed), test_record(&open, seed));
        eprintln!(
            "seed {seed:2}: closed χ² {:6.1} (lag {:2}), open χ² {:5.1} (lag {:2}), threshold {:.1}",
            c.statistic, c.lag, o.statistic, o.lag, c.threshold
        );
        fired_closed += usize::from(c.fires());
        fired_open += usize::from(o.fires());
        sum_open += o.statistic;
    }
    eprintln!(
        "fired: closed loop {fired_closed}/{SEEDS}, open loop {fired_open}/{SEEDS} (mean χ² {:.1})",
        sum_open / SEEDS as f64
    );
    assert!(
        fired_closed >= 19,
        "closed loop fired on {fired_closed}/{SEEDS}"
    );
    assert!(fired_open <= 1, "open loop fired on {fired_open}/{SEEDS}");
}

#[test]
fn a_weak_controller_is_found_less_often_than_a_strong_one() {
    // The statistic grows with the feedback gain: K_p = 0.3 against K_p = 1.5, same seeds.
    let strong = ServoSpec::paper();
    let weak = ServoSpec {
        kp: 0.3,
        feedforward: strong.feedforward + strong.kp - 0.3,
        ..strong.clone()
    };
    let mean = |s: &ServoSpec| {
        (0..5)
            .map(|seed| test_record(s, seed).statistic)
            .sum::<f64>()
            / 5.0
    };
    let (w, s) = (mean(&weak), mean(&strong));
    eprintln!("mean χ²: K_p = 0.3 {w:.1}, K_p = 1.5 {s:.1}");
    assert!(s > 3.0 * w, "weak {w}, strong {s}");
}
