//! The residual tests of a fitted model on a stretch of a record.

use std::ops::Range;

use super::model::{Evaluation, ExtendedModel};
use crate::model::Record;
use crate::validation::{self, TestSet};

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
    validation::residual_tests(
        &h.knots_asc,
        &h.knots_desc,
        shared,
        &rec.u,
        &ev.residual,
        &ev.output[range.clone()],
        range,
    )
}
