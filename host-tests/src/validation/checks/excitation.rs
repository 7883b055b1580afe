//! Persistent excitation of order `(f + p)·m` of the regressor.

use super::setup::CheckSetup;
use super::warning::{Check, Warning, warn};
use crate::numerics::spectrum::spectrum;
use crate::validation::residual::regressor::{channel_count, samples};

/// Pivots of the Gram's Cholesky factorisation below this fraction of the largest do not count
/// to its numerical rank.
const RANK_TOL: f64 = 1e-9;

/// The Gram's condition above which the check warns: the data then determine some
/// directions a million times less well than others.
const MAX_CONDITION: f64 = 1e6;

/// The most rows of the Gram the check factorises (two `rows²` matrices of f64: 41 MB at 1,600
/// rows, 1.8 s with the factorisation).
pub const MAX_ROWS: usize = 1600;

/// The regressor's block Hankel Gram, checked for rank and condition. Above [`MAX_ROWS`] rows
/// (e.g. `f = p = 48` and 64 channels: 6,144) it is checked at the longest `f + p` within
/// them: that Gram is a principal submatrix of the whole one up to the window's edge, so a
/// deficiency found there is one at the horizons asked for (the converse is not assured, and
/// the finding says at which horizons it was checked).
pub(crate) fn persistent_excitation(ex: &[f64], s: &CheckSetup) -> Vec<Warning> {
    let mut out = Vec::new();
    let shared = s.shared();
    // Persistent excitation of order (f + p)·m of the regressor.
    let m = channel_count(s.knots_asc, s.knots_desc, shared);
    let asked = s.f + s.p;
    let k = asked.min((MAX_ROWS / m.max(1)).max(2));
    let dim = k * m;
    let at = match k < asked {
        true => format!(" (checked at f + p = {k} of the {asked} asked, {MAX_ROWS} rows at most)"),
        false => String::new(),
    };
    if dim > 0 && ex.len() > k + 10 {
        let g = hankel_gram(
            samples(ex, s.knots_asc, s.knots_desc, shared).map(|r| r.on),
            ex.len(),
            m,
            k,
        );
        let sp = spectrum(&g, dim, RANK_TOL);
        let condition = sp.condition();
        if condition > MAX_CONDITION {
            // Full numerical rank with a large condition: every direction is excited, some a
            // million times less than others; a rank below `dim`: some are not at all.
            let how = match (sp.rank < dim, condition.is_finite()) {
                (true, true) => format!(
                    "its Hankel Gram has numerical rank {} of {dim} (condition {condition:.1e}): \
                     some directions are not excited",
                    sp.rank
                ),
                (true, false) => format!(
                    "its Hankel Gram has numerical rank {} of {dim} (pivots below {RANK_TOL:.0e} \
                     of the largest): some directions are not excited",
                    sp.rank
                ),
                (false, _) => format!(
                    "its Hankel Gram has full numerical rank {dim} but condition \
                     {condition:.1e}: some directions are excited {:.0e} times less than others",
                    condition
                ),
            };
            out.push(warn(
                Check::PersistentExcitation,
                format!(
                    "the regressor is weakly exciting of order (f+p)·m = {dim}: {how}; the \
                     projection of eq. (11) is ill-conditioned and the model can be poor \
                     (shorter horizons or fewer knots help){at}"
                ),
            ));
        }
    }
    out
}

/// The channels on at a sample with their weights (a weight of 0 is off).
type On = [(usize, f64); 2];

/// Adds `sign · x yᵀ` of two samples' channels to the `m × m` sums `w`.
fn add(w: &mut [f64], m: usize, x: &On, y: &On, sign: f64) {
    for &(i, a) in x {
        for &(j, b) in y {
            w[i * m + j] += sign * a * b;
        }
    }
}

/// The exact Gram `Σ_t φ(t) φ(t)ᵀ / cols` of the stacked regressor `φ(t) = [z(t); …;
/// z(t + k − 1)]` (`z` with `m` channels, at most two on at a sample: `on`, `n` samples) over
/// the `cols = n − k + 1` columns of its block Hankel matrix. Block `(a, b)`, `b ≥ a`, is the
/// window sum `W_l(a) = Σ_{s=a}^{a+cols−1} z(s) z(s + l)ᵀ`, `l = b − a`: the lagged sum over
/// the whole record (one pass, `4·k` products a sample, the last `k` samples in a ring), less
/// the products past the first window, then moved one sample per block row (one product out,
/// one in) with the first and last `2k` samples kept. Memory `O(k·m)²`, none per sample.
/// Row major, `k·m` square. Exact, so positive semidefinite: its eigenvalues measure the excitation, not the edges of
/// a Toeplitz approximation (which can make it indefinite).
fn hankel_gram(on: impl Iterator<Item = On>, n: usize, m: usize, k: usize) -> Vec<f64> {
    let cols = n + 1 - k;
    let ends = 2 * k;
    let (mut head, mut tail) = (Vec::with_capacity(ends), Vec::with_capacity(ends));
    let tail_from = n.saturating_sub(ends);
    let mut ring: Vec<On> = vec![[(0, 0.0); 2]; k];
    // full[l]: Σ_{s=0}^{n−1−l} z(s) z(s + l)ᵀ.
    let mut full = vec![vec![0.0; m * m]; k];
    for (t, e) in on.enumerate().take(n) {
        ring[t % k] = e;
        for (l, w) in full.iter_mut().enumerate().take(t.min(k - 1) + 1) {
            add(w, m, &ring[(t - l) % k], &e, 1.0);
        }
        if t < ends {
            head.push(e);
        }
        if t >= tail_from {
            tail.push(e);
        }
    }
    let at_tail = |s: usize| &tail[s - tail_from];
    let d = k * m;
    let mut g = vec![0.0; d * d];
    for (l, mut w) in full.into_iter().enumerate() {
        // The first window ends at s = cols − 1.
        for s in cols..n - l {
            add(&mut w, m, at_tail(s), at_tail(s + l), -1.0);
        }
        for a in 0..k - l {
            if a > 0 {
                let (out, into) = (a - 1, a - 1 + cols);
                add(&mut w, m, &head[out], &head[out + l], -1.0);
                add(&mut w, m, at_tail(into), at_tail(into + l), 1.0);
            }
            for i in 0..m {
                for j in 0..m {
                    let v = w[i * m + j] / cols as f64;
                    let (r, c) = (a * m + i, (a + l) * m + j);
                    g[r * d + c] = v;
                    g[c * d + r] = v;
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
        // Channel i is on where (t + i) % 3 != 0: two of the three at every sample.
        let on = (0..n).map(|t| {
            let mut e = [(0, 0.0); 2];
            for (slot, i) in (0..m).filter(|i| z[*i][t] != 0.0).enumerate() {
                e[slot] = (i, z[i][t]);
            }
            e
        });
        let g = hankel_gram(on, n, m, k);
        let cols = n - k + 1;
        for r in 0..k * m {
            for c in 0..k * m {
                let (a, i, b, j) = (r / m, r % m, c / m, c % m);
                let direct: f64 =
                    (0..cols).map(|t| z[i][t + a] * z[j][t + b]).sum::<f64>() / cols as f64;
                assert!((g[r * k * m + c] - direct).abs() < 1e-12, "({r}, {c})");
            }
        }
    }
}
