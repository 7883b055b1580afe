//! Integrating plants (voltage → position, a level loop): `y(t) = G₀(q) / (1 − q⁻¹) H[u(t)] + v(t)`
//! with `G₀` stable, one pole fixed at `z = 1`.
//!
//! The static-gain normalisation `G(1) = 1` of the method cannot be imposed on a plant whose
//! gain at `z = 1` is infinite. The route taken is exact: the output is differenced,
//! `Δy(t) = y(t) − y(t − 1) = G₀(q) H[u(t)] + (1 − q⁻¹) v(t)`, which is a Hammerstein system
//! with the stable part `G₀` and the same element, so the method identifies `G₀` (normalised
//! by `G₀(1) = 1`), μ0 and the borders on `(u, Δy)` unchanged. The output disturbance becomes
//! `(1 − q⁻¹) v`, coloured but still independent of the input, and PI-MOESP with past-input
//! instruments is consistent for any output disturbance independent of the input; the
//! differencing adds no parameter to estimate and the pole at `z = 1` is exact, not estimated.
//!
//! Gain convention: the normalisation moves to the plant without the integrator, `G₀(1) = 1`,
//! so the borders `P_a`, `P_d` (and μ0) are the output's rate of change in steady state (output
//! units per sample) for a constant input on that border. The gap between the borders, in
//! input units, is unaffected by the convention.

use crate::identify::{HostModel, IdentifyError, IdentifyOptions, identify};

/// The increments `Δy(t) = y(t) − y(t − 1)`, `t = 1 … n − 1` (one sample fewer than `y`).
pub fn difference(y: &[f64]) -> Vec<f64> {
    y.windows(2).map(|w| w[1] - w[0]).collect()
}

/// The samples of the stable part's record: the input from the second sample on (the first
/// has no increment) and the output's increments ([`difference`]).
pub fn increments(u: &[f64], y: &[f64]) -> (Vec<f64>, Vec<f64>) {
    (u.get(1..).unwrap_or_default().to_vec(), difference(y))
}

/// The running sum `y(t) = y₀ + Σ_{s ≤ t} Δy(s)` (the inverse of [`difference`] given the
/// sample before the first increment).
pub(crate) fn integrate(increments: &[f64], y0: f64) -> Vec<f64> {
    increments
        .iter()
        .scan(y0, |acc, d| {
            *acc += d;
            Some(*acc)
        })
        .collect()
}

/// The record `(u, y)` of an integrating plant as the record of its stable part: the first
/// sample is dropped (it has no increment), `y` is differenced, and a hold loses its first
/// sample (and so does its settling, which counts from the same start).
pub fn increments_record(
    u: &[f64],
    y: &[f64],
    opts: &IdentifyOptions,
) -> Result<(Vec<f64>, Vec<f64>, IdentifyOptions), IdentifyError> {
    if u.len() != y.len() {
        return Err(IdentifyError::LengthMismatch {
            u: u.len(),
            y: y.len(),
        });
    }
    let (u1, dy) = increments(u, y);
    Ok((u1, dy, increments_options(opts)))
}

/// The settings of a record for the record of its increments: the hold and the settling
/// lose their first sample (the increments start one sample later).
pub fn increments_options(opts: &IdentifyOptions) -> IdentifyOptions {
    let mut o = opts.clone();
    o.hold = o.hold.saturating_sub(1);
    o.settle = o.settle.saturating_sub(1).min(o.hold);
    o
}

/// Identifies an integrating plant: the stable part `G₀` (normalised by `G₀(1) = 1`), μ0 and
/// the borders from the differenced output (see the module's text). The returned model is
/// `G₀` with the element; simulate the plant with [`HostModel::simulate_integrating`].
pub fn identify_integrating(
    u: &[f64],
    y: &[f64],
    opts: &IdentifyOptions,
) -> Result<HostModel, IdentifyError> {
    let (u1, dy, o) = increments_record(u, y, opts)?;
    identify(&u1, &dy, &o)
}

impl HostModel {
    /// Simulates the integrating plant of the stable part `m`: the increments `m.simulate(u)`
    /// summed from `y_before`, the output of the sample before `u[0]`.
    pub fn simulate_integrating(&self, u: &[f64], y_before: f64) -> Vec<f64> {
        integrate(&self.simulate(u), y_before)
    }
    /// The poles of the integrating plant: those of `G₀`, then the fixed one at `z = 1`.
    pub fn integrating_poles(&self) -> Vec<(f64, f64)> {
        let mut p = self.poles();
        p.push((1.0, 0.0));
        p
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn integrate_inverts_difference() {
        let y = [0.5, 1.5, -2.0, 4.25, 4.0];
        let back = integrate(&difference(&y), y[0]);
        assert_eq!(back, y[1..].to_vec());
    }

    #[test]
    fn record_of_increments_drops_one_sample_and_one_hold_sample() {
        let opts = IdentifyOptions::uniform(-1.0, 1.0, 4, 10);
        let u = [-1.0, -1.0, 0.5, 1.0];
        let y = [0.0, 1.0, 3.0, 6.0];
        let r = increments_record(&u, &y, &opts);
        assert!(
            matches!(&r, Ok((u1, dy, o)) if *u1 == [-1.0, 0.5, 1.0] && *dy == [1.0, 2.0, 3.0] && o.hold == 9),
            "{r:?}"
        );
        assert!(matches!(
            increments_record(&u, &y[..3], &opts),
            Err(IdentifyError::LengthMismatch { u: 4, y: 3 })
        ));
    }
}
