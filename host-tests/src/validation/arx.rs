//! The least-squares pieces the ARX tests share (the unit-root test [`unit_root`](super::unit_root)
//! and the diagnosis's dead-time test): lagged columns read in place, the residual sum of squares
//! of a regression over chosen rows, and the rows whose lags stay inside one piece of a
//! joined record.

use crate::numerics::lstsq::{normal_by_rows, solve_normal_min_norm};

/// A regression column, read where it is (no lagged copy of the signal is made).
#[derive(Clone, Copy, Debug)]
pub enum Column<'a> {
    /// A constant.
    Constant(f64),
    /// `x(t − lag)`, zero before the signal's start.
    Lagged(&'a [f64], usize),
}

impl Column<'_> {
    /// The column's value at sample `t`.
    pub fn at(&self, t: usize) -> f64 {
        match *self {
            Column::Constant(c) => c,
            Column::Lagged(x, lag) => t
                .checked_sub(lag)
                .and_then(|s| x.get(s))
                .copied()
                .unwrap_or(0.0),
        }
    }
}

/// Residual sum of squares of `y` on the columns `cols` over the rows `rows` (`None` with
/// fewer than ten rows beyond the columns, or when the solve fails).
pub(crate) fn rss(cols: &[Column], y: &[f64], rows: &[usize]) -> Option<f64> {
    fit(cols, y, rows).map(|(_, r)| r)
}

/// The least-squares coefficients of `y` on `cols` over `rows`, and the residual sum of
/// squares.
pub fn fit(cols: &[Column], y: &[f64], rows: &[usize]) -> Option<(Vec<f64>, f64)> {
    let n = rows.len();
    let k = cols.len();
    if n <= k + 10 {
        return None;
    }
    let row = |r: usize, x: &mut [f64]| {
        let t = rows[r];
        for (xc, c) in x.iter_mut().zip(cols) {
            *xc = c.at(t);
        }
        y[t]
    };
    let (g, b) = normal_by_rows(n, k, row);
    let beta = solve_normal_min_norm(&g, &b)?;
    let mut x = vec![0.0; k];
    let rss = (0..n)
        .map(|r| {
            let yt = row(r, &mut x);
            let fit: f64 = x.iter().zip(beta.iter()).map(|(a, b)| a * b).sum();
            (yt - fit).powi(2)
        })
        .sum();
    Some((beta.iter().copied().collect(), rss))
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
        let ones = Column::Constant(1.0);
        let rows: Vec<usize> = (0..40).collect();
        let (beta, r) = fit(&[ones, Column::Lagged(&t, 0)], &y, &rows).ok_or("line fit")?;
        assert!((beta[0] - 1.0).abs() < 1e-9 && (beta[1] - 2.0).abs() < 1e-9);
        assert!(r < 1e-12);
        // Around the mean 40 the squares sum to 4 · Σ (t − 19.5)² = 4 · 5330.
        let r = rss(&[ones], &y, &rows).ok_or("constant fit")?;
        // A lagged column is read in place: zero before the start.
        assert_eq!(Column::Lagged(&t, 2).at(1), 0.0);
        assert_eq!(Column::Lagged(&t, 2).at(5), 3.0);
        assert!((r - 4.0 * 5330.0).abs() < 1e-6, "{r}");
        let time = [0.0, 1.0, 2.0, 10.0, 11.0, 12.0];
        assert_eq!(continuous_rows(&time, 2), [2, 5]);
        Ok(())
    }
}
