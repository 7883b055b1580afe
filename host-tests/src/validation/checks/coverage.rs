//! Both paths over the whole interval: samples per knot segment and path.

use super::setup::CheckSetup;
use super::warning::{Check, Warning, warn};
use crate::validation::residual::regressor::{channel_count, samples};

/// Knot segments with too few samples.
pub(crate) fn path_coverage(ex: &[f64], s: &CheckSetup) -> Vec<Warning> {
    let mut out = Vec::new();
    let shared = s.shared();
    // Both paths over the whole interval.
    let count = channel_count(s.knots_asc, s.knots_desc, shared);
    let na = s.knots_asc.len().saturating_sub(1);
    let mut counts = vec![0usize; count];
    for r in samples(ex, s.knots_asc, s.knots_desc, shared) {
        if let Some(c) = counts.get_mut(r.bin) {
            *c += 1;
        }
    }
    let need = 20.max(ex.len() / (5 * count.max(1)));
    let mut poor = Vec::new();
    for (b, &c) in counts.iter().enumerate() {
        if c < need {
            let (path, k, j) = if b < na || shared {
                ("ascending", s.knots_asc, b)
            } else {
                ("descending", s.knots_desc, b - na)
            };
            let path = if shared { "static" } else { path };
            if let (Some(a), Some(bb)) = (k.get(j), k.get(j + 1)) {
                poor.push(format!("{path} [{a:.3}, {bb:.3}]: {c}"));
            }
        }
    }
    if !poor.is_empty() {
        out.push(warn(
            Check::PathCoverage,
            format!(
                "knot segments with fewer than {need} samples ({}): their border values are poorly determined (interpolated or extrapolated from neighbours)",
                poor.join("; ")
            ),
        ));
    }
    out
}
