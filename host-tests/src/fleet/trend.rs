//! A device's gap trend: the least-squares line through its weekly gaps, with the standard
//! error of its slope.

/// The line `gap ≈ intercept + slope · week`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Trend {
    /// Gap at week 0.
    pub intercept: f64,
    /// Growth per week.
    pub slope: f64,
    /// Standard error of the slope, `√(s² / Σ(w − w̄)²)` with `s²` the residual variance on
    /// `n − 2` degrees of freedom.
    pub slope_se: f64,
    /// Points fitted.
    pub points: usize,
}

impl Trend {
    /// The fitted gap at `week`.
    pub fn at(&self, week: f64) -> f64 {
        self.intercept + self.slope * week
    }
}

/// Fits the line through `(week, gap)` points; `None` with fewer than three points or fewer
/// than two distinct weeks (no standard error then).
pub fn fit(points: &[(f64, f64)]) -> Option<Trend> {
    let n = points.len();
    if n < 3 {
        return None;
    }
    let nf = n as f64;
    let wm = points.iter().map(|p| p.0).sum::<f64>() / nf;
    let gm = points.iter().map(|p| p.1).sum::<f64>() / nf;
    let sxx: f64 = points.iter().map(|p| (p.0 - wm).powi(2)).sum();
    if sxx <= 0.0 {
        return None;
    }
    let sxy: f64 = points.iter().map(|p| (p.0 - wm) * (p.1 - gm)).sum();
    let slope = sxy / sxx;
    let intercept = gm - slope * wm;
    let rss: f64 = points
        .iter()
        .map(|p| (p.1 - intercept - slope * p.0).powi(2))
        .sum();
    Some(Trend {
        intercept,
        slope,
        slope_se: (rss / (nf - 2.0) / sxx).sqrt(),
        points: n,
    })
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;

    #[test]
    fn an_exact_line_is_recovered_with_zero_error() {
        let pts: Vec<(f64, f64)> = (0..6).map(|w| (w as f64, 1.5 + 0.05 * w as f64)).collect();
        let t = fit(&pts).unwrap();
        assert!((t.slope - 0.05).abs() < 1e-14 && (t.intercept - 1.5).abs() < 1e-14);
        assert!(t.slope_se < 1e-12);
        assert!((t.at(10.0) - 2.0).abs() < 1e-13);
    }

    #[test]
    fn the_slope_error_matches_the_textbook_formula() {
        // Points (0,0) (1,1) (2,1) (3,3): Sxy = 4.5, Sxx = 5, slope 0.9, intercept -0.1,
        // residuals 0.1, 0.2, -0.7, 0.4, RSS = 0.70, s² = 0.35, se = √(0.35 / 5).
        let t = fit(&[(0.0, 0.0), (1.0, 1.0), (2.0, 1.0), (3.0, 3.0)]).unwrap();
        assert!((t.slope - 0.9).abs() < 1e-12 && (t.intercept + 0.1).abs() < 1e-12);
        assert!((t.slope_se - 0.07_f64.sqrt()).abs() < 1e-12);
    }

    #[test]
    fn too_few_points_or_one_week_give_no_trend() {
        assert_eq!(fit(&[(0.0, 1.0), (1.0, 2.0)]), None);
        assert_eq!(fit(&[(2.0, 1.0), (2.0, 2.0), (2.0, 3.0)]), None);
    }
}
