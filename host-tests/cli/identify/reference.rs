//! `--reference-column` refused where the closed-loop estimate does not apply.

use crate::failure::Failure;

/// The refusal of `--reference-column NAME` with `--nonlinearity static` (diagnose's; identify
/// has the library's request check, in the same words).
pub fn static_refused(name: &str) -> Failure {
    format!(
        "--reference-column {name} estimates a two-path element (backlash or switch): drop --nonlinearity static"
    )
    .into()
}
