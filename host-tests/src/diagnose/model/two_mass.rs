//! Play between motor and load in an extended model ([`Structure::play_between`](super::Structure)):
//! the two-mass drive of [`crate::sandwich`], driven by the Hammerstein part's static output
//! on the delayed input, fitted by simulation error from the poles of the current `G` (the
//! element's, when the model has one); the additive terms refitted after it.

use crate::diagnose::dynamics::DynamicsError;
use crate::diagnose::error::DiagnoseError;
use crate::diagnose::simulate::delay_input;
use crate::model::Record;
use crate::numerics::poly::eigenvalues;
use crate::sandwich::{TwoMassOptions, fit_two_mass_skipping};

use super::extended::ExtendedModel;

/// Replaces the simulation of `model`'s `G` (and its element, if any) by the two-mass drive
/// with play, fitted on the simulation error of `rec` without the `skip` samples.
pub(super) fn fit_two_mass_into(
    model: &mut ExtendedModel,
    rec: &Record,
    skip: &[bool],
) -> Result<(), DiagnoseError> {
    let ud = delay_input(&rec.u, model.structure.delay);
    let h = model.hammerstein.nonlinearity_output(&ud);
    let target = model.less_additive(rec);
    let poles = match &model.hysteresis {
        Some(el) => el.poles(),
        None => eigenvalues(model.hammerstein.a.clone()).unwrap_or_default(),
    };
    let fit = fit_two_mass_skipping(&h, &target, skip, &poles, &TwoMassOptions::default())
        .map_err(|e| DiagnoseError::Dynamics(DynamicsError::TwoMass(e)))?;
    model.hysteresis = None;
    model.friction = None;
    model.two_mass = Some(fit);
    model.refit_additive(rec, skip);
    Ok(())
}
