//! The least-squares pieces the ARX tests share (the unit-root test [`unit_root`](super::unit_root)
//! and the diagnosis's dead-time test): a lagged copy of a signal, the residual sum of squares
//! of a regression over chosen rows, and the rows whose lags stay inside one piece of a
//! joined record.

use nalgebra::{DMatrix, DVector};

use crate::numerics::lstsq::lstsq_min_norm;

/// Residual sum of squares of `y` on the columns `cols` over the rows `rows` (`None` with
/// fewer than ten rows beyond the columns, or when the solve fails).
pub(crate) fn rss(cols: &[&[f64]], y: &[f64], rows: &[usize]) -> Option<f64> {
    fit(cols, y, rows).map(|(_, r)| r)
}

/// The least-squares coefficients of `y` on `cols` over `rows`, and the residual sum of
/// squares.
pub fn fit(cols: &[&[f64]], y: &[f64], rows: &[usize]) -> Option<(Vec<f64>, f64)> {
    let n = rows.len();
    let k = cols.len();
    if n <= k + 10 {
        return None;
    }
    let x = DMatrix::from_fn(n, k, |r, c| cols[c][rows[r]]);
    let yy = DVector::from_iterator(n, rows.iter().map(|&t| y[t]));
    let beta = lstsq_min_norm(&x, &yy)?;
    let e = &yy - &x * &beta;
    Some((beta.iter().copied().collect(), e.norm_squared()))
}

/// `x` delayed by `lag` samples, zeros before its start.
pub fn lagged(x: &[f64], lag: usize) -> Vec<f64> {
    (0..x.len())
        .map(|t| if t >= lag { x[t - lag] } else { 0.0 })
        .collect()
}

/// The samples `t ≥ span` whose previous `span` samples are consecutive in `time` (rows of a
/// joined record whose lags would reach across a gap are left out).
pub(crate) fn continuous_rows(time: &[f64], span: usize) -> Vec<usize> {
    (span..time.len())
        .filter(|&t| (time[t] - time[t - span] - span as f64).abs() < 0.5)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rss_of_an_exact_line_is_zero_and_of_a_constant_fit_the_variance() -> Result<(), String> {
        let t: Vec<f64> = (0..40).map(f64::from).collect();
        let y: Vec<f64> = t.iter().map(|v| 2.0 * v + 1.0).collect();
        let ones = vec![1.0; 40];
        let rows: Vec<usize> = (0..40).collect();
        let (beta, r) = fit(&[&ones, &t], &y, &rows).ok_or("line fit")?;
        assert!((beta[0] - 1.0).abs() < 1e-9 && (beta[1] - 2.0).abs() < 1e-9);
        assert!(r < 1e-12);
        // Around the mean 40 the squares sum to 4 · Σ (t − 19.5)² = 4 · 5330.
        let r = rss(&[&ones], &y, &rows).ok_or("constant fit")?;
        assert!((r - 4.0 * 5330.0).abs() < 1e-6, "{r}");
        assert_eq!(lagged(&[1.0, 2.0, 3.0], 1), [0.0, 1.0, 2.0]);
        let time = [0.0, 1.0, 2.0, 10.0, 11.0, 12.0];
        assert_eq!(continuous_rows(&time, 2), [2, 5]);
        Ok(())
    }
}
