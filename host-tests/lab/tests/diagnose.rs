//! `hsid diagnose` on data with one undeclared effect (issue 5, part 2): every catalog effect,
//! both plants (the paper's second-order `G` and a first-order lag), both elements (switch
//! and backlash, borders unlike the paper's). The effect must be named first, and the
//! validation error after adding it must be at most 0.7 × the error before and at most
//! 1.3 × the noise floor (the RMS of the noise actually added). On clean data, at most 5 % of
//! 40 runs may add an effect. The residual tests' own checks are `hsid-host`'s
//! `tests/diagnose.rs`.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use hsid_host::model::Element;
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

use hsid_host::diagnose::{Effect, PoleRefinement, Test, diagnose};
use hsid_lab::bench::{Outcome, run_all};
use hsid_lab::scenario::{Plant, Scenario, generate};

const KINDS: [Element; 2] = [Element::Backlash, Element::Switch];

fn threads() -> usize {
    std::thread::available_parallelism().map_or(2, |n| n.get())
}

#[test]
#[ignore = "slow tier, run by scripts/slow-checks.sh: confusion over every effect and seed, about 7 min"]
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
#[ignore = "slow tier, run by scripts/slow-checks.sh: Monte Carlo false-alarm rate, about 3 min"]
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

/// Each effect's tests fire where they should: a delay shows in the input cross-correlation
/// at the delay's lag, a sinusoid as a spectral line at its frequency.
#[test]
fn tests_point_at_the_effect() {
    let s = Scenario::new(
        Some(Effect::PeriodicDisturbance),
        Plant::FirstOrder,
        Element::Switch,
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
        Element::Backlash,
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
