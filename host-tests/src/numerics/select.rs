//! Model selection by an information criterion: `N ln(σ̂²) + penalty(d)` over candidates, the
//! first smallest score wins.

/// The penalty of the information criterion.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Criterion {
    /// Bayesian (Schwarz): `N ln σ̂² + d ln N`. Consistent.
    Bic,
    /// Akaike: `N ln σ̂² + 2d`.
    Aic,
}

impl Criterion {
    /// Upper-case name (`BIC`, `AIC`).
    pub fn name(self) -> &'static str {
        match self {
            Criterion::Bic => "BIC",
            Criterion::Aic => "AIC",
        }
    }

    /// `N ln(max(mse, f64::MIN_POSITIVE)) + penalty` for `samples` residuals of mean square
    /// `mse` and `parameters` estimated parameters.
    pub fn score(self, samples: f64, mse: f64, parameters: f64) -> f64 {
        let penalty = match self {
            Criterion::Bic => parameters * samples.ln(),
            Criterion::Aic => 2.0 * parameters,
        };
        samples * mse.max(f64::MIN_POSITIVE).ln() + penalty
    }
}

/// The candidate with the smallest score (the first of equal ones), `None` if there is none.
pub fn best<T: Copy>(scores: &[(T, f64)]) -> Option<T> {
    scores
        .iter()
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(c, _)| *c)
}

/// `candidate: score − score of chosen` for every candidate, comma separated (`7: +0.0, 10:
/// −12.3`), for a report line.
pub(crate) fn relative_scores<T: Copy + PartialEq + std::fmt::Display>(
    scores: &[(T, f64)],
    chosen: T,
) -> String {
    let base = scores
        .iter()
        .find(|(c, _)| *c == chosen)
        .map_or(f64::NAN, |s| s.1);
    scores
        .iter()
        .map(|(c, v)| format!("{c}: {:+.1}", v - base))
        .collect::<Vec<_>>()
        .join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scores_are_the_textbook_formulas() {
        // N = 100, σ̂² = 0.5, d = 3: BIC = 100 ln 0.5 + 3 ln 100, AIC = 100 ln 0.5 + 6.
        let (n, mse, d) = (100.0, 0.5, 3.0);
        let bic = Criterion::Bic.score(n, mse, d);
        let aic = Criterion::Aic.score(n, mse, d);
        assert!((bic - (-69.314_718_055_994_53 + 13.815_510_557_964_274)).abs() < 1e-9);
        assert!((aic - (-69.314_718_055_994_53 + 6.0)).abs() < 1e-9);
        // A zero mean square is floored, not −∞.
        assert!(Criterion::Bic.score(n, 0.0, d).is_finite());
    }

    #[test]
    fn relative_scores_are_differences_to_the_chosen() {
        assert_eq!(
            relative_scores(&[(7, 10.0), (10, 4.5)], 10),
            "7: +5.5, 10: +0.0"
        );
    }

    #[test]
    fn the_first_smallest_wins() {
        assert_eq!(best(&[(2, 5.0), (3, 1.0), (4, 1.0), (5, 7.0)]), Some(3));
        assert_eq!(best(&[(2, f64::INFINITY), (3, 4.0)]), Some(3));
        assert_eq!(best::<usize>(&[]), None);
    }

    #[test]
    fn both_criteria_stop_where_the_gain_is_below_the_penalty() {
        // Residual variances of nested models: a big drop at d = 2, then tiny gains. BIC
        // stops at 2; with N = 1000 a gain of 0.1 % per parameter is below both penalties.
        let n = 1000.0;
        let mse = [(1, 2.0), (2, 1.0), (3, 0.999), (4, 0.998)];
        let scores = |c: Criterion| -> Vec<(usize, f64)> {
            mse.iter()
                .map(|&(d, m)| (d, c.score(n, m, d as f64)))
                .collect()
        };
        assert_eq!(best(&scores(Criterion::Bic)), Some(2));
        assert_eq!(best(&scores(Criterion::Aic)), Some(2));
    }
}
