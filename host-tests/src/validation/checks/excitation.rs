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
        let g = hankel_gram(&z, k);
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

/// The exact Gram `Σ_t φ(t) φ(t)ᵀ / cols` of the stacked regressor `φ(t) = [z(t); …;
/// z(t + k − 1)]` over the `cols = n − k + 1` columns of its block Hankel matrix. Block
/// `(a, b)`, `b ≥ a`, is the window sum `W_l(a) = Σ_{s=a}^{a+cols−1} z(s) z(s + l)ᵀ`,
/// `l = b − a`: the lagged sum over the whole record (a hat basis has at most two channels
/// on at a sample, so it costs `4·k` products per sample), less the `k − 1 − l` products past
/// the first window, and then moved one sample per block row (one product out, one in).
/// Exact, so positive semidefinite: its eigenvalues measure the excitation, not the edges of
/// a Toeplitz approximation (which can make it indefinite).
fn hankel_gram(z: &[Vec<f64>], k: usize) -> DMatrix<f64> {
    let m = z.len();
    let n = z.first().map_or(0, Vec::len);
    let cols = n + 1 - k;
    // The channels on at each sample.
    let on: Vec<Vec<(usize, f64)>> = (0..n)
        .map(|t| {
            (0..m)
                .filter(|&i| z[i][t] != 0.0)
                .map(|i| (i, z[i][t]))
                .collect()
        })
        .collect();
    let mut g = DMatrix::zeros(k * m, k * m);
    let mut w = vec![0.0; m * m];
    for l in 0..k {
        w.iter_mut().for_each(|v| *v = 0.0);
        for s in 0..n - l {
            for &(i, zi) in &on[s] {
                for &(j, zj) in &on[s + l] {
                    w[i * m + j] += zi * zj;
                }
            }
        }
        // The first window ends at s = cols − 1.
        for s in cols..n - l {
            for &(i, zi) in &on[s] {
                for &(j, zj) in &on[s + l] {
                    w[i * m + j] -= zi * zj;
                }
            }
        }
        for a in 0..k - l {
            if a > 0 {
                let (out, into) = (a - 1, a - 1 + cols);
                for &(i, zi) in &on[out] {
                    for &(j, zj) in &on[out + l] {
                        w[i * m + j] -= zi * zj;
                    }
                }
                for &(i, zi) in &on[into] {
                    for &(j, zj) in &on[into + l] {
                        w[i * m + j] += zi * zj;
                    }
                }
            }
            for i in 0..m {
                for j in 0..m {
                    let v = w[i * m + j] / cols as f64;
                    let (r, c) = (a * m + i, (a + l) * m + j);
                    g[(r, c)] = v;
                    g[(c, r)] = v;
                }
            }
        }
    }
    g
}

#[cfg(test)]
mod tests {
    use super::hankel_gram;

    /// The Gram from the window sums equals `Φ Φᵀ / cols` of the block Hankel matrix built
    /// column by column.
    #[test]
    fn window_sums_give_the_exact_hankel_gram() {
        let (n, m, k) = (40, 3, 4);
        // Two channels on at a time, as a hat basis, with other values.
        let z: Vec<Vec<f64>> = (0..m)
            .map(|i| {
                (0..n)
                    .map(|t| match (t + i) % 3 {
                        0 => 0.0,
                        r => ((t * 7 + i * 3) % 11) as f64 / 10.0 + r as f64,
                    })
                    .collect()
            })
            .collect();
        let g = hankel_gram(&z, k);
        let cols = n - k + 1;
        for r in 0..k * m {
            for c in 0..k * m {
                let (a, i, b, j) = (r / m, r % m, c / m, c % m);
                let direct: f64 =
                    (0..cols).map(|t| z[i][t + a] * z[j][t + b]).sum::<f64>() / cols as f64;
                assert!((g[(r, c)] - direct).abs() < 1e-12, "({r}, {c})");
            }
        }
    }
}
