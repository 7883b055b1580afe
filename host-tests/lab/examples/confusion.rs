//! The confusion table of `hsid diagnose` on simulated Table I experiments with one undeclared
//! effect (or none), over both plants, both elements and several seeds.
//!
//! ```text
//! cargo run --release -p hsid-lab --example confusion -- [--min-gain G] [--propose-every] [SEEDS] [CLEAN_SEEDS]
//! ```
//!
//! `--min-gain G` runs the diagnosis with another minimum gain (`hsid diagnose --min-gain`,
//! default 0.2), and `--propose-every` has every step fit and score every deterministic
//! effect, with or without a residual test's evidence (`Proposing::Every`): the measurements
//! of what the estimation data can show in docs/closing-the-loop.md.
//!
//! Prints one line per run, the confusion table (true effect × effect named first), the
//! false-alarm rate on clean data and the count of added steps that raised the validation
//! error.

use hsid_host::diagnose::DiagnoseOptions;
use hsid_host::diagnose::Effect;
use hsid_host::model::Element;
use hsid_lab::bench::{confusion_table, run_all, take_bench_flags};
use hsid_lab::scenario::{Plant, Scenario};

fn main() {
    let (bench, rest) = take_bench_flags(std::env::args().skip(1).collect()).unwrap_or_else(|e| {
        eprintln!("{e}");
        std::process::exit(2)
    });
    let mut args = rest.into_iter();
    let seeds: u64 = args.next().and_then(|s| s.parse().ok()).unwrap_or(3);
    let clean_seeds: u64 = args.next().and_then(|s| s.parse().ok()).unwrap_or(10);
    let threads = std::thread::available_parallelism().map_or(2, |n| n.get());
    let mut scenarios = Vec::new();
    for plant in Plant::ALL {
        for kind in [Element::Backlash, Element::Switch] {
            for seed in 1..=clean_seeds {
                scenarios.push(Scenario::new(None, plant, kind, 1000 + seed));
            }
            for e in Effect::ALL {
                for seed in 1..=seeds {
                    scenarios.push(Scenario::new(Some(e), plant, kind, seed));
                }
            }
        }
    }
    eprintln!("{} runs on {threads} threads", scenarios.len());
    let adjust = |o: &mut DiagnoseOptions| bench.apply(o);
    let results = run_all(&scenarios, threads, &adjust, &|o| eprintln!("{}", o.line()));
    let mut outcomes = Vec::new();
    for r in results {
        match r {
            Ok(o) => outcomes.push(o),
            Err(e) => eprintln!("error: {e}"),
        }
    }
    println!("{}", confusion_table(&outcomes));
    let clean: Vec<_> = outcomes
        .iter()
        .filter(|o| o.scenario.effect.is_none())
        .collect();
    let alarms = clean.iter().filter(|o| !o.steps.is_empty()).count();
    println!(
        "false alarms on clean data: {alarms} of {} runs ({:.1} %)",
        clean.len(),
        100.0 * alarms as f64 / clean.len().max(1) as f64
    );
    let with: Vec<_> = outcomes
        .iter()
        .filter(|o| o.scenario.effect.is_some())
        .collect();
    let passed = with.iter().filter(|o| o.passes()).count();
    println!(
        "runs with an effect meeting every criterion (named first, after ≤ 0.7 × before, ≤ 1.3 × noise floor): {passed} of {}",
        with.len()
    );
    let worst = with
        .iter()
        .map(|o| o.error_after_first / o.floor)
        .fold(0.0f64, f64::max);
    let worst_ratio = with
        .iter()
        .map(|o| o.error_after_first / o.error_before)
        .fold(0.0f64, f64::max);
    println!("largest after / floor: {worst:.2}; largest after / before: {worst_ratio:.2}");
    let harmful: usize = outcomes.iter().map(|o| o.harmful().len()).sum();
    let steps: usize = outcomes.iter().map(|o| o.steps.len()).sum();
    println!(
        "steps that raised the validation error: {harmful} of {steps} steps added, in {} of {} runs",
        outcomes.iter().filter(|o| !o.harmful().is_empty()).count(),
        outcomes.len()
    );
    let all_steps: Vec<_> = outcomes.iter().flat_map(|o| &o.steps).collect();
    let significant = all_steps
        .iter()
        .filter(|s| s.raised_significantly())
        .count();
    println!(
        "of those, raised significantly (paired Diebold–Mariano on the validation samples, one-sided p < 0.05): {significant}"
    );
    let outliers: Vec<_> = all_steps
        .iter()
        .filter(|s| s.effect == Effect::Outliers)
        .collect();
    let kept = outliers
        .iter()
        .filter(|s| s.setting.ends_with("model kept"))
        .count();
    let lowered = outliers
        .iter()
        .filter(|s| !s.setting.ends_with("model kept") && s.error_after < s.error_before)
        .count();
    println!(
        "outliers steps: {} added, {kept} kept the model, {} re-estimated it ({lowered} of those lowered the validation error on the samples not flagged)",
        outliers.len(),
        outliers.len() - kept
    );
}
