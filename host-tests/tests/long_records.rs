//! A record longer than the choice window: the segments, horizons and order are chosen on its
//! start, and the chosen model alone is refined on the whole record. Checked against the same
//! choices made on the whole record and against the simulated plant's own noise.

#![allow(clippy::panic)]

use hsid_host::choose::{Choices, best_model};
use hsid_host::identify::IdentifyOptions;
use hsid_host::sim::{Backlash, Lti, simulate, table1_excitation, with_hold};
use rand::SeedableRng;
use rand_pcg::Pcg64;

const U_MIN: f64 = -2.0;
const U_MAX: f64 = 2.0;
const HOLD: usize = 200;

/// A servo with a play of 0.6 and a damped second-order plant (poles 0.9 ± 0.2j), driven by
/// the Table I excitation for `len` samples after the hold; white output noise at 20 dB.
/// Returns `(u, y, variance of the noise added)`.
fn servo(len: usize, seed: u64) -> (Vec<f64>, Vec<f64>, f64) {
    let mut rng = Pcg64::seed_from_u64(seed);
    let Ok(ex) = table1_excitation(len, U_MIN, U_MAX, &mut rng) else {
        panic!("a valid interval");
    };
    let u = with_hold(HOLD, U_MIN, &ex);
    // (1 − 0.9q⁻¹)² + 0.04q⁻²: poles 0.9 ± 0.2j; numerator for G(1) = 1.
    let den = vec![1.0, -1.8, 0.85];
    let gain = den.iter().sum::<f64>();
    let Ok(plant) = Lti::new(vec![0.0, 0.6 * gain, 0.4 * gain], den) else {
        panic!("a valid plant");
    };
    let Ok(white) = Lti::new(vec![1.0], vec![1.0]) else {
        panic!("a valid noise model");
    };
    let mut element = Backlash::from_fns(|u| 0.8 * (u - 0.3), |u| 0.8 * (u + 0.3));
    let Ok(sim) = simulate(
        &u,
        &mut element,
        &plant,
        &white,
        Some(20.0),
        HOLD..u.len(),
        &mut rng,
    ) else {
        panic!("the servo simulates");
    };
    let noise = sim.v.iter().map(|v| v * v).sum::<f64>() / sim.v.len() as f64;
    (u, sim.y, noise)
}

#[test]
fn a_long_record_is_chosen_on_its_start_and_refined_whole() {
    let (u, y, noise) = servo(8_000, 3);
    let base = IdentifyOptions::uniform(U_MIN, U_MAX, 7, HOLD);
    let windowed = Choices {
        window: Some(4_000),
        ..Choices::default()
    };
    let whole = Choices {
        window: None,
        ..Choices::default()
    };
    let (Ok(w), Ok(a)) = (
        best_model(&u, &y, &base, &windowed),
        best_model(&u, &y, &base, &whole),
    ) else {
        panic!("both give a model");
    };
    let Some(window) = &w.window else {
        panic!("the record is longer than the window: the choices are made on its start");
    };
    assert_eq!((window.samples, window.record), (4_000, u.len()));
    assert!(a.window.is_none());
    let (Some(wf), Some(af)) = (&w.fit, &a.fit) else {
        panic!("both refined");
    };
    // The refinement is the whole record's: its cost covers every sample after the start.
    assert_eq!(wf.samples, af.samples);
    assert!(wf.samples + wf.start > 7_500, "{} samples", wf.samples);
    // The structure the start resolves is the one the whole record resolves here (the
    // horizons of the subspace start may differ: their choice is bounded by the samples).
    let chosen = |b: &hsid_host::choose::Best| {
        (
            b.segments.as_ref().map(|s| s.segments),
            b.order.as_ref().map(|o| o.order),
        )
    };
    assert_eq!(chosen(&w), chosen(&a));
    // Both reach the noise the simulation added: their prediction error is within 3 % of
    // its variance, and within 0.5 % of each other.
    for mse in [wf.mse, af.mse] {
        assert!(
            (mse / noise - 1.0).abs() < 0.03,
            "prediction error {mse:.3e}, noise {noise:.3e}"
        );
    }
    assert!(
        (wf.mse / af.mse - 1.0).abs() < 0.005,
        "windowed {:.4e}, whole {:.4e}",
        wf.mse,
        af.mse
    );
    // A record no longer than the window is chosen whole: the same model as without one.
    let (us, ys) = (&u[..4_000], &y[..4_000]);
    let (Ok(short_w), Ok(short_a)) = (
        best_model(us, ys, &base, &windowed),
        best_model(us, ys, &base, &whole),
    ) else {
        panic!("both give a model");
    };
    assert!(short_w.window.is_none());
    assert_eq!(short_w.model.a, short_a.model.a);
}
