//! Typed outcomes in words: the findings and the one-paragraph verdict. The loop decides on
//! the types; the prose is made here (the evidence in [`super::evidence`], the dead time in
//! [`super::delay`]).

use std::fmt;

use super::diagnosis::Step;
use super::findings::Finding;
use super::model::Metric;

const OUTSIDE: &str = "found, not in the catalog: ";

impl Finding {
    /// The short name of an effect outside the catalog, as the verdict lists it.
    pub fn outside_name(&self) -> Option<&'static str> {
        match self {
            Finding::DirectionDependence => {
                Some("the residual depends on the direction of the input")
            }
            Finding::StateDependenceBeyondStores => {
                Some("state dependence beyond the level-dependent stores")
            }
            Finding::StateDependence => Some("state-dependent dynamics"),
            Finding::Quantised => Some("the output is quantised"),
            _ => None,
        }
    }

    /// What an effect outside the catalog shows and what it would need.
    fn outside_reason(&self) -> &'static str {
        match self {
            Finding::DirectionDependence => {
                "direction_correlation fires) although the nonlinearity is static: the plant behaves differently when the input falls (e.g. coasting down when the drive returns to 0); a backlash or switch element, or a direction-dependent model, would be needed"
            }
            Finding::StateDependenceBeyondStores => {
                "state_dependence still fires with them: the residual follows the level times the increment of the simulated output in a form the stores do not have); `diagnose::dynamics` has further model classes, measured by the example `tanks_dynamics`"
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

/// The one-paragraph conclusion: what was added and what the final tests still find.
/// `before_rmse`: the validation error before; `after_rmse`: the final model's.
pub fn verdict(
    steps: &[Step],
    findings: &[Finding],
    fired: &[String],
    ending: Ending,
    before_rmse: f64,
    after_rmse: f64,
) -> String {
    let unscorable = findings.iter().any(Finding::unscorable);
    if steps.is_empty() && unscorable {
        return format!(
            "The estimation data cannot score any extension (the inner hold-out block holds behaviour the rest of the record does not show): nothing is added, and the tests that fire ({}) are reported without a diagnosis.",
            fired.join(", ")
        );
    }
    if steps.is_empty() && fired.is_empty() {
        return "No test fires on the estimation residual: the residual is consistent with the model, nothing is added.".to_string();
    }
    if steps.is_empty() {
        return format!(
            "Tests fire ({}) but no catalog effect explains them: the missing effect is not identified; the model is left as identified.",
            fired.join(", ")
        );
    }
    let names: Vec<&str> = steps.iter().map(|s| s.effect.name()).collect();
    let rest = if fired.is_empty() {
        "the final residual is consistent with the extended model".to_string()
    } else if unscorable {
        format!(
            "then the estimation data could not score further extensions; tests still fire ({})",
            fired.join(", ")
        )
    } else if steps.last().is_some_and(|s| !s.effect.deterministic()) {
        format!(
            "the noise model is the last step; on the simulation residual tests still fire ({}) that no deterministic catalog effect explained",
            fired.join(", ")
        )
    } else if ending == Ending::NoCandidate {
        format!(
            "tests still fire ({}) and no further catalog effect explains them",
            fired.join(", ")
        )
    } else {
        format!(
            "the step limit was reached with tests still firing ({})",
            fired.join(", ")
        )
    };
    // Effects found outside the catalog are named, not counted as unexplained tests.
    let outside: Vec<&str> = findings.iter().filter_map(Finding::outside_name).collect();
    let rest = if outside.is_empty() {
        rest
    } else {
        format!("{rest}; {OUTSIDE}{}", outside.join("; "))
    };
    let last_metric = match steps.last().map(|s| s.metric) {
        Some(Metric::Prediction) => " (the last in one-step prediction)",
        _ => "",
    };
    format!(
        "Added {} (in this order); validation error {:.4} → {:.4}{last_metric}; {rest}.",
        names.join(", "),
        before_rmse,
        steps.last().map_or(after_rmse, |s| s.error_after)
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The verdict lists an effect outside the catalog by the words its finding opens with.
    #[test]
    fn outside_names_open_their_findings() {
        for f in [
            Finding::DirectionDependence,
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
