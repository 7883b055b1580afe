//! Typed outcomes in words: the findings and the one-paragraph verdict. The loop decides on
//! the types; the prose is made here (the evidence in [`super::evidence`], the dead time in
//! [`super::delay`]).

use std::fmt;

use super::effects::Effect;
use super::findings::Finding;
use super::model::Metric;

const OUTSIDE: &str = "found, not in the catalog: ";

impl Finding {
    /// The short name of an effect outside the catalog, as the verdict lists it.
    pub(crate) fn outside_name(&self) -> Option<&'static str> {
        match self {
            Finding::DirectionDependence => {
                Some("the residual depends on the direction of the input")
            }
            Finding::DirectionDependenceBeyondElement => Some(
                "the residual depends on the direction of the input beyond the element with memory",
            ),
            Finding::StateDependenceBeyondStores => {
                Some("state dependence beyond the level-dependent stores")
            }
            Finding::StateDependence => Some("state-dependent dynamics"),
            Finding::Quantised => Some("the output is quantised"),
            Finding::Friction { .. } => Some(
                "the error depends on the direction the model moves (friction on its velocity)",
            ),
            _ => None,
        }
    }

    /// What an effect outside the catalog shows and what it would need.
    fn outside_reason(&self) -> &'static str {
        match self {
            Finding::DirectionDependence => {
                "direction_correlation fires) although the nonlinearity is static: the plant behaves differently when the input falls (e.g. coasting down when the drive returns to 0); the play operator or relay (`hysteresis`, tried on a model without an output map or stores) was not confirmed by the estimation hold-out, so a direction-dependent model beyond them would be needed"
            }
            Finding::DirectionDependenceBeyondElement => {
                "direction_correlation still fires with the play operator or relay added): the plant behaves differently when the input falls in a way a play or relay on the knots does not represent (e.g. coasting down with dry friction when the drive returns to 0); a direction-dependent model of the dynamics would be needed"
            }
            Finding::StateDependenceBeyondStores => {
                "state_dependence still fires with them: the residual follows the level times the increment of the simulated output in a form the stores do not have); the example `tanks_dynamics` measures further model classes (a polynomial state term, an internal overflow)"
            }
            Finding::StateDependence => {
                "state_dependence fires: the residual follows the level times the increment of the simulated output, a speed or gain that changes with the level); the level-dependent stores (`state_dependent_dynamics`) were not added: they start from an order-2 model, and the hold-out must confirm them"
            }
            Finding::Quantised => {
                "data check output_quantisation); quantisation is measurement noise bounded by half a step and is left in the residual"
            }
            _ => "",
        }
    }
}

impl fmt::Display for Finding {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Finding::Integrating => f.write_str(
                "the output integrates (data check integrating): no extension is scored against a model normalised to G(1) = 1; run `hsid diagnose --integrating`",
            ),
            Finding::FoldsUnfittable { error } => write!(
                f,
                "the estimation data cannot score extensions: the current model cannot be fitted without one of the inner validation's blocks ({error})"
            ),
            Finding::BlockUnscorable {
                start,
                end,
                rmse,
                in_sample,
            } => write!(
                f,
                "the estimation data cannot score extensions: the model fitted without samples {start}..{end} simulates them with RMSE {rmse:.4}, more than 3 × its in-sample RMSE {in_sample:.4} (that block holds behaviour the rest of the record does not show)"
            ),
            Finding::NotExplained {
                test,
                detail,
                p_value,
                tried,
            } => {
                let tried: Vec<String> = tried
                    .iter()
                    .map(|(e, gain, p)| {
                        format!(
                            "{} changes the hold-out MSE by {:+.1} % (p = {:.2})",
                            e.name(),
                            -100.0 * gain,
                            p
                        )
                    })
                    .collect();
                let why = if tried.is_empty() {
                    "no catalog effect left to try".to_string()
                } else {
                    tried.join("; ")
                };
                write!(
                    f,
                    "{test} fired ({detail}; p = {p_value:.2e}) but no catalog effect explains it ({why}): effect not identified"
                )
            }
            Finding::Friction { t, difference } => write!(
                f,
                "{OUTSIDE}{} (the sign of the final model's simulated velocity, a regressor beside the terms of its output-error equation, has the coefficient {difference:+.3e} with t = {t:.1} (Newey–West errors; the finding is made beyond |t| = 3)): Coulomb friction and an offset on the model's velocity are fitted by `hsid identify --friction` (docs/friction.md); the diagnosis does not add them as a step",
                self.outside_name().unwrap_or_default(),
            ),
            outside => write!(
                f,
                "{OUTSIDE}{} ({}",
                outside.outside_name().unwrap_or_default(),
                outside.outside_reason()
            ),
        }
    }
}

/// How the loop ended, for the verdict.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Ending {
    /// No extension passed the inner validation.
    NoCandidate,
    /// The loop ended otherwise (step limit, a noise model, nothing to score).
    Other,
}

/// How the diagnosis ends, for the verdict.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum End {
    /// Nothing added: the output integrates.
    Integrating,
    /// Nothing added: the estimation data cannot score any extension.
    Unscorable,
    /// Nothing added: no test fires on the estimation residual.
    Consistent,
    /// Nothing added: tests fire but no catalog effect explains them.
    NotIdentified,
    /// Effects added; the final residual is consistent with the extended model.
    Explained,
    /// Effects added, then the estimation data could not score further extensions.
    UnscorableAfter,
    /// Effects added, the noise model last; tests still fire on the simulation residual.
    NoiseLast,
    /// Effects added; tests still fire and no further catalog effect explains them.
    NoFurther,
    /// Effects added until the step limit, tests still firing.
    StepLimit,
}

/// The one-paragraph conclusion: what was added and what the final tests still find, in
/// words by `Display`.
#[derive(Clone, Debug, PartialEq)]
pub struct Verdict {
    /// Effects added, in order.
    pub added: Vec<Effect>,
    /// How it ends.
    pub end: End,
    /// Tests that fire on the final estimation residual.
    pub fired: Vec<String>,
    /// Effects found outside the catalog (named, not counted as unexplained tests; listed
    /// when an effect was added).
    pub outside: Vec<Finding>,
    /// Validation error before.
    pub error_before: f64,
    /// Validation error after the last step.
    pub error_after: f64,
    /// Metric of the last step's error.
    pub last_metric: Metric,
}

impl Verdict {
    /// The verdict of the effects added and the findings. `last`: the metric and the
    /// validation error of the last step; `fired`: the tests that fire on the final
    /// estimation residual; `before_rmse`: the validation error before; `after_rmse`: the
    /// final model's.
    pub fn new(
        added: Vec<Effect>,
        last: Option<(Metric, f64)>,
        findings: &[Finding],
        fired: Vec<String>,
        ending: Ending,
        before_rmse: f64,
        after_rmse: f64,
    ) -> Self {
        let unscorable = findings.iter().any(Finding::unscorable);
        let integrating = findings.contains(&Finding::Integrating);
        let end = match added.last() {
            None if integrating => End::Integrating,
            None if unscorable => End::Unscorable,
            None if fired.is_empty() => End::Consistent,
            None => End::NotIdentified,
            Some(_) if fired.is_empty() => End::Explained,
            Some(_) if unscorable => End::UnscorableAfter,
            Some(e) if !e.deterministic() => End::NoiseLast,
            Some(_) if ending == Ending::NoCandidate => End::NoFurther,
            Some(_) => End::StepLimit,
        };
        Verdict {
            added,
            end,
            fired,
            outside: findings
                .iter()
                .filter(|f| f.outside_catalog())
                .cloned()
                .collect(),
            error_before: before_rmse,
            error_after: last.map_or(after_rmse, |l| l.1),
            last_metric: last.map_or(Metric::Simulation, |l| l.0),
        }
    }
}

impl fmt::Display for Verdict {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let fired = self.fired.join(", ");
        let rest = match self.end {
            End::Integrating => {
                return write!(
                    f,
                    "The output integrates (data check integrating): the model's normalisation G(1) = 1 does not hold, so no extension is scored against it and nothing is added; `hsid diagnose --integrating` diagnoses the plant's stable part on the output's increments."
                );
            }
            End::Unscorable => {
                return write!(
                    f,
                    "The estimation data cannot score any extension (the inner hold-out block holds behaviour the rest of the record does not show): nothing is added, and the tests that fire ({fired}) are reported without a diagnosis."
                );
            }
            End::Consistent => {
                return f.write_str(
                    "No test fires on the estimation residual: the residual is consistent with the model, nothing is added.",
                );
            }
            End::NotIdentified => {
                return write!(
                    f,
                    "Tests fire ({fired}) but no catalog effect explains them: the missing effect is not identified; the model is left as identified."
                );
            }
            End::Explained => {
                "the final residual is consistent with the extended model".to_string()
            }
            End::UnscorableAfter => format!(
                "then the estimation data could not score further extensions; tests still fire ({fired})"
            ),
            End::NoiseLast => format!(
                "the noise model is the last step; on the simulation residual tests still fire ({fired}) that no deterministic catalog effect explained"
            ),
            End::NoFurther => {
                format!("tests still fire ({fired}) and no further catalog effect explains them")
            }
            End::StepLimit => {
                format!("the step limit was reached with tests still firing ({fired})")
            }
        };
        let names: Vec<&str> = self.added.iter().map(|e| e.name()).collect();
        let outside: Vec<&str> = self
            .outside
            .iter()
            .filter_map(Finding::outside_name)
            .collect();
        let rest = if outside.is_empty() {
            rest
        } else {
            format!("{rest}; {OUTSIDE}{}", outside.join("; "))
        };
        let last_metric = match self.last_metric {
            Metric::Prediction => " (the last in one-step prediction)",
            Metric::Simulation => "",
        };
        write!(
            f,
            "Added {} (in this order); validation error {:.4} → {:.4}{last_metric}; {rest}.",
            names.join(", "),
            self.error_before,
            self.error_after
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The verdict lists an effect outside the catalog by the words its finding opens with.
    #[test]
    fn outside_names_open_their_findings() {
        for f in [
            Finding::DirectionDependence,
            Finding::DirectionDependenceBeyondElement,
            Finding::StateDependenceBeyondStores,
            Finding::StateDependence,
            Finding::Quantised,
        ] {
            let text = f.to_string();
            assert!(
                f.outside_name()
                    .is_some_and(|name| text.starts_with(&format!("{OUTSIDE}{name} ("))),
                "{text}"
            );
            assert!(f.outside_catalog() && !f.unscorable());
        }
    }
}
