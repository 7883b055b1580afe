//! The residual tests of a fitted model on a stretch of a record.

use std::ops::Range;

use super::model::{Evaluation, ExtendedModel, Record};
use crate::validation::residual::{self, TestSet};

/// Tests of a model's residual on `range` of `rec`; `ev` is the model's evaluation there and
/// `shared` says whether the nonlinearity has one border for both directions.
pub fn residual_tests(
    model: &ExtendedModel,
    rec: &Record,
    range: Range<usize>,
    ev: &Evaluation,
    shared: bool,
) -> TestSet {
    let h = &model.hammerstein;
    let (delta, z, bins, count) = residual::regressor(&rec.u, &h.knots_asc, &h.knots_desc, shared);
    let r = range.clone();
    let zs: Vec<Vec<f64>> = z.iter().map(|c| c[r.clone()].to_vec()).collect();
    residual::run_tests(&residual::ResidualInput {
        residual: &ev.residual,
        u: &rec.u[r.clone()],
        delta: &delta[r.clone()],
        regressor: &zs,
        bins: &bins[r.clone()],
        bin_count: count,
        simulated: &ev.output[r],
    })
}
