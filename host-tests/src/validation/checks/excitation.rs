//! Persistent excitation of order `(f + p)·m` of the regressor.

use nalgebra::DMatrix;

use super::setup::CheckSetup;
use super::warning::{Check, Warning, warn};
use crate::validation::residual::regressor;

/// The regressor's block-Toeplitz Gram, checked for rank and condition.
pub(crate) fn persistent_excitation(ex: &[f64], s: &CheckSetup) -> Vec<Warning> {
    let mut out = Vec::new();
    let shared = s.shared();
    // Persistent excitation of order (f + p)·m of the regressor.
    let (_, z, _, _) = regressor(ex, s.knots_asc, s.knots_desc, shared);
    let m = z.len();
    let k = s.f + s.p;
    let dim = k * m;
    if dim > 0 && ex.len() > k + 10 {
        let cols = ex.len() - k + 1;
        // Block-Toeplitz Gram from lagged products R_ij(l) = Σ_t z_i(t) z_j(t + l).
        let mut r = vec![vec![vec![0.0; m]; m]; k];
        for (l, rl) in r.iter_mut().enumerate() {
            for (i, row) in rl.iter_mut().enumerate() {
                for (j, v) in row.iter_mut().enumerate() {
                    *v = (0..cols).map(|t| z[i][t] * z[j][t + l]).sum::<f64>() / cols as f64;
                }
            }
        }
        let g = DMatrix::from_fn(dim, dim, |a, b| {
            let (ba, ia) = (a / m, a % m);
            let (bb, ib) = (b / m, b % m);
            if bb >= ba {
                r[bb - ba][ia][ib]
            } else {
                r[ba - bb][ib][ia]
            }
        });
        let ev = g.symmetric_eigenvalues();
        let max = ev.max();
        let min = ev.min();
        let rank = ev.iter().filter(|&&v| v > 1e-9 * max).count();
        let well_conditioned = min > 1e-6 * max;
        if !well_conditioned {
            out.push(warn(
                Check::PersistentExcitation,
                format!(
                    "the regressor is not persistently exciting of order (f+p)·m = {dim}: its Hankel Gram has numerical rank {rank} of {dim} ({}); the projection of eq. (11) is ill-conditioned and the model can be poor (shorter horizons or fewer knots help)",
                    if min > 1e-15 * max {
                        format!("condition {:.1e}", max / min)
                    } else {
                        "singular".to_string()
                    }
                ),
            ));
        }
    }
    out
}
