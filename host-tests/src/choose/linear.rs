//! The linear baseline: the linear model a user would fit elsewhere (`oe`/`tfest`, a few lines
//! of scipy), fitted on every record beside the model with the element, so that the model
//! reported is never worse than it.
//!
//! In the model class it is the static element with one segment on `[u_min, u_max]` (a gain
//! and an offset in front of `G` with `G(1) = 1`), identified like any model: the subspace
//! start at horizons from the data (shortened where the input Hankel Gram is rank deficient,
//! a stable start where the subspace model is not stable), refined by output error (the
//! prediction-error method with a white noise model, which minimises the simulation error as
//! `oe` does), the order by the same criterion among orders 1 to [`LINEAR_MAX_ORDER`].

use super::{Best, Choices, ChooseError, KnotPlacement, OrderCandidates, Segments, best_model};
use crate::identify::IdentifyOptions;
use crate::refine::pem::NoiseOrder;

/// The highest order of the linear baseline: orders 1 to 6 are refined and the smallest BIC is
/// kept (a linear fit has few parameters, so all of them cost little).
pub const LINEAR_MAX_ORDER: usize = 6;

/// `base` (interval, hold, horizons, order) with the linear element: static, the two knots
/// `u_min` and `u_max`.
pub fn linear_options(base: &IdentifyOptions) -> IdentifyOptions {
    let mut opts = base.clone();
    opts.static_nonlinearity = true;
    opts.knots_asc = vec![base.u_min(), base.u_max()];
    opts.knots_desc = opts.knots_asc.clone();
    opts
}

/// Whether `opts` already is the linear model (static, one segment): no baseline to fit.
pub fn is_linear(opts: &IdentifyOptions) -> bool {
    opts.static_nonlinearity && opts.knots_asc.len() <= 2 && opts.knots_desc.len() <= 2
}

/// The linear baseline of `(u, y)`: [`best_model`] with [`linear_options`], horizons and
/// estimator as in `choices`, the two knots kept.
pub fn linear_model(
    u: &[f64],
    y: &[f64],
    base: &IdentifyOptions,
    choices: &Choices,
) -> Result<Best, ChooseError> {
    let choices = Choices {
        segments: Segments::Given,
        knots: KnotPlacement::Given,
        noise: NoiseOrder::Fixed(0),
        orders: OrderCandidates::UpTo(LINEAR_MAX_ORDER),
        ..choices.clone()
    };
    best_model(u, y, &linear_options(base), &choices)
}
