//! The element with memory in an extended model ([`Structure::element`](super::Structure)):
//! the play operator or relay on the knots and `G`, fitted by simulation error from the
//! model's subspace estimate on the delayed input, the additive terms refitted after it.
//! With an output map in the structure ([`Structure::output_map_segments`](super::Structure)),
//! the map is the output saturation alone: the element's simulation clamped at the levels the
//! data check finds the output pinned at, `G` and the borders fitted through the clamp.

use crate::diagnose::dynamics::DynamicsError;
use crate::diagnose::error::DiagnoseError;
use crate::diagnose::output_map::OutputMap;
use crate::diagnose::simulate::delay_input;
use crate::hysteresis::{ElementFitOptions, Start, fit_hysteresis_skipping};
use crate::model::MemoryElement;

use super::extended::ExtendedModel;
use super::fit_options::Saturation;
use crate::model::Record;

/// Replaces the simulation of `model`'s Hammerstein part by the element `kind` and `G`,
/// fitted on the simulation error of `rec` without the `skip` samples (the input drives the
/// element through them). The start is the model's static or two-path estimate
/// (`shared`: one border for both directions). `G` is kept to the poles a record of
/// `fitted` samples can validate ([`ExtendedModel::validatable_radius`]): the inner
/// validation refuses a model with a slower mode, so the fit must look for its best model
/// among the others. With `clamp` (levels where the output is pinned), the simulation is
/// clamped there in the fit and the model's output map is that clamp alone (the identity
/// with flat ends at the levels); without it the model has no output map.
pub(super) fn fit_element(
    model: &mut ExtendedModel,
    rec: &Record,
    skip: &[bool],
    kind: MemoryElement,
    shared: bool,
    fitted: usize,
    clamp: Option<&Saturation>,
) -> Result<(), DiagnoseError> {
    let ud = delay_input(&rec.u, model.structure.delay);
    let target = model.less_additive(rec);
    let start = if shared {
        Start::Static
    } else {
        Start::TwoPath
    };
    let fit = fit_hysteresis_skipping(
        &ud,
        &target,
        skip,
        &model.hammerstein,
        start,
        &ElementFitOptions {
            max_pole_radius: ExtendedModel::validatable_radius(fitted),
            floor: clamp.and_then(|c| c.floor),
            ceiling: clamp.and_then(|c| c.ceiling),
            ..ElementFitOptions::new(kind)
        },
    )
    .map_err(|e| DiagnoseError::Dynamics(DynamicsError::Hysteresis(e)))?;
    model.hysteresis = Some(fit.model);
    model.output_map = clamp.map(saturation_map);
    // The additive terms were fitted to the subspace model's residual.
    model.refit_additive(rec, skip);
    Ok(())
}

/// The output saturation alone: the identity with flat ends at the levels.
fn saturation_map(sat: &Saturation) -> OutputMap {
    OutputMap {
        x: vec![0.0, 1.0],
        v: vec![0.0, 1.0],
        ceiling: sat.ceiling,
        floor: sat.floor,
    }
}
