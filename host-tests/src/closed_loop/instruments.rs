//! Instruments from a logged reference: the input predicted from the reference alone, and the
//! block Hankel matrix of its regressors.
//!
//! In closed loop the input `u(t)` depends on the noise of earlier samples (through the
//! controller), so its regressors `z(u)` are correlated with the noise. The reference `r(t)` is
//! chosen by the experimenter, independent of the noise; any function of `r` is an instrument.
//! The instruments here are the regressors `z(ũ)` of an input `ũ` predicted from the reference
//! alone: a least-squares FIR predictor `û(t) = c + Σ_{l=0..L} a_l r(t − l)` fitted on the
//! command samples (those strictly inside `]u_min, u_max[`), then mapped onto the commands'
//! distribution by rank (the `k`-th smallest prediction becomes the `k`-th smallest command: a
//! monotone map, so `ũ` is still a function of `r`). A regression's prediction is narrower
//! than what it predicts, and the outer segments' ramps would hardly move without the map:
//! their instruments would be weak. The samples at `u_min` or `u_max` (the Table I
//! excursions, which the schedule fixes, not the controller) are kept as they are. `z(ũ)` is nonlinear in `r` like `z(u)` is in `u`,
//! so its channels stay separate; a linear function of `r` would make the ramps of one lag
//! nearly collinear (Bussgang: every static function of a Gaussian signal correlates with
//! the past of `r` in the same proportions).

use nalgebra::{DMatrix, DVector};

use crate::closed_loop::error::ReferenceError;
use crate::closed_loop::linalg::spd_factor;
use crate::reference::{RefConfig, block_hankel, regressors};

/// Lags `L` of the reference in the input's predictor (`L + 1` coefficients and a constant).
pub(crate) const PREDICTOR_LAGS: usize = 20;

/// Whether `u` sits at an end of `[u_min, u_max]` (within `1e-12` of the interval's width).
fn at_end(u: f64, cfg: &RefConfig) -> bool {
    let tol = 1e-12 * (cfg.u_max - cfg.u_min);
    (u - cfg.u_min).abs() <= tol || (u - cfg.u_max).abs() <= tol
}

/// The predictor's regressor row at `t`: `1, r(t), r(t − 1), …, r(t − lags)`; before the
/// record's start, `r(0)` (the reference at rest).
fn row(r: &[f64], t: usize, lags: usize) -> DVector<f64> {
    DVector::from_fn(lags + 2, |i, _| match i {
        0 => 1.0,
        _ => r[t.saturating_sub(i - 1)],
    })
}

/// The input predicted from the reference (see the module's documentation): `u` at the ends
/// of the interval, the FIR prediction mapped onto the commands' distribution elsewhere.
pub(crate) fn predicted_input(
    u: &[f64],
    r: &[f64],
    cfg: &RefConfig,
    lags: usize,
) -> Result<Vec<f64>, ReferenceError> {
    let commands: Vec<usize> = (0..u.len()).filter(|&t| !at_end(u[t], cfg)).collect();
    let needed = 10 * (lags + 2);
    if commands.len() < needed {
        return Err(ReferenceError::FewCommands {
            needed,
            got: commands.len(),
        });
    }
    let mut gram = DMatrix::zeros(lags + 2, lags + 2);
    let mut rhs = DVector::zeros(lags + 2);
    for &t in &commands {
        let x = row(r, t, lags);
        gram += &x * x.transpose();
        rhs += &x * u[t];
    }
    let coef = spd_factor(gram, "the reference's lags")?.solve(&rhs);
    let fir: Vec<f64> = commands
        .iter()
        .map(|&t| row(r, t, lags).dot(&coef))
        .collect();
    let mut out = u.to_vec();
    for (t, v) in commands.iter().zip(matched(&fir, &commands, u)) {
        out[*t] = v;
    }
    Ok(out)
}

/// The FIR predictions `fir` of the command samples `commands` mapped onto the commands'
/// distribution: the `k`-th smallest prediction becomes the `k`-th smallest command.
fn matched(fir: &[f64], commands: &[usize], u: &[f64]) -> Vec<f64> {
    let mut sorted_u: Vec<f64> = commands.iter().map(|&t| u[t]).collect();
    sorted_u.sort_by(f64::total_cmp);
    let mut order: Vec<usize> = (0..fir.len()).collect();
    order.sort_by(|&a, &b| fir[a].total_cmp(&fir[b]));
    let mut out = vec![0.0; fir.len()];
    for (rank, &i) in order.iter().enumerate() {
        out[i] = sorted_u[rank];
    }
    out
}

/// The instruments `W`: the block Hankel matrix of `z(ũ)` with the `f + p` block rows and `j`
/// columns of the data's `[Z_p; Z_f]`.
pub fn instruments(predicted: &[f64], cfg: &RefConfig, j: usize) -> DMatrix<f64> {
    block_hankel(&regressors(predicted, cfg), 0, cfg.f + cfg.p, j)
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    #[test]
    fn a_reference_driven_input_is_predicted_exactly() {
        // u(t) = 0.5 + 0.8 r(t) − 0.3 r(t − 2) inside ]−3, 3[, with excursions to the ends.
        let cfg = RefConfig::uniform(-3.0, 3.0, 6, 6, 10, 10, 2);
        let r: Vec<f64> = (0..600)
            .map(|t| ((t * 7919) % 101) as f64 / 50.0 - 1.0)
            .collect();
        let u: Vec<f64> = (0..600)
            .map(|t| match t % 4 {
                1 => 3.0,
                3 => -3.0,
                _ => 0.5 + 0.8 * r[t] - 0.3 * r[t.saturating_sub(2)],
            })
            .collect();
        let p = predicted_input(&u, &r, &cfg, 5).unwrap();
        let worst = u
            .iter()
            .zip(&p)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        assert!(worst < 1e-9, "worst {worst}");
    }

    #[test]
    fn a_constant_reference_is_refused() {
        let cfg = RefConfig::uniform(-3.0, 3.0, 6, 6, 10, 10, 2);
        let u: Vec<f64> = (0..600).map(|t| (t % 5) as f64 * 0.5 - 1.0).collect();
        let r = vec![0.7; 600];
        assert_eq!(
            predicted_input(&u, &r, &cfg, 5),
            Err(ReferenceError::RankDeficient("the reference's lags"))
        );
    }
}
