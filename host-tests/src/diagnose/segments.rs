//! The number of uniform segments per path, chosen on the estimation data by the BIC of the
//! in-sample simulation error, `N ln(MSE) + k ln N`, `k` = border values + 2 n + 2.

use std::ops::RangeInclusive;

use super::model::{self, FitOptions, InitialState, Metric, Saturation, Structure};
use super::options::{DiagnoseOptions, PoleRefinement};
use crate::identify::IdentifyOptions;
use crate::model::Record;
use crate::numerics::select::{Criterion, best};

/// Sets `id`'s knots to the best uniform segment count in `range` and says so in words (empty
/// when no count could be fitted: `id` is then left alone). `shared`: one border for both
/// directions.
pub fn select_segments(
    range: &RangeInclusive<usize>,
    est: &Record,
    id: &mut IdentifyOptions,
    opts: &DiagnoseOptions,
    shared: bool,
) -> String {
    let (u_min, u_max, hold) = (id.u_min(), id.u_max(), id.hold);
    let initial = opts.initial.unwrap_or(if hold > 0 {
        InitialState::Rest
    } else {
        InitialState::Estimated
    });
    let ne = est.len();
    let mut scores: Vec<(usize, f64)> = Vec::new();
    let mut tried = Vec::new();
    for segs in range.clone() {
        let trial = IdentifyOptions::uniform(u_min, u_max, segs, hold);
        let mut ids = id.clone();
        ids.knots_desc = trial.knots_asc.clone();
        ids.knots_asc = trial.knots_asc;
        let fo = FitOptions {
            identify: ids,
            initial,
            time_center: 0.0,
            time_scale: 1.0,
            outlier_k: opts.outlier_k,
            rounds: 1,
            refit: true,
            refine_poles: opts.refine_poles != PoleRefinement::Never,
            saturation: Saturation::default(),
        };
        let Ok(m) = model::fit_structure(&Structure::base(), est, &fo) else {
            continue;
        };
        let e = model::evaluate(&m, est, hold..ne, Metric::Simulation);
        let borders = if shared { segs + 1 } else { 2 * segs + 1 };
        let k = (borders + 2 * m.hammerstein.order + 2) as f64;
        let nn = (ne - hold) as f64;
        let bic = Criterion::Bic.score(nn, e.rmse * e.rmse, k);
        if bic.is_finite() {
            tried.push(format!("{segs}: {bic:.1}"));
            scores.push((segs, bic));
        }
    }
    let Some(segs) = best(&scores) else {
        return String::new();
    };
    let u = IdentifyOptions::uniform(u_min, u_max, segs, hold);
    id.knots_desc = u.knots_asc.clone();
    id.knots_asc = u.knots_asc;
    format!(
        "; {segs} uniform segments per path, chosen by the BIC of the estimation simulation error (tried {})",
        tried.join(", ")
    )
}
