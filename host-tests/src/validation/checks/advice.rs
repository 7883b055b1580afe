//! What each data check means when it fires and what the user can do about it, in one
//! sentence each, and the checks as lines of text: the same words in the terminal of
//! `identify` and `diagnose` and in the HTML pages' table.

use super::warning::{Check, Warning};

/// The data checks run on a record before any fit (`validation::checks::check_data`), in
/// their order: what an identification's page can report.
pub const BEFORE_FIT: [Check; 7] = [
    Check::Table1Structure,
    Check::PathCoverage,
    Check::PersistentExcitation,
    Check::Hold,
    Check::OutputSaturation,
    Check::OutputQuantisation,
    Check::InputLevels,
];

/// Every data check, in the order `diagnose` runs them: those before any fit, then the two
/// on the base model's residual and poles.
pub const CHECKS: [Check; 9] = {
    let mut all = [Check::Integrating; 9];
    let mut i = 0;
    while i < BEFORE_FIT.len() {
        all[i] = BEFORE_FIT[i];
        i += 1;
    }
    all[7] = Check::Feedback;
    all
};

/// `(what it means, what to do)` for a data check that warns.
pub fn check_advice(c: Check) -> (&'static str, &'static str) {
    match c {
        Check::Table1Structure => (
            "A monotone run of the input starts inside the interval: the method's excitation \
             (Table I) has every run start at u_min or u_max, so that the element's path is known.",
            "Record with the method's excitation (hsid excite); or fit the play operator or \
             relay itself by simulation error (hsid identify --fit simulation, which the \
             default --fit auto runs on such a record); or identify the element as static \
             (--nonlinearity static) if it has no memory.",
        ),
        Check::PathCoverage => (
            "A path is not visited over the whole interval: its border there is extrapolated.",
            "Sweep the input over [u_min, u_max] in both directions, or narrow --umin/--umax \
             to what the record covers.",
        ),
        Check::PersistentExcitation => (
            "The regressor is not persistently exciting: some border values and dynamics are \
             not determined by the record.",
            "Record longer or with more reversals, or use fewer segments (--segments) or \
             shorter horizons (--f, --p).",
        ),
        Check::Hold => (
            "No settled hold at u_min: the border's start value μ0 is not measured.",
            "Start the record with a hold at u_min longer than the plant settles, or give μ0 \
             (--mu0) and --hold 0.",
        ),
        Check::OutputSaturation => (
            "The output sits at an extreme: a clipped sensor or actuator, which the model \
             does not describe.",
            "Reduce the input range so the output stays inside the sensor's range, or cut \
             the saturated stretch out of the record.",
        ),
        Check::OutputQuantisation => (
            "The output takes values on a grid: the sensor's resolution adds an error the \
             noise model does not assume.",
            "Use a finer sensor setting; otherwise expect the fit to stop at the grid step.",
        ),
        Check::InputLevels => (
            "The input takes few distinct values: the borders between those levels are not \
             determined.",
            "Use sweeps through many levels (hsid excite) rather than steps.",
        ),
        Check::Integrating => (
            "The base model has a pole too slow for the record: the plant integrates \
             (position from a voltage, a level) or the output drifts, and the gain \
             normalisation G(1) = 1 is meaningless.",
            "For an integrating plant, diagnose its stable part with --integrating (the \
             output's increments); for a drifting sensor, let offset_drift model it.",
        ),
        Check::Order => (
            "The estimate of the declared order has a static gain that cannot be told from \
             zero, so it cannot be normalised to G(1) = 1: the record supports fewer states \
             (or the plant differentiates its input, which is outside the model class). The \
             diagnosis started from the highest order that can be normalised.",
            "Give that order (--order); the unmodeled_dynamics step says whether more states \
             pay on the extended model. Sample faster or record longer to support more.",
        ),
        Check::Feedback => (
            "The input is correlated with earlier residuals: it was computed from the measured \
             output (closed loop), which biases the open-loop estimate toward the controller.",
            "Record an open-loop experiment (an input not computed from the output, e.g. hsid \
             excite). A model far from the data can also look like feedback: see the other \
             warnings first.",
        ),
    }
}

/// The data checks `run` with the warnings they gave, as lines: one summary line (`data
/// checks: all 7 passed (…)` or `data checks: 6 of 7 passed, 1 warning:`), then per warning
/// its check, its finding and what to do.
pub fn checks_text(warnings: &[Warning], run: &[Check]) -> Vec<String> {
    let fired: Vec<&Warning> = warnings.iter().filter(|w| run.contains(&w.check)).collect();
    let names = run
        .iter()
        .map(|c| c.to_string())
        .collect::<Vec<_>>()
        .join(", ");
    let ran = run.len();
    if fired.is_empty() {
        return vec![format!(
            "data checks: all {ran} passed, the data meet the method's assumptions ({names})"
        )];
    }
    let failed = run
        .iter()
        .filter(|c| fired.iter().any(|w| w.check == **c))
        .count();
    let mut lines = vec![format!(
        "data checks: {} of {ran} passed, {} warning{} ({names}):",
        ran - failed,
        fired.len(),
        if fired.len() == 1 { "" } else { "s" }
    )];
    for w in fired {
        let (meaning, action) = check_advice(w.check);
        lines.push(format!(
            "  warning [{}]: {} {meaning} What to do: {action}",
            w.check, w.message
        ));
    }
    lines
}
