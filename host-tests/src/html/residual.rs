//! The data checks and residual tests of a plain model on one record, for the pages of
//! `identify` and `validate` (the page of `diagnose` takes them from the diagnosis): the same
//! checks and tests `diagnose` runs, on the simulation residual after the hold.

use crate::identify::{HostModel, IdentifyOptions};
use crate::validation::checks::{CheckSetup, check_data};
use crate::validation::residual::{ResidualInput, TestSet, regressor, run_tests};
use crate::validation::{Nonlinearity, Warning};

/// The residual tests of `model`'s simulation `sim` of the record `(u, y)`, leaving out the
/// first `skip` samples; `shared`: one border for both directions (a static element). `None`
/// when fewer than 20 samples remain.
pub fn residual_tests(
    model: &HostModel,
    u: &[f64],
    y: &[f64],
    sim: &[f64],
    skip: usize,
    shared: bool,
) -> Option<TestSet> {
    let n = u.len().min(y.len()).min(sim.len());
    if skip + 20 > n {
        return None;
    }
    let residual: Vec<f64> = (skip..n).map(|i| y[i] - sim[i]).collect();
    let (delta, z, bins, bin_count) =
        regressor(&u[..n], &model.knots_asc, &model.knots_desc, shared);
    let regressor: Vec<Vec<f64>> = z.iter().map(|c| c[skip..n].to_vec()).collect();
    Some(run_tests(&ResidualInput {
        residual: &residual,
        u: &u[skip..n],
        delta: &delta[skip..n],
        regressor: &regressor,
        bins: &bins[skip..n],
        bin_count,
        simulated: &sim[skip..n],
    }))
}

/// The data checks of an estimation record identified with `opts` as `kind`.
pub fn data_checks(
    u: &[f64],
    y: &[f64],
    opts: &IdentifyOptions,
    kind: Nonlinearity,
) -> Vec<Warning> {
    check_data(
        u,
        y,
        &CheckSetup {
            kind,
            knots_asc: &opts.knots_asc,
            knots_desc: &opts.knots_desc,
            hold: opts.hold,
            settle: opts.settle,
            mu0_known: opts.mu0.is_some(),
            f: opts.f,
            p: opts.p,
        },
    )
}
