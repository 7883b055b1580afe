//! Small statistics kit of the diagnosis: moments, correlations, the tails and quantiles of
//! the normal, chi-square and Poisson distributions (thin wrappers over the `statrs` crate that
//! answer out-of-range arguments with 0, 1, ±∞ or NaN instead of a panic), the FFT and
//! periodogram, robust scale, heteroscedasticity-and-autocorrelation-consistent variances and
//! small least squares problems.

use nalgebra::{DMatrix, DVector};
use statrs::distribution::{ChiSquared, ContinuousCDF};
use statrs::function::{erf, gamma};

/// Mean (0 for an empty slice).
pub fn mean(x: &[f64]) -> f64 {
    if x.is_empty() {
        return 0.0;
    }
    x.iter().sum::<f64>() / x.len() as f64
}

/// Population variance (0 for an empty slice).
pub fn variance(x: &[f64]) -> f64 {
    if x.is_empty() {
        return 0.0;
    }
    let m = mean(x);
    x.iter().map(|v| (v - m) * (v - m)).sum::<f64>() / x.len() as f64
}

/// Median (NaN for an empty slice).
pub fn median(x: &[f64]) -> f64 {
    if x.is_empty() {
        return f64::NAN;
    }
    let mut v = x.to_vec();
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

/// Robust standard deviation `1.4826 · median(|x − median(x)|)` (the MAD rule's scale).
pub(crate) fn mad_sigma(x: &[f64]) -> f64 {
    let m = median(x);
    let dev: Vec<f64> = x.iter().map(|v| (v - m).abs()).collect();
    1.4826 * median(&dev)
}

/// Running median with an odd window `w` (shrunk at the ends).
pub(crate) fn running_median(x: &[f64], w: usize) -> Vec<f64> {
    let h = w / 2;
    let n = x.len();
    (0..n)
        .map(|i| {
            let lo = i.saturating_sub(h);
            let hi = (i + h + 1).min(n);
            median(&x[lo..hi])
        })
        .collect()
}

/// Sample autocorrelation `ρ(k)`, `k = 0 … max_lag` (biased estimator, `ρ(0) = 1`).
pub fn acf(x: &[f64], max_lag: usize) -> Vec<f64> {
    let n = x.len();
    let m = mean(x);
    let c0: f64 = x.iter().map(|v| (v - m) * (v - m)).sum();
    (0..=max_lag)
        .map(|k| {
            if c0 <= 0.0 || k >= n {
                return if k == 0 { 1.0 } else { 0.0 };
            }
            let ck: f64 = (0..n - k).map(|t| (x[t] - m) * (x[t + k] - m)).sum();
            ck / c0
        })
        .collect()
}

/// Sample cross-correlation `r_xy(k) = Σ_t x̃(t) ỹ(t + k) / (N σ_x σ_y)` for
/// `k = −max_lag … max_lag` (index `k + max_lag`). Positive `k`: `y` follows `x` by `k`
/// samples (for `x` an input and `y` a residual, an effect of the input `k` samples later).
pub(crate) fn ccf(x: &[f64], y: &[f64], max_lag: usize) -> Vec<f64> {
    let n = x.len().min(y.len());
    let (mx, my) = (mean(&x[..n]), mean(&y[..n]));
    let sx: f64 = x[..n].iter().map(|v| (v - mx) * (v - mx)).sum::<f64>();
    let sy: f64 = y[..n].iter().map(|v| (v - my) * (v - my)).sum::<f64>();
    let den = (sx * sy).sqrt();
    let k = max_lag as isize;
    (-k..=k)
        .map(|lag| {
            if den <= 0.0 {
                return 0.0;
            }
            let mut s = 0.0;
            for t in 0..n as isize {
                let u = t + lag;
                if u >= 0 && u < n as isize {
                    s += (x[t as usize] - mx) * (y[u as usize] - my);
                }
            }
            s / den
        })
        .collect()
}

/// Standard deviation of a sample cross-correlation between two independent series with
/// autocorrelations `ra`, `rb` (Bartlett): `√((1 + 2 Σ_k ρ_a(k) ρ_b(k)) / N)`.
pub(crate) fn ccf_sigma(ra: &[f64], rb: &[f64], n: usize) -> f64 {
    let s: f64 = ra.iter().zip(rb).skip(1).map(|(a, b)| a * b).sum();
    ((1.0 + 2.0 * s).max(0.2) / n.max(1) as f64).sqrt()
}

/// Upper tail `P(Z > x)` of the standard normal.
pub fn normal_sf(x: f64) -> f64 {
    0.5 * erf::erfc(x / std::f64::consts::SQRT_2)
}

/// Quantile of the standard normal: `−∞` for `p ≤ 0`, `+∞` for `p ≥ 1`, NaN for NaN.
pub fn normal_quantile(p: f64) -> f64 {
    if p.is_nan() {
        return f64::NAN;
    }
    if p <= 0.0 {
        return f64::NEG_INFINITY;
    }
    if p >= 1.0 {
        return f64::INFINITY;
    }
    -std::f64::consts::SQRT_2 * erf::erfc_inv(2.0 * p)
}

/// Upper tail `P(χ²_k > x)`: 1 for `x ≤ 0`, NaN for an invalid `k` or a NaN argument.
pub fn chi2_sf(x: f64, k: f64) -> f64 {
    if x.is_nan() {
        return f64::NAN;
    }
    if x <= 0.0 {
        return 1.0;
    }
    if x == f64::INFINITY {
        return 0.0;
    }
    gamma::checked_gamma_ur(0.5 * k, 0.5 * x).unwrap_or(f64::NAN)
}

/// Quantile of the chi-square distribution with `k` degrees of freedom (NaN for `p` outside
/// `[0, 1]` or an invalid `k`).
pub fn chi2_quantile(p: f64, k: f64) -> f64 {
    match ChiSquared::new(k) {
        Ok(d) if (0.0..=1.0).contains(&p) => d.inverse_cdf(p),
        _ => f64::NAN,
    }
}

/// Upper tail `P(X ≥ k)` of a Poisson count with mean `lambda` (the binomial count of rare
/// events): the regularised lower incomplete gamma `P(k, λ)`; 1 for `k = 0` or `λ = ∞`, 0 for
/// `λ = 0`, NaN for a negative or NaN `lambda`.
pub fn poisson_sf(k: usize, lambda: f64) -> f64 {
    if k == 0 || lambda == f64::INFINITY {
        return 1.0;
    }
    if lambda == 0.0 {
        return 0.0;
    }
    gamma::checked_gamma_lr(k as f64, lambda).unwrap_or(f64::NAN)
}

/// Long-run variance of the mean of `x` (Newey–West, Bartlett weights up to `lags`):
/// `Var(x̄) ≈ (γ0 + 2 Σ_k (1 − k/(L+1)) γ_k) / N`.
pub(crate) fn newey_west_var_of_mean(x: &[f64], lags: usize) -> f64 {
    let n = x.len();
    if n == 0 {
        return f64::NAN;
    }
    let m = mean(x);
    let gamma = |k: usize| -> f64 {
        (0..n.saturating_sub(k))
            .map(|t| (x[t] - m) * (x[t + k] - m))
            .sum::<f64>()
            / n as f64
    };
    let mut s = gamma(0);
    for k in 1..=lags.min(n.saturating_sub(1)) {
        s += 2.0 * (1.0 - k as f64 / (lags as f64 + 1.0)) * gamma(k);
    }
    s.max(gamma(0) * 1e-3) / n as f64
}

/// Non-negative least squares `min ‖X β − y‖, β_i ≥ 0 for i ≥ free` (the first `free`
/// coefficients are unconstrained): Lawson–Hanson active set on the normal equations.
pub(crate) fn nnls(x: &DMatrix<f64>, y: &DVector<f64>, free: usize) -> Option<DVector<f64>> {
    if x.nrows() != y.len() || x.iter().chain(y.iter()).any(|v| !v.is_finite()) {
        return None;
    }
    nnls_gram(&x.tr_mul(x), &x.tr_mul(y), free)
}

/// [`nnls`] from the Gram matrix `XᵀX` and `Xᵀy`.
pub(crate) fn nnls_gram(g: &DMatrix<f64>, b: &DVector<f64>, free: usize) -> Option<DVector<f64>> {
    let p = g.ncols();
    let mut passive = vec![false; p];
    for v in passive.iter_mut().take(free) {
        *v = true;
    }
    let solve_passive = |passive: &[bool]| -> Option<DVector<f64>> {
        let idx: Vec<usize> = (0..p).filter(|&i| passive[i]).collect();
        let mut beta = DVector::zeros(p);
        if idx.is_empty() {
            return Some(beta);
        }
        let k = idx.len();
        let gs = DMatrix::from_fn(k, k, |r, c| g[(idx[r], idx[c])]);
        let bs = DVector::from_fn(k, |r, _| b[idx[r]]);
        let sol = crate::numerics::lstsq::solve_min_norm(gs, &bs)?;
        for (r, &i) in idx.iter().enumerate() {
            beta[i] = sol[r];
        }
        Some(beta)
    };
    let mut beta = solve_passive(&passive)?;
    for _ in 0..(3 * p + 10) {
        let w = b - g * &beta;
        let cand = (free..p)
            .filter(|&i| !passive[i])
            .max_by(|&a, &c| w[a].total_cmp(&w[c]));
        let Some(j) = cand else { break };
        if w[j] <= 1e-12 * w.amax().max(1e-300) {
            break;
        }
        passive[j] = true;
        loop {
            let z = solve_passive(&passive)?;
            let bad: Vec<usize> = (free..p).filter(|&i| passive[i] && z[i] <= 0.0).collect();
            if bad.is_empty() {
                beta = z;
                break;
            }
            let mut alpha = 1.0f64;
            for &i in &bad {
                let d = beta[i] - z[i];
                if d > 0.0 {
                    alpha = alpha.min(beta[i] / d);
                }
            }
            beta = &beta + (&z - &beta) * alpha;
            for i in free..p {
                if passive[i] && beta[i] <= 1e-14 {
                    passive[i] = false;
                    beta[i] = 0.0;
                }
            }
        }
    }
    Some(beta)
}

/// In-place radix-2 FFT of `(re, im)` pairs; the length must be a power of two.
pub(crate) fn fft(data: &mut [(f64, f64)]) {
    let n = data.len();
    if n < 2 || !n.is_power_of_two() {
        return;
    }
    let mut j = 0;
    for i in 1..n {
        let mut bit = n >> 1;
        while j & bit != 0 {
            j ^= bit;
            bit >>= 1;
        }
        j |= bit;
        if i < j {
            data.swap(i, j);
        }
    }
    let mut len = 2;
    while len <= n {
        let ang = -2.0 * std::f64::consts::PI / len as f64;
        for start in (0..n).step_by(len) {
            for k in 0..len / 2 {
                let (s, c) = (ang * k as f64).sin_cos();
                let (ar, ai) = data[start + k];
                let (br, bi) = data[start + k + len / 2];
                let (tr, ti) = (br * c - bi * s, br * s + bi * c);
                data[start + k] = (ar + tr, ai + ti);
                data[start + k + len / 2] = (ar - tr, ai - ti);
            }
        }
        len <<= 1;
    }
}

/// Hann-windowed periodogram of `x` (mean removed), zero-padded to a power of two at least
/// twice the length: `(ω, I(ω))` for `0 < ω < π` in radians per sample. The window's power is
/// normalised so that white noise of variance σ² has `E I(ω) = σ²`.
pub(crate) fn periodogram(x: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let n = x.len();
    if n < 4 {
        return (Vec::new(), Vec::new());
    }
    let m = mean(x);
    let nfft = (2 * n).next_power_of_two();
    let w: Vec<f64> = (0..n)
        .map(|t| 0.5 - 0.5 * (2.0 * std::f64::consts::PI * t as f64 / (n - 1) as f64).cos())
        .collect();
    let wpow: f64 = w.iter().map(|v| v * v).sum();
    let mut data = vec![(0.0, 0.0); nfft];
    for t in 0..n {
        data[t] = ((x[t] - m) * w[t], 0.0);
    }
    fft(&mut data);
    let mut omega = Vec::with_capacity(nfft / 2);
    let mut power = Vec::with_capacity(nfft / 2);
    for (k, &(re, im)) in data.iter().enumerate().take(nfft / 2).skip(1) {
        omega.push(2.0 * std::f64::consts::PI * k as f64 / nfft as f64);
        power.push((re * re + im * im) / wpow);
    }
    (omega, power)
}

/// Excess kurtosis `m4 / m2² − 3`.
pub(crate) fn excess_kurtosis(x: &[f64]) -> f64 {
    let m = mean(x);
    let m2 = x.iter().map(|v| (v - m).powi(2)).sum::<f64>() / x.len().max(1) as f64;
    let m4 = x.iter().map(|v| (v - m).powi(4)).sum::<f64>() / x.len().max(1) as f64;
    if m2 <= 0.0 {
        return 0.0;
    }
    m4 / (m2 * m2) - 3.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantiles_match_tables() {
        assert!((normal_quantile(0.995) - 2.575_829).abs() < 1e-5);
        assert!((normal_quantile(0.01) + 2.326_348).abs() < 1e-5);
        assert!((chi2_quantile(0.99, 1.0) - 6.634_897).abs() < 1e-4);
        assert!((chi2_quantile(0.99, 20.0) - 37.566_23).abs() < 1e-3);
        assert!((chi2_quantile(0.95, 3.0) - 7.814_728).abs() < 1e-4);
        assert!((chi2_sf(37.566_23, 20.0) - 0.01).abs() < 1e-6);
        assert!((normal_sf(1.959_964) - 0.025).abs() < 1e-7);
    }

    #[test]
    fn nnls_keeps_signs() {
        let x = DMatrix::from_row_slice(4, 2, &[1.0, 0.0, 1.0, 1.0, 1.0, 2.0, 1.0, 3.0]);
        let y = DVector::from_vec(vec![3.0, 2.0, 1.0, 0.0]);
        let b = nnls(&x, &y, 1).unwrap_or_else(|| DVector::zeros(2));
        assert!(b[1].abs() < 1e-12, "{b}");
        assert!((b[0] - 1.5).abs() < 1e-12, "{b}");
    }

    #[test]
    fn fft_of_a_tone() {
        let n = 64;
        let mut d: Vec<(f64, f64)> = (0..n)
            .map(|t| {
                (
                    (2.0 * std::f64::consts::PI * 5.0 * t as f64 / n as f64).cos(),
                    0.0,
                )
            })
            .collect();
        fft(&mut d);
        assert!((d[5].0 - 32.0).abs() < 1e-9);
        assert!(d[6].0.abs() < 1e-9);
    }
}
