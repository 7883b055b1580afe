//! Friction in an extended model ([`Structure::friction`](super::Structure)): Coulomb
//! friction and an offset on the output's velocity, fed back into `G`'s input
//! ([`crate::friction`]), fitted with `G` by simulation error from the model's Hammerstein
//! part on the delayed input; the additive terms refitted after it.

use crate::diagnose::dynamics::DynamicsError;
use crate::diagnose::error::DiagnoseError;
use crate::diagnose::simulate::delay_input;
use crate::friction::{FrictionOptions, fit_friction};
use crate::model::Record;

use super::extended::ExtendedModel;

/// Replaces the simulation of `model`'s Hammerstein part by its element and `G` with friction
/// on the velocity, fitted on the simulation error of `rec` without the `skip` samples (the
/// input drives the simulation through them), from the Hammerstein part (the fit never ends
/// worse than it: its start is among the fit's); the friction on the sign of the output itself
/// when `speed`, else of its change.
pub(super) fn fit_friction_into(
    model: &mut ExtendedModel,
    rec: &Record,
    skip: &[bool],
    speed: bool,
) -> Result<(), DiagnoseError> {
    let ud = delay_input(&rec.u, model.structure.delay);
    let target = model.less_additive(rec);
    let fit = fit_friction(
        &ud,
        &target,
        skip,
        &model.hammerstein,
        false,
        &FrictionOptions {
            speed,
            ..FrictionOptions::default()
        },
    )
    .map_err(|e| DiagnoseError::Dynamics(DynamicsError::Friction(e)))?;
    model.friction = Some(fit.model);
    model.refit_additive(rec, skip);
    Ok(())
}
