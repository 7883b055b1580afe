//! `hsid.solve_checkpoint`: an identifier's checkpoint solved, as `hsid solve --state` does.

use hsid_host::identify::solve_checkpoint as solve;
use hsid_host::model_file::NonlinearityKind;
use pyo3::prelude::*;

use crate::error::Failure;
use crate::model::Model;

/// Solves the checkpoint `state` (the bytes `Identifier::save` wrote on a device or a
/// desktop, f32 or f64) into a model; the GIL is released while solving. A checkpoint records
/// whether the element is static (one border) but not which two-path element it is.
#[pyfunction]
pub fn solve_checkpoint(py: Python<'_>, state: &[u8]) -> PyResult<Model> {
    let solved = py.detach(|| solve(state)).map_err(Failure::from)?;
    let kind = solved.shared_knots.then_some(NonlinearityKind::Static);
    Ok(Model::new(solved.model.to_json(kind)))
}
