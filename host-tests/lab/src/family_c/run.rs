//! Runs of the diagnosis on the family (in parallel), each scored against its truth and its
//! resolvability.

use super::class::{Class, Loop};
use super::design::Scenario;
use super::generate::{Data, Truth, generate};
use super::resolvable::{Resolvability, resolvability};
use super::servo::Mechanics;
use hsid_host::diagnose::{Check, Diagnosis, Effect, Finding, diagnose};

/// A step that raised the validation error.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Harm {
    /// The effect added.
    pub effect: Effect,
    /// Validation error before the step, in the step's metric.
    pub before: f64,
    /// Validation error after it.
    pub after: f64,
    /// One-sided p-value of the raise ([`Step::p_worse`](hsid_host::diagnose::Step::p_worse)).
    pub p_worse: f64,
}

impl Harm {
    /// Whether the raise is significant at 5 %.
    pub fn significant(&self) -> bool {
        self.p_worse < 0.05
    }

    /// `friction 0.0124 → 0.0131 (+5.6 %, p 0.03)`.
    pub fn describe(&self) -> String {
        format!(
            "{} {:.5} → {:.5} (+{:.1} %, p {:.3})",
            self.effect.name(),
            self.before,
            self.after,
            100.0 * (self.after / self.before - 1.0),
            self.p_worse
        )
    }
}

/// The outcome of one scenario.
#[derive(Clone, Debug)]
pub struct Outcome {
    /// The scenario.
    pub scenario: Scenario,
    /// Its truth.
    pub truth: Truth,
    /// Effects added, in order (empty when the diagnosis failed).
    pub named: Vec<Effect>,
    /// Data checks that fired.
    pub fired: Vec<Check>,
    /// The diagnosis's error, when it failed.
    pub error: Option<String>,
    /// Validation error before (simulation RMSE).
    pub error_before: f64,
    /// Validation error after the last step (its metric), `error_before` without one.
    pub error_after: f64,
    /// Steps whose validation error rose.
    pub harmful: Vec<Harm>,
    /// The diagnosis found friction outside its steps ([`Finding::Friction`]).
    pub friction_found: bool,
    /// Whether the true effect is resolvable on the estimation record.
    pub resolvability: Resolvability,
    /// A two-mass drive's play: the truth `2α` (rad) and the diagnosis's, when its final
    /// model is a two-mass drive (the model's gap, in the output's units × samples, times
    /// the sample time: rad for the motor's speed in rad/s).
    pub play: Option<(f64, Option<f64>)>,
    /// Wall time of the diagnosis, ms.
    pub millis: u128,
}

impl Outcome {
    /// Named right, by [`Class::named_right`]; a failed diagnosis is not.
    pub fn right(&self) -> bool {
        self.error.is_none() && self.scenario.class.named_right(&self.named)
    }

    /// The effect named first.
    pub fn first(&self) -> Option<Effect> {
        self.named.first().copied()
    }

    /// Whether the run counts as resolvable.
    pub fn resolvable(&self) -> bool {
        self.resolvability.resolvable
    }

    /// The play found over the truth's, less 1, when both are known.
    pub fn play_error(&self) -> Option<f64> {
        match self.play {
            Some((truth, Some(found))) => Some(found / truth - 1.0),
            _ => None,
        }
    }

    /// One line for logs.
    pub fn line(&self) -> String {
        let (s, t, d) = (&self.scenario, &self.truth, &self.truth.design);
        let named: Vec<&str> = self.named.iter().map(|e| e.name()).collect();
        let fired: Vec<&str> = self.fired.iter().map(|c| c.name()).collect();
        let harmful: Vec<String> = self.harmful.iter().map(Harm::describe).collect();
        format!(
            "{} {:<12} {:<6} seed {:>2} | {} n {} ts {:.4} s {} {} {} snr {:.1} dB level {:.3}{}{} | named {} | checks {} | before {:.5} after {:.5} floor {:.5} | resolvable {} | harmful {} | {} ms + check {} ms{}{}{}",
            if self.right() { "ok  " } else { "MISS" },
            s.class.name(),
            s.lp.name(),
            s.seed,
            d.plant,
            t.declared_order,
            d.ts,
            d.input.name(),
            t.controller.map_or("open".to_string(), |c| c.describe()),
            d.colour.name(),
            d.snr_db,
            d.level,
            d.pin.map_or(String::new(), |(p, _)| format!(
                " {p:?} pinned {:.3}",
                t.pinned.0
            )),
            if d.segments(s.lp) == 1 {
                " 1 segment"
            } else {
                ""
            },
            if named.is_empty() {
                "-".into()
            } else {
                named.join(" > ")
            },
            if fired.is_empty() {
                "-".into()
            } else {
                fired.join(",")
            },
            self.error_before,
            self.error_after,
            t.noise_floor,
            self.resolvability.describe(),
            if harmful.is_empty() {
                "0".into()
            } else {
                format!("{} ({})", harmful.len(), harmful.join("; "))
            },
            self.millis,
            self.resolvability.millis,
            match (self.play, self.play_error()) {
                (Some((truth, Some(found))), Some(e)) => format!(
                    " | play {truth:.4} rad, found {found:.4} ({:+.1} %)",
                    100.0 * e
                ),
                (Some((truth, None)), _) => format!(" | play {truth:.4} rad, not found"),
                _ => String::new(),
            },
            if self.friction_found {
                " | friction found"
            } else {
                ""
            },
            self.error
                .as_ref()
                .map_or(String::new(), |e| format!(" | error: {e}")),
        )
    }
}

/// The outcome of a diagnosis (or its failure) on generated data, the resolvability decided.
pub fn score(
    s: &Scenario,
    data: &Data,
    result: Result<&Diagnosis, String>,
    millis: u128,
) -> Outcome {
    let mut o = Outcome {
        scenario: *s,
        truth: data.truth.clone(),
        named: Vec::new(),
        fired: Vec::new(),
        error: None,
        error_before: f64::NAN,
        error_after: f64::NAN,
        harmful: Vec::new(),
        friction_found: false,
        resolvability: resolvability(data, s.class, result.as_ref().ok().copied()),
        play: match &data.truth.servo.mechanics {
            Mechanics::TwoMass(d) if d.half_play > 0.0 => Some((
                2.0 * d.half_play,
                result
                    .as_ref()
                    .ok()
                    .and_then(|r| r.model.two_mass.as_ref())
                    .map(|tm| tm.gap() * data.truth.design.ts),
            )),
            _ => None,
        },
        millis,
    };
    match result {
        Err(e) => o.error = Some(e),
        Ok(d) => {
            o.named = d.steps.iter().map(|s| s.effect).collect();
            o.fired = d.warnings.iter().map(|w| w.check).collect();
            o.fired.dedup();
            o.friction_found = d
                .unexplained
                .iter()
                .any(|f| matches!(f, Finding::Friction { .. }));
            o.error_before = d.before.rmse;
            o.error_after = d.steps.last().map_or(d.before.rmse, |s| s.error_after);
            o.harmful = d
                .steps
                .iter()
                .filter(|s| s.error_after > s.error_before)
                .map(|s| Harm {
                    effect: s.effect,
                    before: s.error_before,
                    after: s.error_after,
                    p_worse: s.p_worse,
                })
                .collect();
        }
    }
    o
}

/// Simulates, diagnoses and scores one scenario; `report` sees the diagnosis.
pub fn run_one(s: &Scenario, report: &(dyn Fn(&Diagnosis) + Sync)) -> Outcome {
    let data = generate(s);
    let clock = std::time::Instant::now();
    let result = diagnose(&data.record, &data.validation, &data.options);
    let millis = clock.elapsed().as_millis();
    if let Ok(d) = &result {
        report(d);
    }
    score(s, &data, result.as_ref().map_err(|e| e.to_string()), millis)
}

/// The scenarios of a run: `seeds` seeds of every class in open and closed loop.
pub fn family(seeds: u64) -> Vec<Scenario> {
    let mut out = Vec::new();
    for class in Class::ALL {
        for lp in Loop::ALL {
            out.extend((1..=seeds).map(|seed| Scenario::new(class, lp, seed)));
        }
    }
    out
}

/// Runs scenarios on `threads` threads, calling `progress` after each and `report` on each
/// diagnosis; the outcomes in the scenarios' order.
pub fn run_all(
    scenarios: &[Scenario],
    threads: usize,
    progress: &(dyn Fn(&Outcome) + Sync),
    report: &(dyn Fn(&Diagnosis) + Sync),
) -> Vec<Outcome> {
    crate::parallel::in_parallel(scenarios, threads, &|s| run_one(s, report), progress)
}
