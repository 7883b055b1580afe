//! The family's confusion table and its summary: named right per class and overall, false
//! alarms on clean runs, harmful steps.

use std::fmt::Write as _;

use super::class::{Class, Expect};
use super::run::Outcome;
use hsid_host::diagnose::{Check, Effect};

/// The data checks shown beside the table.
pub const CHECKS: [Check; 3] = [Check::Feedback, Check::Integrating, Check::OutputSaturation];

/// The confusion table (Markdown): rows the true class, columns the effect named first (and
/// "error" for a failed diagnosis), then how many runs each data check fired in, the runs and
/// the runs named right.
pub fn confusion_table(outcomes: &[Outcome]) -> String {
    let mut cols: Vec<Option<Effect>> = vec![None];
    cols.extend(Effect::PROPOSED.into_iter().map(Some));
    let mut s = String::from("| true \\ named first |");
    for c in &cols {
        let _ = write!(s, " {} |", c.map_or("none", Effect::name));
    }
    s.push_str(" error |");
    for c in CHECKS {
        let _ = write!(s, " check {} |", c.name());
    }
    s.push_str(" runs | named right |\n|---|");
    s.push_str(&"---|".repeat(cols.len() + CHECKS.len() + 3));
    s.push('\n');
    for class in Class::ALL {
        let mine: Vec<&Outcome> = outcomes
            .iter()
            .filter(|o| o.scenario.class == class)
            .collect();
        if mine.is_empty() {
            continue;
        }
        let _ = write!(s, "| **{}** |", class.name());
        let cell = |k: usize| {
            if k == 0 {
                "·".to_string()
            } else {
                k.to_string()
            }
        };
        for c in &cols {
            let k = mine
                .iter()
                .filter(|o| o.error.is_none() && o.first() == *c)
                .count();
            let _ = write!(s, " {} |", cell(k));
        }
        let errors = mine.iter().filter(|o| o.error.is_some()).count();
        let _ = write!(s, " {} |", cell(errors));
        for c in CHECKS {
            let k = mine.iter().filter(|o| o.fired.contains(&c)).count();
            let _ = write!(s, " {} |", cell(k));
        }
        let right = mine.iter().filter(|o| o.right()).count();
        let _ = writeln!(s, " {} | {right} |", mine.len());
    }
    s
}

/// `named right, {label}: k of n (p %)` for `runs`, the percentage with `decimals` digits.
fn named_right_line(s: &mut String, label: &str, runs: &[&Outcome], decimals: usize) {
    let right = runs.iter().filter(|o| o.right()).count();
    let pct = 100.0 * right as f64 / runs.len().max(1) as f64;
    let _ = writeln!(
        s,
        "named right, {label}: {right} of {} ({pct:.decimals$} %)",
        runs.len()
    );
}

/// The summary lines: named right per class and overall, false alarms on clean runs (an
/// effect added; the feedback or integrating check firing), the feedback and integrating
/// checks on the other classes, harmful steps.
pub fn summary(outcomes: &[Outcome]) -> String {
    let mut s = String::new();
    let pct = |a: usize, b: usize| 100.0 * a as f64 / b.max(1) as f64;
    for class in Class::ALL {
        let mine: Vec<&Outcome> = outcomes
            .iter()
            .filter(|o| o.scenario.class == class)
            .collect();
        if mine.is_empty() {
            continue;
        }
        named_right_line(&mut s, class.name(), &mine, 0);
    }
    let all: Vec<&Outcome> = outcomes.iter().collect();
    named_right_line(&mut s, "overall", &all, 1);
    let with: Vec<&Outcome> = outcomes
        .iter()
        .filter(|o| o.scenario.class != Class::Clean)
        .collect();
    named_right_line(&mut s, "runs with an effect", &with, 1);
    let clean: Vec<&Outcome> = outcomes
        .iter()
        .filter(|o| o.scenario.class == Class::Clean)
        .collect();
    let alarms = clean.iter().filter(|o| !o.named.is_empty()).count();
    let _ = writeln!(
        s,
        "false alarms on clean runs (an effect added): {alarms} of {} ({:.1} %)",
        clean.len(),
        pct(alarms, clean.len())
    );
    let checks = clean
        .iter()
        .filter(|o| {
            o.fired
                .iter()
                .any(|c| matches!(c, Check::Feedback | Check::Integrating))
        })
        .count();
    let _ = writeln!(
        s,
        "clean runs where the feedback or integrating check fired: {checks} of {}",
        clean.len()
    );
    for (check, class) in [
        (Check::Feedback, Class::ClosedLoop),
        (Check::Integrating, Class::Integrating),
    ] {
        let others: Vec<&&Outcome> = with.iter().filter(|o| o.scenario.class != class).collect();
        let k = others.iter().filter(|o| o.fired.contains(&check)).count();
        let _ = writeln!(
            s,
            "runs with an effect other than {} where the {} check fired: {k} of {}",
            class.name(),
            check.name(),
            others.len()
        );
    }
    let harmful: usize = outcomes.iter().map(|o| o.harmful.len()).sum();
    let steps: usize = outcomes.iter().map(|o| o.named.len()).sum();
    let runs = outcomes.iter().filter(|o| !o.harmful.is_empty()).count();
    let _ = writeln!(
        s,
        "steps that raised the validation error: {harmful} of {steps} steps added, in {runs} of {} runs",
        outcomes.len()
    );
    let significant = outcomes
        .iter()
        .flat_map(|o| &o.harmful)
        .filter(|h| h.significant())
        .count();
    let _ = writeln!(
        s,
        "of those, raised significantly (paired Diebold–Mariano on the validation samples, one-sided p < 0.05): {significant}"
    );
    resolution_lines(&mut s, &with);
    let errors = outcomes.iter().filter(|o| o.error.is_some()).count();
    let _ = writeln!(
        s,
        "diagnoses that failed with an error: {errors} of {}",
        outcomes.len()
    );
    s
}

/// Whether the run's effect shows in the base model's validation error beyond the diagnosis's
/// resolution: an effect is added only when it lowers the inner hold-out MSE by the minimum
/// gain `g` (20 % by default; the run's own, [`Outcome::min_gain`]), so one whose perfect
/// model could lower the validation MSE from the base model's to the noise floor's by less —
/// `before < floor / √(1 − g)` — is below what the diagnosis claims to find. `None` for the classes not scored by a deterministic effect in
/// the simulation error (clean, coloured noise, and the data-check classes).
pub fn shown(o: &Outcome) -> Option<bool> {
    let deterministic =
        matches!(o.scenario.class.expect(), Expect::First(e) if e != Effect::ColoredNoise);
    let g = o.min_gain;
    (deterministic && o.error.is_none())
        .then(|| o.error_before >= o.truth.noise_floor / (1.0 - g).sqrt())
}

/// Named right among the deterministic-effect runs whose effect shows beyond the resolution,
/// and the runs below it (by class, with how many of them were named right).
fn resolution_lines(s: &mut String, with: &[&Outcome]) {
    let shown_runs: Vec<&Outcome> = with
        .iter()
        .copied()
        .filter(|o| shown(o) == Some(true))
        .collect();
    named_right_line(
        s,
        "deterministic effects shown beyond the resolution (base validation error ≥ floor / √(1 − min_gain))",
        &shown_runs,
        1,
    );
    let below: Vec<String> = with
        .iter()
        .filter(|o| shown(o) == Some(false))
        .map(|o| {
            let mark = if o.right() { "named" } else { "not named" };
            format!(
                "{} seed {} ({:.3}× floor, {mark})",
                o.scenario.class.name(),
                o.scenario.seed,
                o.error_before / o.truth.noise_floor
            )
        })
        .collect();
    let _ = writeln!(
        s,
        "deterministic effects below the resolution: {} runs{}{}",
        below.len(),
        if below.is_empty() { "" } else { ": " },
        below.join(", ")
    );
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::family_b::generate::generate;
    use crate::family_b::scenario::Scenario;

    fn outcome(class: Class, before_over_floor: f64) -> Outcome {
        let s = Scenario::new(class, 1);
        let truth = generate(&s).truth;
        Outcome {
            scenario: s,
            named: Vec::new(),
            fired: Vec::new(),
            error: None,
            error_before: before_over_floor * truth.noise_floor,
            error_after_first: f64::NAN,
            floor: truth.noise_floor,
            harmful: Vec::new(),
            millis: 0,
            min_gain: 0.20,
            friction_found: false,
            truth,
        }
    }

    #[test]
    fn an_effect_shows_from_the_floor_over_the_root_of_one_minus_the_gain() {
        // min_gain 0.20: the threshold is 1/√0.8 = 1.118 × the floor.
        assert_eq!(shown(&outcome(Class::Delay, 1.12)), Some(true));
        assert_eq!(shown(&outcome(Class::Delay, 1.11)), Some(false));
        assert_eq!(shown(&outcome(Class::ColouredNoise, 2.0)), None);
        assert_eq!(shown(&outcome(Class::Integrating, 2.0)), None);
        let mut failed = outcome(Class::Drift, 2.0);
        failed.error = Some("failed".into());
        assert_eq!(shown(&failed), None);
        let mut s = String::new();
        resolution_lines(&mut s, &[&outcome(Class::Delay, 1.05)]);
        assert!(
            s.contains("below the resolution: 1 runs: delay seed 1 (1.050× floor, not named)"),
            "{s}"
        );
    }
}
