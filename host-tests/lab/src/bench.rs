//! Runs of the diagnosis on simulated scenarios (parallel), scored against the truth: the
//! effect named first, the validation error before and after, the noise floor; and the
//! confusion table of true against named effects.

use std::fmt::Write as _;

use hsid_host::diagnose::{DiagnoseError, DiagnoseOptions, Effect, Metric, Proposing, diagnose};

use crate::scenario::{Scenario, generate};

/// The outcome of one scenario.
#[derive(Clone, Debug)]
pub struct Outcome {
    /// The scenario.
    pub scenario: Scenario,
    /// Validation error of the model before (simulation RMSE).
    pub error_before: f64,
    /// Validation error after the first effect, in its metric (prediction for
    /// `colored_noise`, outliers excluded for `outliers`); `error_before` when none was added.
    pub error_after_first: f64,
    /// Validation error of the final model (simulation).
    pub error_final: f64,
    /// The noise floor of `error_after_first`: RMS of the noise added over the validation
    /// samples (of the white innovations for a prediction error).
    pub floor: f64,
    /// Tests that fired on the validation residual before.
    pub fired_before: Vec<String>,
    /// Every step added, in order, with its validation errors.
    pub steps: Vec<StepOutcome>,
    /// Wall time, ms.
    pub millis: u128,
    /// The diagnosis found friction outside the catalog
    /// ([`Finding::Friction`](hsid_host::diagnose::Finding::Friction)).
    pub friction_found: bool,
}

/// One step of a run: its effect and setting, its validation error before and after (in the
/// step's metric) and the p-value that it raised the error.
#[derive(Clone, Debug)]
pub struct StepOutcome {
    /// The effect added.
    pub effect: Effect,
    /// Its setting, in words.
    pub setting: String,
    /// Validation error before the step.
    pub error_before: f64,
    /// Validation error after the step.
    pub error_after: f64,
    /// One-sided p-value of a raise ([`Step::p_worse`](hsid_host::diagnose::Step::p_worse)).
    pub p_worse: f64,
}

impl StepOutcome {
    /// Whether the step raised the validation error.
    pub fn raised(&self) -> bool {
        self.error_after > self.error_before
    }

    /// Whether it raised it significantly at 5 %.
    pub fn raised_significantly(&self) -> bool {
        self.raised() && self.p_worse < 0.05
    }
}

impl Outcome {
    /// Effects added, in order.
    pub fn named(&self) -> Vec<Effect> {
        self.steps.iter().map(|st| st.effect).collect()
    }

    /// Steps added that raised the validation error (each step's error after above its error
    /// before, in the step's metric): steps that hurt.
    pub fn harmful(&self) -> Vec<Effect> {
        self.steps
            .iter()
            .filter(|st| st.raised())
            .map(|st| st.effect)
            .collect()
    }

    /// The first effect named, if any.
    pub fn first(&self) -> Option<Effect> {
        self.steps.first().map(|st| st.effect)
    }

    /// Whether the diagnosis did what the issue asks: the right effect named first, the error
    /// after ≤ 0.7 × before and ≤ 1.3 × the noise floor; on clean data, nothing added.
    pub fn passes(&self) -> bool {
        match self.scenario.effect {
            None => self.steps.is_empty(),
            Some(e) => {
                self.first() == Some(e)
                    && self.error_after_first <= 0.7 * self.error_before
                    && self.error_after_first <= 1.3 * self.floor
            }
        }
    }

    /// One line for logs.
    pub fn line(&self) -> String {
        let s = &self.scenario;
        format!(
            "{} {:<21} {:<11} {:<8} seed {:>2} | named {:<40} | before {:.4} after {:.4} ({:.2}×) floor {:.4} ({:.2}×) | harmful steps {}{} | {} ms{}",
            if self.passes() { "ok  " } else { "FAIL" },
            s.effect.map_or("clean", Effect::name),
            s.plant.name(),
            s.kind.name(),
            s.seed,
            self.named()
                .iter()
                .map(|e| e.name())
                .collect::<Vec<_>>()
                .join(" > "),
            self.error_before,
            self.error_after_first,
            self.error_after_first / self.error_before,
            self.floor,
            self.error_after_first / self.floor,
            self.harmful().len(),
            self.steps
                .iter()
                .filter(|st| st.raised())
                .map(|st| format!(
                    " ({} {:.6} → {:.6}, {:+.2} %, p {:.2})",
                    st.effect.name(),
                    st.error_before,
                    st.error_after,
                    100.0 * (st.error_after / st.error_before - 1.0),
                    st.p_worse
                ))
                .collect::<String>(),
            self.millis,
            if self.friction_found {
                " | friction found"
            } else {
                ""
            }
        )
    }
}

/// Simulates and diagnoses one scenario with its options.
pub fn run_one(s: &Scenario) -> Result<Outcome, DiagnoseError> {
    run_adjusted(s, &|_| {})
}

/// Simulates and diagnoses one scenario with its options as `adjust` leaves them (e.g.
/// another minimum gain, for a sweep of the step rule).
pub fn run_adjusted(
    s: &Scenario,
    adjust: &(dyn Fn(&mut DiagnoseOptions) + Sync),
) -> Result<Outcome, DiagnoseError> {
    let mut data = generate(s).map_err(DiagnoseError::Output)?;
    adjust(&mut data.options);
    let t = std::time::Instant::now();
    let d = diagnose(&data.record, &data.validation, &data.options)?;
    let millis = t.elapsed().as_millis();
    let first = d.steps.first();
    let prediction = first.is_some_and(|f| f.metric == Metric::Prediction);
    Ok(Outcome {
        scenario: *s,
        error_before: d.before.rmse,
        error_after_first: first.map_or(d.before.rmse, |f| f.error_after),
        error_final: d.after.rmse,
        floor: if prediction {
            data.innovation_floor
        } else {
            data.noise_floor
        },
        fired_before: d.tests_before.fired_names(),
        steps: d
            .steps
            .iter()
            .map(|s| StepOutcome {
                effect: s.effect,
                setting: s.setting.clone(),
                error_before: s.error_before,
                error_after: s.error_after,
                p_worse: s.p_worse,
            })
            .collect(),
        millis,
        friction_found: d
            .unexplained
            .iter()
            .any(|f| matches!(f, hsid_host::diagnose::Finding::Friction { .. })),
    })
}

/// Runs scenarios on `threads` threads with the options `adjust` leaves (see
/// [`run_adjusted`]); `progress` is called after each.
pub fn run_all(
    scenarios: &[Scenario],
    threads: usize,
    adjust: &(dyn Fn(&mut DiagnoseOptions) + Sync),
    progress: &(dyn Fn(&Outcome) + Sync),
) -> Vec<Result<Outcome, String>> {
    crate::parallel::in_parallel(
        scenarios,
        threads,
        &|s| run_adjusted(s, adjust).map_err(|e| e.to_string()),
        &|r| {
            if let Ok(o) = r {
                progress(o);
            }
        },
    )
}

/// The confusion table (Markdown): rows the true effect, columns the effect named first.
pub fn confusion_table(outcomes: &[Outcome]) -> String {
    let mut rows: Vec<Option<Effect>> = vec![None];
    rows.extend(Effect::ALL.into_iter().map(Some));
    let name = |e: Option<Effect>| e.map_or("none (clean)", Effect::name);
    // Columns: every effect the diagnosis can name first.
    let mut cols = rows.clone();
    cols.push(Some(Effect::StateDependentDynamics));
    let mut s = String::new();
    let _ = write!(s, "| true \\ named first |");
    for c in &cols {
        let _ = write!(s, " {} |", name(*c));
    }
    let _ = writeln!(s, " runs | passed |");
    let _ = write!(s, "|---|");
    for _ in &cols {
        let _ = write!(s, "---|");
    }
    let _ = writeln!(s, "---|---|");
    for r in &rows {
        let mine: Vec<&Outcome> = outcomes
            .iter()
            .filter(|o| o.scenario.effect == *r)
            .collect();
        if mine.is_empty() {
            continue;
        }
        let _ = write!(s, "| **{}** |", name(*r));
        for c in &cols {
            let k = mine.iter().filter(|o| o.first() == *c).count();
            if k == 0 {
                let _ = write!(s, " · |");
            } else {
                let _ = write!(s, " {k} |");
            }
        }
        let passed = mine.iter().filter(|o| o.passes()).count();
        let _ = writeln!(s, " {} | {passed} |", mine.len());
    }
    s
}

/// What a bench changes in each scenario's diagnosis options, from its flags `--min-gain G`
/// and `--propose-every`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BenchSettings {
    /// [`DiagnoseOptions::min_gain`] (`None`: the scenario's own).
    pub min_gain: Option<f64>,
    /// [`Proposing::Every`] instead of the scenario's own.
    pub propose_every: bool,
}

impl BenchSettings {
    /// Sets the options the flags name.
    pub fn apply(&self, o: &mut DiagnoseOptions) {
        if let Some(g) = self.min_gain {
            o.min_gain = g;
        }
        if self.propose_every {
            o.proposing = Proposing::Every;
        }
    }
}

/// The bench flags `--min-gain G` and `--propose-every` taken out of a bench's arguments: the
/// [`BenchSettings`] and the other arguments in order; an error when `G` is missing or not in
/// [0, 1).
pub fn take_bench_flags(args: Vec<String>) -> Result<(BenchSettings, Vec<String>), String> {
    let mut settings = BenchSettings::default();
    let mut rest = Vec::new();
    let mut it = args.into_iter();
    while let Some(a) = it.next() {
        match a.as_str() {
            "--propose-every" => settings.propose_every = true,
            "--min-gain" => {
                let g = it
                    .next()
                    .and_then(|v| v.parse::<f64>().ok())
                    .filter(|g| (0.0..1.0).contains(g))
                    .ok_or("--min-gain takes a number in [0, 1): the least relative MSE reduction of a step")?;
                settings.min_gain = Some(g);
            }
            _ => rest.push(a),
        }
    }
    Ok((settings, rest))
}

#[cfg(test)]
mod tests {
    use super::{BenchSettings, DiagnoseOptions, Proposing, take_bench_flags};

    fn args(a: &[&str]) -> Vec<String> {
        a.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn the_bench_flags_are_taken_out_and_checked() -> Result<(), String> {
        let (b, rest) = take_bench_flags(args(&["6", "--min-gain", "0.1", "10"]))?;
        assert_eq!(
            b,
            BenchSettings {
                min_gain: Some(0.1),
                propose_every: false
            }
        );
        assert_eq!(rest, args(&["6", "10"]));
        let (b, rest) = take_bench_flags(args(&["--propose-every", "6", "10"]))?;
        assert!(b.propose_every && b.min_gain.is_none());
        assert_eq!(rest, args(&["6", "10"]));
        let (b, rest) = take_bench_flags(args(&["6", "10"]))?;
        assert_eq!((b, rest), (BenchSettings::default(), args(&["6", "10"])));
        for bad in [
            &["--min-gain"][..],
            &["--min-gain", "1"],
            &["--min-gain", "x"],
        ] {
            match take_bench_flags(args(bad)) {
                Err(e) => assert!(e.contains("[0, 1)"), "{e}"),
                Ok(v) => return Err(format!("{bad:?} taken as {v:?}")),
            }
        }
        let id = hsid_host::identify::IdentifyOptions::uniform(0.0, 1.0, 4, 0);
        let mut o = DiagnoseOptions::new(id, hsid_host::model::Element::Static);
        assert_eq!(o.proposing, Proposing::WithEvidence);
        BenchSettings {
            min_gain: Some(0.05),
            propose_every: true,
        }
        .apply(&mut o);
        assert_eq!((o.min_gain, o.proposing), (0.05, Proposing::Every));
        Ok(())
    }
}
