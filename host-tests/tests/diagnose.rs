//! `hsid diagnose` on data with one undeclared effect (issue 5, part 2): every catalog effect,
//! both plants (the paper's second-order `G` and a first-order lag), both elements (switch
//! and backlash, borders unlike the paper's). The effect must be named first, and the
//! validation error after adding it must be at most 0.7 × the error before and at most
//! 1.3 × the noise floor (the RMS of the noise actually added). On clean data, at most 5 % of
//! 40 runs may add an effect.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

use hsid_host::diagnose::bench::{Outcome, run_all};
use hsid_host::diagnose::scenario::{Plant, Scenario, generate};
use hsid_host::diagnose::{Effect, Nonlinearity, PoleRefinement, Test, diagnose};
use hsid_host::validation::residual::{ResidualInput, run_tests};
use rand::SeedableRng;
use rand_distr::{Distribution, StandardNormal};

const KINDS: [Nonlinearity; 2] = [Nonlinearity::Backlash, Nonlinearity::Switch];

fn threads() -> usize {
    std::thread::available_parallelism().map_or(2, |n| n.get())
}

#[test]
fn every_effect_is_named_first_and_fixed() {
    let mut scenarios = Vec::new();
    for e in Effect::ALL {
        for plant in Plant::ALL {
            for kind in KINDS {
                scenarios.push(Scenario::new(Some(e), plant, kind, 1));
            }
        }
    }
    let results = run_all(&scenarios, threads(), &|_| {}, &|o| {
        println!("{}", o.line())
    });
    let outcomes: Vec<Outcome> = results.into_iter().map(|r| r.unwrap()).collect();
    let failed: Vec<String> = outcomes
        .iter()
        .filter(|o| !o.passes())
        .map(Outcome::line)
        .collect();
    assert!(failed.is_empty(), "failed:\n{}", failed.join("\n"));
    // Every effect, both plants, both elements.
    assert_eq!(outcomes.len(), 7 * 2 * 2);
}

#[test]
fn clean_data_raises_at_most_five_percent_false_alarms() {
    // 40 runs: 10 seeds for each plant and element. The reported models' pole refinement does
    // not take part in the decisions; it is left out here to keep the test short.
    let mut scenarios = Vec::new();
    for plant in Plant::ALL {
        for kind in KINDS {
            for seed in 0..10 {
                scenarios.push(Scenario::new(None, plant, kind, 500 + seed));
            }
        }
    }
    let next = AtomicUsize::new(0);
    let alarms: Mutex<Vec<String>> = Mutex::new(Vec::new());
    std::thread::scope(|sc| {
        for _ in 0..threads() {
            sc.spawn(|| {
                loop {
                    let i = next.fetch_add(1, Ordering::SeqCst);
                    let Some(s) = scenarios.get(i) else { break };
                    let mut data = generate(s).unwrap();
                    data.options.refine_poles = PoleRefinement::Never;
                    let d = diagnose(&data.record, &data.validation, &data.options).unwrap();
                    if !d.steps.is_empty() {
                        let names: Vec<&str> = d.steps.iter().map(|s| s.effect.name()).collect();
                        alarms.lock().unwrap().push(format!(
                            "{} {} seed {}: {}",
                            s.plant.name(),
                            s.kind.name(),
                            s.seed,
                            names.join(", ")
                        ));
                    }
                }
            });
        }
    });
    let alarms = alarms.into_inner().unwrap();
    println!(
        "false alarms: {} of {}: {alarms:?}",
        alarms.len(),
        scenarios.len()
    );
    assert_eq!(scenarios.len(), 40);
    assert!(alarms.len() * 20 <= scenarios.len(), "{alarms:?}");
}

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

/// Each effect's tests fire where they should: a delay shows in the input cross-correlation
/// at the delay's lag, a sinusoid as a spectral line at its frequency.
#[test]
fn tests_point_at_the_effect() {
    let s = Scenario::new(
        Some(Effect::PeriodicDisturbance),
        Plant::FirstOrder,
        Nonlinearity::Switch,
        3,
    );
    let data = generate(&s).unwrap();
    let mut opts = data.options.clone();
    opts.max_steps = 0;
    let d = diagnose(&data.record, &data.validation, &opts).unwrap();
    assert!(d.tests_before.fired(Test::SpectralLine));
    let w = 2.0 * std::f64::consts::PI / 23.7;
    assert!(
        (d.tests_before.line_frequency - w).abs() < 0.01,
        "{}",
        d.tests_before.line_frequency
    );
    let s = Scenario::new(
        Some(Effect::InputDelay),
        Plant::FirstOrder,
        Nonlinearity::Backlash,
        3,
    );
    let data = generate(&s).unwrap();
    let mut opts = data.options.clone();
    opts.max_steps = 0;
    let d = diagnose(&data.record, &data.validation, &opts).unwrap();
    assert!(d.tests_before.fired(Test::InputCorrelation));
    assert!(
        (1..=4).contains(&d.tests_before.strongest_input_lag),
        "lag {}",
        d.tests_before.strongest_input_lag
    );
}

#[test]
fn static_knot_never_visited_gets_advice_for_static_data() {
    use hsid_host::diagnose::model::Record;
    use hsid_host::diagnose::{DiagnoseError, DiagnoseOptions, Validation};
    use hsid_host::identify::IdentifyOptions;
    // The input stays in [0, 3]; knot 4 (u = 4) lives on [3, 10] and is never excited.
    let u: Vec<f64> = (0..600)
        .map(|t| 1.5 + 1.5 * (t as f64 / 20.0).sin())
        .collect();
    let y: Vec<f64> = u.iter().map(|v| 0.5 * v).collect();
    let mut id = IdentifyOptions::uniform(0.0, 10.0, 5, 0);
    id.knots_asc = vec![0.0, 1.0, 2.0, 3.0, 4.0, 10.0];
    id.knots_desc = id.knots_asc.clone();
    id.order = Some(1);
    let opts = DiagnoseOptions::new(id, Nonlinearity::Static);
    let e = diagnose(&Record::new(u, y), &Validation::Split(0.7), &opts).unwrap_err();
    assert!(
        matches!(e, DiagnoseError::KnotNotVisited { knot: 4, .. }),
        "{e:?}"
    );
    let msg = e.to_string();
    assert!(msg.contains("never visits [3, 10]"), "{msg}");
    assert!(msg.contains("move or remove that knot"), "{msg}");
    assert!(!msg.contains("Table I"), "{msg}");
}
