//! Statistical tests of a residual against the model's assumptions, each at the 1 % level
//! (99 % bounds):
//!
//! | test | statistic | reference distribution under "nothing missing" |
//! |---|---|---|
//! | `whiteness` | Ljung–Box `Q = N(N+2) Σ_{k≤K} ρ̂(k)²/(N−k)` | χ²(K) |
//! | `input_correlation` | max over lags `−K…K` of `|r̂_uε(k)| / σ_k`, input prewhitened | normal, Bonferroni over the lags |
//! | `direction_correlation` | the same with δ(t) | idem |
//! | `regressor_correlation` | max over channels `z_i` and lags `0…K` | idem |
//! | `structure_input` | binned means of ε per path and knot segment | χ²(bins − 1) |
//! | `structure_output` | binned means of ε in deciles of the simulated output | χ²(9) |
//! | `trend` | slope and mean of ε over time, Newey–West standard errors | normal, two tests |
//! | `spectral_line` | largest Hann periodogram ordinate / local median spectrum | exponential, max of M |
//! | `state_dependence` | max over lags `0…K` of the correlation of ε with `(ŷ − ȳ)·Δŷ` (ŷ the simulated output, the product's part not explained by `1, ŷ, Δŷ`), prewhitened | normal, Bonferroni over the lags |
//! | `heavy_tails` | count of |ε − median| beyond 5 robust σ (1.4826 MAD) | Poisson(N · 5.7e-7) |
//!
//! The cross-correlations are computed after prewhitening (an AR model of the input filters
//! both signals), and `σ_k² = (1 + 2 Σ_j ρ_ε(j) ρ_x(j)) / N` (Bartlett) corrects their bounds
//! for what colour remains; the plain white-noise bound is `2.58/√N`. Binned means use
//! the residual's autocorrelation for their variances. Spectral lines shared with the input
//! (the Table I excitation has lines at π/2 and π) are not counted: they are input effects.

pub mod correlation;
pub mod regressor;
pub mod result;
pub mod spectrum;
pub mod state;
pub mod structure;
pub mod tails;
pub mod trend;
pub mod whiteness;

pub use regressor::regressor;

use crate::numerics::rms;
use crate::validation::stats::acf;
pub use result::{Curves, LEVEL, ResidualInput, Test, TestResult, TestSet};

fn max_lag(n: usize) -> usize {
    (n / 10).clamp(2, 25)
}

/// Runs every test on a residual.
pub fn run_tests(inp: &ResidualInput) -> TestSet {
    let r = inp.residual;
    let n = r.len();
    let mut set = TestSet {
        samples: n,
        rms: rms(r),
        ..TestSet::default()
    };
    if n < 40 {
        return set;
    }
    let k = max_lag(n);
    let rho = acf(r, k);
    whiteness::whiteness(inp, &rho, k, &mut set);
    correlation::correlations(inp, &rho, k, &mut set);
    structure::structure(inp, &rho, &mut set);
    trend::trend(inp, &mut set);
    spectrum::spectral_line(inp, &mut set);
    state::state_dependence(inp, &rho, k, &mut set);
    tails::heavy_tails(inp, &mut set);
    set
}
