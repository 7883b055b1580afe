//! Periodic disturbance: a sinusoid at the residual's strongest line, its frequency refined.

use super::candidate::Candidate;
use super::catalog::Effect;
use super::proposal::Proposal;
use crate::diagnose::error::DiagnoseError;
use crate::diagnose::model::Metric;
use crate::validation::stats::periodogram;

impl Proposal<'_> {
    /// A sinusoid at the refined frequency of the strongest spectral line.
    pub fn periodic_disturbance(&self) -> Result<Option<Candidate>, DiagnoseError> {
        let effect = Effect::PeriodicDisturbance;
        let Some(w) = refine_frequency(self.residual, self.tests.line_frequency) else {
            return Ok(None);
        };
        let opts = vec![(format!("ω = {w:.5}"), self.with(|s| s.frequencies.push(w)))];
        self.best_of(effect, opts, Metric::Simulation)
    }
}

/// Power of the least-squares sinusoid at `w` in `r`.
fn sinusoid_power(r: &[f64], w: f64) -> f64 {
    let (mut cc, mut ss, mut cs, mut rc, mut rs) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for (t, v) in r.iter().enumerate() {
        let (s, c) = (w * t as f64).sin_cos();
        cc += c * c;
        ss += s * s;
        cs += c * s;
        rc += v * c;
        rs += v * s;
    }
    let det = cc * ss - cs * cs;
    if det.abs() < 1e-300 {
        return 0.0;
    }
    let a = (rc * ss - rs * cs) / det;
    let b = (rs * cc - rc * cs) / det;
    a * rc + b * rs
}

/// Refines a spectral line's frequency by maximising the least-squares sinusoid's power
/// (golden section within two periodogram bins).
pub fn refine_frequency(r: &[f64], w0: f64) -> Option<f64> {
    if !(w0 > 0.0 && w0 < std::f64::consts::PI) || r.len() < 16 {
        return None;
    }
    let (omega, _) = periodogram(r);
    let bin = omega.first().copied().unwrap_or(0.01);
    let (mut a, mut b) = (
        (w0 - 2.0 * bin).max(1e-6),
        (w0 + 2.0 * bin).min(std::f64::consts::PI),
    );
    let g = 0.618_033_988_749_895;
    let mut x1 = b - g * (b - a);
    let mut x2 = a + g * (b - a);
    let mut f1 = sinusoid_power(r, x1);
    let mut f2 = sinusoid_power(r, x2);
    for _ in 0..40 {
        if f1 > f2 {
            b = x2;
            x2 = x1;
            f2 = f1;
            x1 = b - g * (b - a);
            f1 = sinusoid_power(r, x1);
        } else {
            a = x1;
            x1 = x2;
            f1 = f2;
            x2 = a + g * (b - a);
            f2 = sinusoid_power(r, x2);
        }
    }
    Some(0.5 * (a + b))
}
