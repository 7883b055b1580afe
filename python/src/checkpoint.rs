//! `hsid.solve_checkpoint`: an identifier's checkpoint solved, as `hsid solve --state` does.

use hsid_host::identify::{Solver, solve_checkpoint_with};
use hsid_host::model::Element;
use pyo3::prelude::*;

use crate::error::{Class, Failure};
use crate::model::Model;

/// The solve called `name` (`"dense"` or `"structured"`).
fn solver(name: &str) -> Result<Solver, Failure> {
    Solver::from_name(name).ok_or_else(|| {
        Failure::new(
            Class::Settings,
            "solver",
            format!("solver {name:?}: give \"dense\" or \"structured\" (the firmware's)"),
        )
    })
}

/// Solves the checkpoint `state` (the bytes `Identifier::save` wrote on a device or a
/// desktop, f32 or f64) into a model with the core's `solver` (`"dense"`, or `"structured"`
/// as the firmware solves: its model bit for bit); the GIL is released while solving. A
/// checkpoint records whether the element is static (one border) but not which two-path
/// element it is.
#[pyfunction]
#[pyo3(signature = (state, solver="dense"))]
pub fn solve_checkpoint(py: Python<'_>, state: &[u8], solver: &str) -> PyResult<Model> {
    let how = self::solver(solver)?;
    let solved = py
        .detach(|| solve_checkpoint_with(state, how))
        .map_err(Failure::from)?;
    let kind = solved.shared_knots.then_some(Element::Static);
    Ok(Model::new(solved.model.to_json(kind)))
}
