//! The family's table (Markdown) and its summary: per class and loop the runs, the resolvable
//! runs, named right among them and overall, false alarms on clean runs, harmful steps, the
//! effects named first and the mean wall time.

use std::collections::BTreeMap;
use std::fmt::Write as _;

use super::class::{Class, Loop};
use super::resolvable::Method;
use super::run::Outcome;

/// `k of n (p %)`.
fn share(k: usize, n: usize) -> String {
    format!("{k} of {n} ({:.0} %)", 100.0 * k as f64 / n.max(1) as f64)
}

/// The effects named first and how often (`none` for no step, `error` for a failed
/// diagnosis): `friction 2, none 1`.
fn named_first(runs: &[&Outcome]) -> String {
    let mut counts: BTreeMap<&str, usize> = BTreeMap::new();
    for o in runs {
        let name = match (&o.error, o.first()) {
            (Some(_), _) => "error",
            (None, None) => "none",
            (None, Some(e)) => e.name(),
        };
        *counts.entry(name).or_default() += 1;
    }
    let parts: Vec<String> = counts.iter().map(|(k, v)| format!("{k} {v}")).collect();
    parts.join(", ")
}

/// The table: one row per class and loop that has runs (the wall time is the diagnosis's and
/// the resolvability check's together).
pub fn table(outcomes: &[Outcome]) -> String {
    let mut s = String::from(
        "| class | loop | runs | resolvable | named right among resolvable | named right | false alarms | harmful steps (significant) | named first | mean wall time (s) |\n\
         |---|---|---|---|---|---|---|---|---|---|\n",
    );
    for class in Class::ALL {
        for lp in Loop::ALL {
            let mine: Vec<&Outcome> = outcomes
                .iter()
                .filter(|o| o.scenario.class == class && o.scenario.lp == lp)
                .collect();
            if mine.is_empty() {
                continue;
            }
            let n = mine.len();
            let resolvable: Vec<&&Outcome> = mine.iter().filter(|o| o.resolvable()).collect();
            let right_res = resolvable.iter().filter(|o| o.right()).count();
            let right = mine.iter().filter(|o| o.right()).count();
            let alarms = match class {
                Class::Clean => {
                    let k = mine
                        .iter()
                        .filter(|o| o.error.is_none() && !o.named.is_empty())
                        .count();
                    k.to_string()
                }
                _ => "—".into(),
            };
            let harmful: usize = mine.iter().map(|o| o.harmful.len()).sum();
            let significant: usize = mine
                .iter()
                .flat_map(|o| &o.harmful)
                .filter(|h| h.significant())
                .count();
            let wall = mine
                .iter()
                .map(|o| (o.millis + o.resolvability.millis) as f64)
                .sum::<f64>()
                / n as f64
                / 1000.0;
            let (res_cell, right_res_cell) = match class {
                Class::Clean => ("—".to_string(), "—".to_string()),
                _ => (
                    resolvable.len().to_string(),
                    format!("{right_res} of {}", resolvable.len()),
                ),
            };
            let _ = writeln!(
                s,
                "| **{}** | {} | {n} | {res_cell} | {right_res_cell} | {right} of {n} | {alarms} | {harmful} ({significant}) | {} | {wall:.1} |",
                class.name(),
                lp.name(),
                named_first(&mine),
            );
        }
    }
    s
}

/// The summary lines: named right among the resolvable runs and overall (runs with an
/// effect), false alarms on clean runs by loop, harmful steps, how resolvability was decided,
/// failed diagnoses.
pub fn summary(outcomes: &[Outcome]) -> String {
    let mut s = String::new();
    let with: Vec<&Outcome> = outcomes
        .iter()
        .filter(|o| o.scenario.class != Class::Clean)
        .collect();
    let resolvable: Vec<&&Outcome> = with.iter().filter(|o| o.resolvable()).collect();
    let _ = writeln!(
        s,
        "named right among resolvable runs with an effect: {}",
        share(
            resolvable.iter().filter(|o| o.right()).count(),
            resolvable.len()
        )
    );
    let _ = writeln!(
        s,
        "named right among all runs with an effect: {}",
        share(with.iter().filter(|o| o.right()).count(), with.len())
    );
    for lp in Loop::ALL {
        let clean: Vec<&Outcome> = outcomes
            .iter()
            .filter(|o| o.scenario.class == Class::Clean && o.scenario.lp == lp)
            .collect();
        if clean.is_empty() {
            continue;
        }
        let alarms = clean
            .iter()
            .filter(|o| o.error.is_none() && !o.named.is_empty())
            .count();
        let _ = writeln!(
            s,
            "false alarms on clean runs, {} loop (any step added): {}",
            lp.name(),
            share(alarms, clean.len())
        );
    }
    let steps: usize = outcomes.iter().map(|o| o.named.len()).sum();
    let harmful: Vec<String> = outcomes
        .iter()
        .flat_map(|o| {
            o.harmful.iter().map(move |h| {
                format!(
                    "{} {} seed {}: {}",
                    o.scenario.class.name(),
                    o.scenario.lp.name(),
                    o.scenario.seed,
                    h.describe()
                )
            })
        })
        .collect();
    let significant = outcomes
        .iter()
        .flat_map(|o| &o.harmful)
        .filter(|h| h.significant())
        .count();
    let _ = writeln!(
        s,
        "steps that raised the validation error: {} of {steps} steps added, {significant} significantly (Step::p_worse < 0.05){}{}",
        harmful.len(),
        if harmful.is_empty() { "" } else { ": " },
        harmful.join("; ")
    );
    let count = |m: Method| with.iter().filter(|o| o.resolvability.method == m).count();
    let _ = writeln!(
        s,
        "resolvability decided by the family's fits: {}, by the diagnosis's candidate: {}, undecided: {}",
        count(Method::Fit),
        count(Method::Candidate),
        count(Method::Undecided)
    );
    let plays: Vec<&Outcome> = outcomes
        .iter()
        .filter(|o| o.play.is_some_and(|(_, found)| found.is_some()))
        .collect();
    let within = plays
        .iter()
        .filter(|o| o.play_error().is_some_and(|e| e.abs() <= 0.1))
        .count();
    let errors: Vec<String> = plays
        .iter()
        .filter_map(|o| o.play_error())
        .map(|e| format!("{:+.1} %", 100.0 * e))
        .collect();
    let _ = writeln!(
        s,
        "two-mass play after the step within 10 % of the truth: {} of {} runs with the step{}{}",
        within,
        plays.len(),
        if errors.is_empty() { "" } else { ": " },
        errors.join(", ")
    );
    let errors = outcomes.iter().filter(|o| o.error.is_some()).count();
    let _ = writeln!(
        s,
        "diagnoses that failed with an error: {}",
        share(errors, outcomes.len())
    );
    s
}
