//! A piecewise-constant input with few levels.

use super::warning::{Check, Warning, warn};

/// An input with at most 40 distinct values, each held for 20 samples on average or more.
pub(crate) fn input_levels(ex: &[f64]) -> Vec<Warning> {
    let mut out = Vec::new();
    // Piecewise-constant input with few levels.
    let mut levels = ex.to_vec();
    levels.sort_by(f64::total_cmp);
    levels.dedup();
    if levels.len() <= 40 && levels.len() * 20 < ex.len() {
        out.push(warn(
            Check::InputLevels,
            format!(
                "the input takes only {} distinct values: the nonlinearity is observed at those levels only and interpolated between them, and the dynamics only at the level changes",
                levels.len()
            ),
        ));
    }
    out
}
