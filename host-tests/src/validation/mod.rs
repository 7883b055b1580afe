//! Validation beneath the diagnosis: the data against the method's assumptions and a model's
//! residual against the model's.
//!
//! * [`checks`]: the data checks of an estimation record, before any fit (Table I structure,
//!   both paths over the whole interval, persistent excitation, the hold for μ0, saturation,
//!   quantisation, input levels, feedback, an integrating plant); one entry: [`data_checks`];
//! * [`residual`]: the statistical tests of a residual, each at the 1 % level; one entry:
//!   [`residual_tests`];
//! * [`stats`], [`noise`], [`arx`] and [`unit_root`]: the statistics they use (distributions,
//!   correlations, spectra, the AR model of a signal, least-squares ARX pieces and the
//!   unit-root test).
//!
//! The diagnosis runs both and acts on them; the pages of `identify` and `validate` show
//! them. Nothing here depends on the diagnosis.

use std::ops::Range;

use crate::identify::IdentifyOptions;

pub mod arx;
pub mod checks;
pub mod noise;
pub mod residual;
pub mod stats;
pub mod unit_root;

use crate::model::Element;
pub use checks::{Check, CheckSetup, Saturation, Warning};
pub use residual::{Test, TestSet};

/// The data checks of an estimation record `(u, y)` identified with `opts` (knots chosen) as
/// `kind`.
pub fn data_checks(u: &[f64], y: &[f64], opts: &IdentifyOptions, kind: Element) -> Vec<Warning> {
    checks::check_data(u, y, &CheckSetup::new(opts, kind))
}

/// The residual tests of a model with the knots `knots_asc` and `knots_desc` (`shared`: one
/// border for both directions, a static element) on `range` of a record with the input `u`:
/// `residual` and `simulated` are the model's residual and simulated output on `range` (one
/// value per sample of it). The hat-basis regressor, δ and the bins are built on the whole
/// of `u` and taken on `range`.
pub fn residual_tests(
    knots_asc: &[f64],
    knots_desc: &[f64],
    shared: bool,
    u: &[f64],
    residual: &[f64],
    simulated: &[f64],
    range: Range<usize>,
) -> TestSet {
    let (delta, z, bins, bin_count) = residual::regressor(u, knots_asc, knots_desc, shared);
    let regressor: Vec<Vec<f64>> = z.iter().map(|c| c[range.clone()].to_vec()).collect();
    residual::run_tests(&residual::ResidualInput {
        residual,
        u: &u[range.clone()],
        delta: &delta[range.clone()],
        regressor: &regressor,
        bins: &bins[range],
        bin_count,
        simulated,
    })
}
