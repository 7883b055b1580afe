//! `hsid.solve_many`: many devices' checkpoints solved across cores, one model or one
//! exception object per checkpoint, as `hsid fleet` does.

use hsid_host::fleet::solve::{Checkpoint, solve_many as solve};
use hsid_host::fleet::{DeviceError, DeviceResult};
use hsid_host::model::Element;
use pyo3::prelude::*;

use crate::error::{Class, Failure};
use crate::model::Model;

/// Solves every checkpoint of `states` on `threads` worker threads (`None`: one per core)
/// with the GIL released; returns, in order, a `Model` for each checkpoint that solved and
/// the `HsidError` (not raised) for each that did not, so that one bad device never costs
/// the batch.
#[pyfunction]
#[pyo3(signature = (states, threads = None))]
pub fn solve_many(
    py: Python<'_>,
    states: Vec<Vec<u8>>,
    threads: Option<usize>,
) -> PyResult<Vec<Py<PyAny>>> {
    let checkpoints: Vec<Checkpoint> = states
        .into_iter()
        .enumerate()
        .map(|(i, bytes)| Checkpoint {
            device: i.to_string(),
            bytes: Ok(bytes),
        })
        .collect();
    let results = py
        .detach(|| solve(&checkpoints, None, threads))
        .map_err(|e| PyErr::from(Failure::new(Class::Settings, "threads", e.to_string())))?;
    results.into_iter().map(|r| outcome(py, r)).collect()
}

/// A device's model, or its error as an exception object.
fn outcome(py: Python<'_>, r: DeviceResult) -> PyResult<Py<PyAny>> {
    match r.outcome {
        Ok(solved) => {
            let kind = solved.shared_knots.then_some(Element::Static);
            Ok(Py::new(py, Model::new(solved.model.to_json(kind)))?.into_any())
        }
        Err(e) => {
            let failure = match e {
                DeviceError::Solve(e) => Failure::from(e),
                other => Failure::new(Class::Data, other.kind(), other.to_string()),
            };
            Ok(PyErr::from(failure).into_value(py).into_any())
        }
    }
}
