//! Does the output integrate? An augmented Dickey–Fuller test with the input as a covariate:
//! the ARX model of the output on the hat-basis regressor channels (lags `0…L`) and a
//! constant,
//!
//! ```text
//! y(t) = c + Σᵢ aᵢ y(t − i) + Σⱼ bⱼᵀ z(t − j) + e(t),
//! ```
//!
//! fitted once free and once with the unit root imposed (`Σ aᵢ = 1`, i.e. the increments
//! `Δy(t)` on `Δy(t − 1…t − n_a + 1)` and the same `z` lags). `τ = sign(ρ̂) √F`, with
//! `ρ̂ = Σ âᵢ − 1` and `F` the one-restriction statistic of the two residual sums of squares,
//! is the Dickey–Fuller `t` statistic of `ρ`. A stable plant rejects the unit root (`τ`
//! far below the 1 % critical value −3.43 of the test with a constant); an integrator —
//! voltage → position, a level loop — does not.
//!
//! The test is of the data, not of the model fitted under the method's normalisation
//! `G(1) = 1`, which an integrating plant breaks: that model's poles then land anywhere, and
//! the pole-radius rule of [`checks::integrating`](super::checks::integrating) misses it. With
//! the input as a stationary covariate the statistic's null distribution lies between
//! Dickey–Fuller's and the normal (Hansen, "Rethinking the univariate approach to unit root
//! testing", Econometric Theory 1995), so −3.43 errs towards not rejecting, i.e. towards the
//! warning.

use super::arx::{Column, continuous_rows, fit, rss};
use crate::numerics::select::{Criterion, best};

/// Dickey–Fuller's 1 % critical value of `τ` for the regression with a constant (asymptotic).
pub(crate) const CRITICAL_1PCT: f64 = -3.43;

/// The test's result.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UnitRoot {
    /// Output lags of the ARX model (by BIC, 1…6).
    pub ar_order: usize,
    /// `Σ âᵢ − 1`: zero for an integrator, negative for a stable plant.
    pub rho: f64,
    /// The `t` statistic of `ρ`.
    pub tau: f64,
}

impl UnitRoot {
    /// Whether the unit root is rejected at 1 % (the output does not integrate).
    pub fn rejected(&self) -> bool {
        self.tau < CRITICAL_1PCT
    }
}

/// The test on `y` after the regressor channels `z`, input lags `0…lags`; rows whose lags reach
/// across a gap in `time` are left out. `None` when the record is too short to fit.
pub fn unit_root(z: &[Vec<f64>], y: &[f64], time: &[f64], lags: usize) -> Option<UnitRoot> {
    const MAX_AR: usize = 6;
    let zl: Vec<Column> = (0..=lags)
        .flat_map(|j| z.iter().map(move |c| Column::Lagged(c, j)))
        .collect();
    let dy: Vec<f64> = (0..y.len())
        .map(|t| if t == 0 { 0.0 } else { y[t] - y[t - 1] })
        .collect();
    let yl: Vec<Column> = (1..=MAX_AR).map(|i| Column::Lagged(y, i)).collect();
    let dyl: Vec<Column> = (1..MAX_AR).map(|i| Column::Lagged(&dy, i)).collect();
    let rows = continuous_rows(time, (lags + 1).max(MAX_AR + 1));
    let n = rows.len() as f64;
    let scores: Vec<(usize, f64)> = (1..=MAX_AR)
        .filter_map(|na| {
            let cols = columns(&yl[..na], &zl);
            let r = rss(&cols, y, &rows)?;
            Some((na, Criterion::Bic.score(n, r / n, cols.len() as f64)))
        })
        .collect();
    let na = best(&scores)?;
    let free = columns(&yl[..na], &zl);
    let (beta, rss_free) = fit(&free, y, &rows)?;
    let rss_root = rss(&columns(&dyl[..na - 1], &zl), &dy, &rows)?;
    let rho = beta[1..=na].iter().sum::<f64>() - 1.0;
    let dof = (n - free.len() as f64).max(1.0);
    let f = ((rss_root - rss_free).max(0.0) / (rss_free / dof)).max(0.0);
    Some(UnitRoot {
        ar_order: na,
        rho,
        tau: rho.signum() * f.sqrt(),
    })
}

/// The constant, the output lags and the input lags, as regression columns.
fn columns<'a>(outputs: &[Column<'a>], inputs: &[Column<'a>]) -> Vec<Column<'a>> {
    let mut c = vec![Column::Constant(1.0)];
    c.extend_from_slice(outputs);
    c.extend_from_slice(inputs);
    c
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A pseudo-random sequence in [−1, 1) (a linear congruential generator: the test needs no
    /// statistical quality, only an input that varies).
    fn input(len: usize, seed: u64) -> Vec<f64> {
        let mut s = seed;
        (0..len)
            .map(|_| {
                s = s
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                ((s >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
            })
            .collect()
    }

    fn record(pole: f64, seed: u64) -> (Vec<Vec<f64>>, Vec<f64>, Vec<f64>) {
        let u = input(3000, seed);
        let v = input(3000, seed + 7);
        let mut x = 0.0;
        let y: Vec<f64> = u
            .iter()
            .zip(&v)
            .map(|(ui, vi)| {
                x = pole * x + 0.1 * ui;
                x + 0.02 * vi
            })
            .collect();
        let time = (0..y.len()).map(|t| t as f64).collect();
        (vec![u], y, time)
    }

    #[test]
    fn an_integrator_keeps_its_unit_root_and_a_slow_stable_plant_rejects_it() -> Result<(), String>
    {
        for seed in 1..=3 {
            let (z, y, time) = record(1.0, seed);
            let r = unit_root(&z, &y, &time, 2).ok_or("too short")?;
            assert!(!r.rejected(), "integrator, seed {seed}: {r:?}");
            assert!(r.rho.abs() < 0.01, "{r:?}");
            let (z, y, time) = record(0.98, seed);
            let r = unit_root(&z, &y, &time, 2).ok_or("too short")?;
            assert!(r.rejected(), "pole 0.98, seed {seed}: {r:?}");
            // Output (not equation) noise biases the ARX estimate of ρ = −0.02; its sign holds.
            assert!(r.rho < -0.01 && r.rho > -0.1, "{r:?}");
        }
        Ok(())
    }
}
