//! Structure: binned means of the residual per path and knot segment, and in deciles of the
//! simulated output.

use super::result::{LEVEL, ResidualInput, Test, TestSet, result};
use crate::validation::stats::{chi2_quantile, chi2_sf, mean};

/// The structure tests against the input per path and against the simulated output, into
/// `set` (autocorrelation `rho` of the residual).
pub fn structure(inp: &ResidualInput, rho: &[f64], set: &mut TestSet) {
    let r = inp.residual;
    let n = r.len();
    // Structure against the input per path, and against the simulated output.
    match binned_test(r, inp.bins, inp.bin_count, rho) {
        Some((c, df)) => set.tests.push(result(
            Test::StructureInput,
            c,
            chi2_quantile(1.0 - LEVEL, df as f64),
            chi2_sf(c, df as f64),
            format!(
                "mean residual in {} (path, knot segment) bins, autocorrelation-corrected",
                df + 1
            ),
        )),
        None => set.tests.push(result(
            Test::StructureInput,
            0.0,
            f64::NAN,
            1.0,
            "fewer than two bins with 10 samples".into(),
        )),
    }
    let mut sorted = inp.simulated.to_vec();
    sorted.sort_by(f64::total_cmp);
    let edges: Vec<f64> = (1..10).map(|i| sorted[(n - 1) * i / 10]).collect();
    let out_bins: Vec<usize> = inp
        .simulated
        .iter()
        .map(|&v| edges.iter().filter(|&&e| v > e).count())
        .collect();
    match binned_test(r, &out_bins, 10, rho) {
        Some((c, df)) => set.tests.push(result(
            Test::StructureOutput,
            c,
            chi2_quantile(1.0 - LEVEL, df as f64),
            chi2_sf(c, df as f64),
            "mean residual in deciles of the simulated output, autocorrelation-corrected".into(),
        )),
        None => set.tests.push(result(
            Test::StructureOutput,
            0.0,
            f64::NAN,
            1.0,
            "simulated output is constant".into(),
        )),
    }
}

/// Variance-corrected binned means test: `(chi2, df)` or `None` with fewer than two bins.
pub(crate) fn binned_test(
    r: &[f64],
    bins: &[usize],
    count: usize,
    rho: &[f64],
) -> Option<(f64, usize)> {
    let n = r.len();
    let var = crate::validation::stats::variance(r);
    let m = mean(r);
    let mut chi2 = 0.0;
    let mut used = 0;
    for b in 0..count {
        let idx: Vec<usize> = (0..n).filter(|&t| bins[t] == b).collect();
        let nb = idx.len();
        if nb < 10 {
            continue;
        }
        let mb = idx.iter().map(|&t| r[t]).sum::<f64>() / nb as f64;
        // Σ_{s,t ∈ b} ρ(s − t) = n_b + 2 Σ_k ρ(k) #{t ∈ b : t + k ∈ b}.
        let mut pairs = nb as f64;
        for (k, rk) in rho.iter().enumerate().skip(1) {
            let c = idx
                .iter()
                .filter(|&&t| t + k < n && bins[t + k] == b)
                .count();
            pairs += 2.0 * rk * c as f64;
        }
        let vb = var * pairs.max(0.2 * nb as f64) / (nb as f64 * nb as f64);
        if vb > 0.0 {
            chi2 += (mb - m) * (mb - m) / vb;
            used += 1;
        }
    }
    (used >= 2).then_some((chi2, used - 1))
}
