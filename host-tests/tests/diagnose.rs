//! The residual tests of `hsid diagnose` hold their level on white noise and fire on what they
//! test; a static knot the input never visits gets advice for static data. The diagnosis on
//! simulated data with one undeclared effect (every catalog effect named first and fixed, the
//! false alarms on clean data) is `hsid-lab`'s `tests/diagnose.rs`.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use hsid_host::diagnose::{Test, diagnose};
use hsid_host::model::Element;
use hsid_host::validation::residual::{ResidualInput, run_tests};
use rand::SeedableRng;
use rand_distr::{Distribution, StandardNormal};

/// The residual tests for a residual, an input (δ its sign, one ramp channel, six bins over
/// [−3, 3]) and a simulated output.
fn tests_on(r: &[f64], u: &[f64], sim: &[f64]) -> hsid_host::diagnose::TestSet {
    let delta: Vec<f64> = u.iter().map(|v| if *v > 0.0 { 1.0 } else { 0.0 }).collect();
    let bins: Vec<usize> = u
        .iter()
        .map(|v| ((v + 3.0).clamp(0.0, 5.99)) as usize)
        .collect();
    let z = vec![u.iter().map(|v| v.max(0.0)).collect::<Vec<f64>>()];
    run_tests(&ResidualInput {
        residual: r,
        u,
        delta: &delta,
        regressor: &z,
        bins: &bins,
        bin_count: 6,
        simulated: sim,
    })
}

/// The residual tests hold their 1 % level on white noise (independent of everything).
#[test]
fn residual_tests_hold_their_level_on_white_noise() {
    let mut rng = rand_pcg::Pcg32::seed_from_u64(7);
    let runs = 200;
    let n = 1500;
    let mut fired = std::collections::BTreeMap::<Test, usize>::new();
    for _ in 0..runs {
        let mut g = || -> Vec<f64> { (0..n).map(|_| StandardNormal.sample(&mut rng)).collect() };
        let r = g();
        let u: Vec<f64> = g();
        let sim: Vec<f64> = g();
        let t = tests_on(&r, &u, &sim);
        for test in t.tests.iter().filter(|t| t.fired) {
            *fired.entry(test.name).or_default() += 1;
        }
    }
    println!("{fired:?}");
    // 1 % level: expect 2 of 200; allow sampling error (P(Bin(200, 0.01) > 7) < 0.001).
    for (name, k) in &fired {
        assert!(*k <= 7, "{name} fired {k} times in {runs} white-noise runs");
    }
}

/// The state-dependence test fires on a residual driven by the level times the increment of
/// the simulated output (a speed that changes with the level), and not on the same residual
/// without that part.
#[test]
fn state_dependence_fires_on_level_times_increment() {
    let mut rng = rand_pcg::Pcg32::seed_from_u64(11);
    let n = 1500;
    let mut g = || -> Vec<f64> { (0..n).map(|_| StandardNormal.sample(&mut rng)).collect() };
    let e = g();
    // A slow simulated output (AR(1) at 0.95) and an input unrelated to the residual.
    let mut sim = vec![0.0; n];
    for t in 1..n {
        sim[t] = 0.95 * sim[t - 1] + e[t];
    }
    let u = g();
    let noise = g();
    let mean = sim.iter().sum::<f64>() / n as f64;
    let w: Vec<f64> = (0..n)
        .map(|t| (sim[t] - mean) * if t > 0 { sim[t] - sim[t - 1] } else { 0.0 })
        .collect();
    let w_rms = (w.iter().map(|v| v * v).sum::<f64>() / n as f64).sqrt();
    let run = |r: &[f64]| tests_on(r, &u, &sim);
    // The effect at a third of the noise's RMS.
    let with: Vec<f64> = noise
        .iter()
        .zip(&w)
        .map(|(v, w)| v + 0.3 * w / w_rms)
        .collect();
    assert!(run(&with).fired(Test::StateDependence));
    assert!(!run(&noise).fired(Test::StateDependence));
}

#[test]
fn static_knot_never_visited_gets_advice_for_static_data() {
    use hsid_host::diagnose::{DiagnoseError, DiagnoseOptions, Validation};
    use hsid_host::identify::IdentifyOptions;
    use hsid_host::model::Record;
    // The input stays in [0, 3]; knot 4 (u = 4) lives on [3, 10] and is never excited.
    let u: Vec<f64> = (0..600)
        .map(|t| 1.5 + 1.5 * (t as f64 / 20.0).sin())
        .collect();
    let y: Vec<f64> = u.iter().map(|v| 0.5 * v).collect();
    let mut id = IdentifyOptions::uniform(0.0, 10.0, 5, 0);
    id.knots_asc = vec![0.0, 1.0, 2.0, 3.0, 4.0, 10.0];
    id.knots_desc = id.knots_asc.clone();
    id.order = Some(1);
    let opts = DiagnoseOptions::new(id, Element::Static);
    let e = diagnose(&Record::new(u, y).unwrap(), &Validation::Split(0.7), &opts).unwrap_err();
    assert!(
        matches!(e, DiagnoseError::KnotNotVisited { knot: 4, .. }),
        "{e:?}"
    );
    let msg = e.to_string();
    assert!(msg.contains("never visits [3, 10]"), "{msg}");
    assert!(msg.contains("move or remove that knot"), "{msg}");
    assert!(!msg.contains("Table I"), "{msg}");
}
