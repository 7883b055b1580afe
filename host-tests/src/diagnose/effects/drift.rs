//! Offset or drift: a polynomial trend in time of degree 0 to 2, or an offset with an
//! exponential settling.

use super::candidate::Candidate;
use super::catalog::Effect;
use super::proposal::Proposal;
use crate::diagnose::error::DiagnoseError;
use crate::diagnose::model::Metric;

/// Time constants of the settling term tried, in half-lengths of the estimation record, in
/// steps of √2: from a settling over the record's first tenth to one still far from its level
/// at the end (close to a ramp there). Chosen on the hold-out like the degree: a time
/// constant estimated with the dynamics is traded against slow poles, and on the fitting part
/// alone it came out at ramp-like values where the hold-out preferred a settling.
pub const SETTLING: [f64; 9] = [0.125, 0.177, 0.25, 0.354, 0.5, 0.707, 1.0, 1.414, 2.0];

impl Proposal<'_> {
    /// Trends of degree 0, 1 and 2, then an offset with an exponential settling of each time
    /// constant in [`SETTLING`]. A settling drift (a sensor warming up) levels off, which no
    /// polynomial fitted on the record carries past its end.
    pub fn offset_drift(&self) -> Result<Option<Candidate>, DiagnoseError> {
        let effect = Effect::OffsetDrift;
        let half = self.holdout.opts.time_scale.max(1.0);
        let polynomials = (0..=2).map(|d| {
            (
                format!("degree {d}"),
                self.with(|s| {
                    s.trend_degree = Some(d);
                    s.settling = None;
                }),
            )
        });
        let settling = SETTLING.iter().map(|&k| {
            (
                format!("settling T = {:.0} samples", k * half),
                self.with(|s| {
                    s.trend_degree = Some(0);
                    s.settling = Some(k);
                }),
            )
        });
        self.best_of(
            effect,
            polynomials.chain(settling).collect(),
            Metric::Simulation,
        )
    }
}
