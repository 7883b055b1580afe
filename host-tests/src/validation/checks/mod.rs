//! The data against the method's assumptions, before any fit. Every violation is a warning
//! that says what was found and what it costs; one file per family of checks.

pub mod advice;
pub mod coverage;
pub mod excitation;
pub mod feedback;
pub mod hold;
pub mod input_levels;
pub mod integrating;
pub mod output;
pub mod setup;
pub mod table1;
pub mod warning;

pub use advice::{BEFORE_FIT, CHECKS, check_advice, checks_text};
pub use output::{Saturation, saturation};
pub use setup::CheckSetup;
pub use warning::{Check, Warning, warn};

/// Runs all checks on an estimation record (`u` and `y` of one length).
pub(crate) fn check_data(u: &[f64], y: &[f64], s: &CheckSetup) -> Vec<Warning> {
    let n = u.len();
    if n < 10 {
        return Vec::new();
    }
    let ex = &u[s.hold.min(n)..];
    let mut out = Vec::new();
    // The first run after the hold starts at the hold's last sample, not at the first sample
    // after it.
    out.extend(table1::table1_structure(
        &u[s.hold.min(n).saturating_sub(1)..],
        s,
    ));
    out.extend(coverage::path_coverage(ex, s));
    out.extend(excitation::persistent_excitation(ex, s));
    out.extend(hold::hold(y, s));
    out.extend(output::output_sensor(y));
    out.extend(input_levels::input_levels(ex));
    out
}
