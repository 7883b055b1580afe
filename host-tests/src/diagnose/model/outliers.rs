//! Outliers flagged by the MAD rule.

use crate::numerics::rms;
use crate::validation::stats::{mad_sigma, running_median};

/// Flags isolated outliers of a residual: the residual minus its running median (window 7) is
/// beyond `k` robust standard deviations (1.4826 MAD), in runs of at most two samples.
pub fn detect_outliers(r: &[f64], k: f64) -> Vec<bool> {
    let n = r.len();
    if n < 8 {
        return vec![false; n];
    }
    let med = running_median(r, 7);
    let s: Vec<f64> = r.iter().zip(&med).map(|(a, b)| a - b).collect();
    let sigma = mad_sigma(&s).max(1e-3 * rms(&s)).max(1e-300);
    let mut flags: Vec<bool> = s.iter().map(|v| v.abs() > k * sigma).collect();
    let mut i = 0;
    while i < n {
        if flags[i] {
            let mut j = i;
            while j < n && flags[j] {
                j += 1;
            }
            if j - i > 2 {
                for f in &mut flags[i..j] {
                    *f = false;
                }
            }
            i = j;
        } else {
            i += 1;
        }
    }
    flags
}
