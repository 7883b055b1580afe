//! Spectral lines of the residual not shared with the input.

use super::result::{LEVEL, ResidualInput, Test, TestSet, result};
use crate::validation::stats::{periodogram, running_median};

/// The spectral line test on `inp`, into `set` with the periodogram curves.
pub(crate) fn spectral_line(inp: &ResidualInput, set: &mut TestSet) {
    let r = inp.residual;
    let n = r.len();
    // Spectral lines not shared with the input.
    let (omega, power) = periodogram(r);
    let (_, pu) = periodogram(inp.u);
    let mm = power.len();
    if mm > 20 {
        let low = 4.0 * 2.0 * std::f64::consts::PI / n as f64;
        let (_, _, med_u) = line_scan(&pu, &vec![false; mm]);
        let mut exclude: Vec<bool> = omega.iter().map(|&w| w < low).collect();
        let qu = -(1.0 - (1.0 - LEVEL).powf(1.0 / mm as f64)).ln();
        for i in 0..mm {
            if med_u[i] > 0.0 && pu[i] / (med_u[i] / std::f64::consts::LN_2) > qu {
                for e in exclude
                    .iter_mut()
                    .take((i + 6).min(mm))
                    .skip(i.saturating_sub(5))
                {
                    *e = true;
                }
            }
        }
        let (q, idx, med) = line_scan(&power, &exclude);
        // Every tested bin counts as one ordinate (conservative: neighbouring bins of the
        // zero-padded, Hann-windowed periodogram are correlated).
        let indep = exclude.iter().filter(|&&e| !e).count().max(1) as f64;
        let p = 1.0 - (1.0 - (-q).exp()).powf(indep);
        let thr = -(1.0 - (1.0 - LEVEL).powf(1.0 / indep)).ln();
        let total: f64 = power.iter().sum();
        let g = power.get(idx).copied().unwrap_or(0.0) / total.max(1e-300);
        set.line_frequency = omega.get(idx).copied().unwrap_or(0.0);
        set.tests.push(result(
            Test::SpectralLine,
            q,
            thr,
            p,
            format!(
                "largest line at ω = {:.4} rad/sample (period {:.1} samples), {q:.1} × the local median spectrum; Fisher's g = {g:.4}",
                set.line_frequency,
                2.0 * std::f64::consts::PI / set.line_frequency.max(1e-12)
            ),
        ));
        set.curves.power_threshold = med
            .iter()
            .map(|v| v / std::f64::consts::LN_2 * thr)
            .collect();
        set.curves.omega = omega;
        set.curves.power = power;
        set.curves.power_median = med;
    }
}

/// Local-median spectral line test on the periodogram: `(ratio, index, median curve)`.
pub(crate) fn line_scan(power: &[f64], exclude: &[bool]) -> (f64, usize, Vec<f64>) {
    let m = power.len();
    let w = (m / 20).clamp(16, 128);
    let med: Vec<f64> = running_median(power, 2 * w + 1);
    let mut best = (0.0, 0usize);
    for i in 0..m {
        if exclude[i] {
            continue;
        }
        let s = med[i] / std::f64::consts::LN_2;
        if s > 0.0 {
            let q = power[i] / s;
            if q > best.0 {
                best = (q, i);
            }
        }
    }
    (best.0, best.1, med)
}
