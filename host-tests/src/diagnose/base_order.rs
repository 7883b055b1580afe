//! The base model's order when the declared one cannot be normalised.
//!
//! The paper's model is normalised to `G(1) = 1`; the core refuses an estimate whose static
//! gain it cannot tell from zero ([`hsid::Error::ZeroStaticGain`]). A plant differentiating
//! its input has such a gain, but so has an estimate of more states than the record supports:
//! a slowly sampled plant, or an output curve the linear part cannot carry, leaves the extra
//! states a zero near `z = 1` that cancels the gain. When the user declared the order, the
//! diagnosis steps it down to the highest order whose estimate can be normalised, says so in
//! a warning of its own ([`Check::Order`]), and goes on from there: the unmodeled-dynamics
//! step can still propose the declared order again, on the extended structure. With the order
//! chosen from the singular values, or when no lower order can be normalised either, the
//! error stands.

use super::error::DiagnoseError;
use super::fit_plan::FitPlan;
use super::model::{self, ExtendedModel, Structure};
use super::options::DiagnoseOptions;
use crate::identify::{IdentifyError, IdentifyOptions};
use crate::model::Record;
use crate::validation::checks::{Check, Warning, warn};

/// Whether `e` is the core's refusal of a (near) zero static gain.
fn zero_gain(e: &DiagnoseError) -> bool {
    matches!(
        e,
        DiagnoseError::Identify(IdentifyError::Core(hsid::Error::ZeroStaticGain))
    )
}

/// The base structure fitted on `est` with the reported options of `plan`; when that fails
/// with a zero static gain at the order `id` declares, the highest lower order that does not,
/// with `id` and `plan` set to it and the warning that says so.
pub(crate) fn fit_base(
    est: &Record,
    opts: &DiagnoseOptions,
    id: &mut IdentifyOptions,
    plan: &mut FitPlan,
) -> Result<(ExtendedModel, Option<Warning>), DiagnoseError> {
    let first = model::fit_structure(&Structure::base(), est, &plan.reported);
    let declared = match (&first, id.order) {
        (Err(e), Some(n)) if zero_gain(e) => n,
        _ => return first.map(|m| (m, None)),
    };
    for order in (1..declared).rev() {
        let lower = IdentifyOptions {
            order: Some(order),
            ..id.clone()
        };
        let lower_plan = FitPlan::new(opts, &lower, est);
        match model::fit_structure(&Structure::base(), est, &lower_plan.reported) {
            Ok(m) => {
                *id = lower;
                *plan = lower_plan;
                return Ok((m, Some(lowered(declared, order))));
            }
            Err(e) if zero_gain(&e) => continue,
            Err(e) => return Err(e),
        }
    }
    first.map(|m| (m, None))
}

/// The warning for the declared order `declared` stepped down to `used`.
fn lowered(declared: usize, used: usize) -> Warning {
    warn(
        Check::Order,
        format!(
            "the estimate of the declared order {declared} has a static gain G(1) that cannot be told from zero, so it cannot be normalised (a zero near z = 1: more states than the record supports, or a differentiating plant, which is outside the model class); the base model has order {used}, the highest that can, and the unmodeled_dynamics step may propose more on the extended model (give --order {used} to start there without this warning)"
        ),
    )
}
