//! The hold at `u_min` that measures μ0: present, and the output settled in it.

use super::setup::CheckSetup;
use super::warning::{Check, Warning, warn};
use crate::validation::stats::{mean, newey_west_var_of_mean, normal_sf};

/// A missing hold (without a known μ0), or an output still moving in it.
pub fn hold(y: &[f64], s: &CheckSetup) -> Vec<Warning> {
    let mut out = Vec::new();
    let n = y.len();
    // Hold for μ0.
    if s.hold > 0 {
        let settled = &y[s.settle.min(s.hold)..s.hold.min(n)];
        if settled.len() >= 20 {
            let h = settled.len() / 2;
            let (a, b) = (&settled[..h], &settled[h..]);
            let lags = 5;
            let diff = mean(a) - mean(b);
            let se = (newey_west_var_of_mean(a, lags) + newey_west_var_of_mean(b, lags)).sqrt();
            let z = diff / se.max(1e-300);
            if 2.0 * normal_sf(z.abs()) < 0.01 {
                out.push(warn(
                    Check::Hold,
                    format!(
                        "the output still moves during the hold (first half − second half = {diff:.4}, z = {z:.1}): μ0 from the hold is biased; a longer hold or settle helps"
                    ),
                ));
            }
        }
    } else if !s.mu0_known {
        out.push(warn(
            Check::Hold,
            "no hold at u_min: μ0 is estimated with the model from the whole record (row-centred Hankel products, μ0 = mean(y) − μ·mean(z)); the paper's method measures it in a hold".into(),
        ));
    }
    out
}
