//! Runs of the diagnosis on the family (in parallel), each scored against its truth.

use super::class::Class;
use super::generate::{Truth, generate};
use super::scenario::Scenario;
use hsid_host::diagnose::{Check, DiagnoseOptions, Effect, Metric, diagnose};

/// The outcome of one scenario.
#[derive(Clone, Debug)]
pub struct Outcome {
    /// The scenario.
    pub scenario: Scenario,
    /// Its truth.
    pub truth: Truth,
    /// Effects added, in order (empty when the diagnosis failed).
    pub named: Vec<Effect>,
    /// Data checks that fired on the estimation record.
    pub fired: Vec<Check>,
    /// The diagnosis's error, when it failed.
    pub error: Option<String>,
    /// Validation error before (simulation RMSE).
    pub error_before: f64,
    /// Validation error after the first step, in its metric (`error_before` without one).
    pub error_after_first: f64,
    /// The floor of `error_after_first`: RMS of the validation noise, or of its innovations
    /// when the first step's metric is the one-step prediction.
    pub floor: f64,
    /// Steps whose validation error after is above their error before.
    pub harmful: Vec<Harm>,
    /// Wall time of the diagnosis, ms.
    pub millis: u128,
    /// The minimum gain the diagnosis ran with ([`DiagnoseOptions::min_gain`]).
    pub min_gain: f64,
    /// The diagnosis found friction outside the catalog
    /// ([`Finding::Friction`](hsid_host::diagnose::Finding::Friction)).
    pub friction_found: bool,
}

/// A step that raised the validation error.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Harm {
    /// The effect added.
    pub effect: Effect,
    /// Validation error before the step, in the step's metric.
    pub before: f64,
    /// Validation error after it.
    pub after: f64,
    /// One-sided p-value of the raise (paired Diebold–Mariano on the validation samples,
    /// [`Step::p_worse`](hsid_host::diagnose::Step::p_worse)).
    pub p_worse: f64,
}

impl Harm {
    /// Whether the raise is significant at 5 %.
    pub fn significant(&self) -> bool {
        self.p_worse < 0.05
    }

    /// In words: `outliers 0.012402 → 0.012548, +1.18 %, p 0.21`.
    pub fn describe(&self) -> String {
        format!(
            "{} {:.6} → {:.6}, +{:.2} %, p {:.2}",
            self.effect.name(),
            self.before,
            self.after,
            100.0 * (self.after / self.before - 1.0),
            self.p_worse
        )
    }
}

impl Outcome {
    /// The effect named first.
    pub fn first(&self) -> Option<Effect> {
        self.named.first().copied()
    }

    /// Named right, by [`Class::named_right`]; a failed diagnosis is not.
    pub fn right(&self) -> bool {
        self.error.is_none() && self.scenario.class.named_right(self.first(), &self.fired)
    }

    /// One line for logs.
    pub fn line(&self) -> String {
        let (s, t, d) = (&self.scenario, &self.truth, &self.truth.design);
        let named: Vec<&str> = self.named.iter().map(|e| e.name()).collect();
        let fired: Vec<&str> = self.fired.iter().map(|c| c.name()).collect();
        format!(
            "{} {:<17} seed {:>2} | n {} ts {:.2} {:<9} {:<8} {:<15} snr {:>4.1} dB | named {:<36} | checks {:<32} | before {:.4} after {:.4} ({:.2}×) floor {:.4} ({:.2}×) | harmful {}{} | {} ms{}{}",
            if self.right() { "ok  " } else { "MISS" },
            s.class.name(),
            s.seed,
            t.declared_order,
            d.ts,
            d.input.name(),
            d.kind.name(),
            d.colour.name(),
            d.snr_db,
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
            self.error_after_first,
            self.error_after_first / self.error_before,
            self.floor,
            self.error_after_first / self.floor,
            self.harmful.len(),
            if self.harmful.is_empty() {
                String::new()
            } else {
                let h: Vec<String> = self.harmful.iter().map(Harm::describe).collect();
                format!(" ({})", h.join("; "))
            },
            self.millis,
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

/// Simulates and diagnoses one scenario with the family's options.
pub fn run_one(s: &Scenario) -> Outcome {
    run_adjusted(s, &|_| {})
}

/// Simulates and diagnoses one scenario with the family's options as `adjust` leaves them
/// (e.g. another minimum gain, for a sweep of the step rule).
pub fn run_adjusted(s: &Scenario, adjust: &(dyn Fn(&mut DiagnoseOptions) + Sync)) -> Outcome {
    let mut data = generate(s);
    adjust(&mut data.options);
    let clock = std::time::Instant::now();
    let result = diagnose(&data.record, &data.validation, &data.options);
    let millis = clock.elapsed().as_millis();
    let mut o = Outcome {
        scenario: *s,
        truth: data.truth.clone(),
        named: Vec::new(),
        fired: Vec::new(),
        error: None,
        error_before: f64::NAN,
        error_after_first: f64::NAN,
        floor: data.truth.noise_floor,
        harmful: Vec::new(),
        millis,
        min_gain: data.options.min_gain,
        friction_found: false,
    };
    match result {
        Err(e) => o.error = Some(e.to_string()),
        Ok(d) => {
            let first = d.steps.first();
            o.named = d.steps.iter().map(|s| s.effect).collect();
            o.fired = d.warnings.iter().map(|w| w.check).collect();
            o.fired.dedup();
            o.friction_found = d
                .unexplained
                .iter()
                .any(|f| matches!(f, hsid_host::diagnose::Finding::Friction { .. }));
            o.error_before = d.before.rmse;
            o.error_after_first = first.map_or(d.before.rmse, |f| f.error_after);
            if first.is_some_and(|f| f.metric == Metric::Prediction) {
                o.floor = data.truth.innovation_floor;
            }
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

/// The scenarios of a full run: `clean` clean seeds and `seeds` seeds of every other class.
pub fn family(seeds: u64, clean: u64) -> Vec<Scenario> {
    let mut out: Vec<Scenario> = (1..=clean)
        .map(|s| Scenario::new(Class::Clean, s))
        .collect();
    for c in Class::ALL.into_iter().filter(|&c| c != Class::Clean) {
        out.extend((1..=seeds).map(|s| Scenario::new(c, s)));
    }
    out
}

/// Runs scenarios on `threads` threads with the options `adjust` leaves (see
/// [`run_adjusted`]), calling `progress` after each; the outcomes in the scenarios' order.
pub fn run_all(
    scenarios: &[Scenario],
    threads: usize,
    adjust: &(dyn Fn(&mut DiagnoseOptions) + Sync),
    progress: &(dyn Fn(&Outcome) + Sync),
) -> Vec<Outcome> {
    crate::parallel::in_parallel(scenarios, threads, &|s| run_adjusted(s, adjust), progress)
}
