//! `hsid.solve_many`: many devices' checkpoints solved across cores, one model or one
//! exception object per checkpoint, as `hsid fleet` does.

use hsid_host::fleet::solve::{Checkpoint, solve_many as solve};
use hsid_host::fleet::{DeviceError, DeviceResult};
use hsid_host::model::Element;
use pyo3::prelude::*;
use pyo3::types::{PyByteArray, PyBytes, PyMemoryView, PyString};

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
    states: &Bound<'_, PyAny>,
    threads: Option<usize>,
) -> PyResult<Vec<Py<PyAny>>> {
    let states = checkpoints(states)?;
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

/// The bytes of each checkpoint of `states`, a list (or other iterable) of bytes-like objects;
/// one bytes object, a str or an item that is not bytes is a `DataError` saying what to give.
fn checkpoints(states: &Bound<'_, PyAny>) -> Result<Vec<Vec<u8>>, Failure> {
    let type_name = |o: &Bound<'_, PyAny>| {
        o.get_type()
            .name()
            .map_or_else(|_| "?".to_string(), |n| n.to_string())
    };
    if states.is_instance_of::<PyBytes>()
        || states.is_instance_of::<PyByteArray>()
        || states.is_instance_of::<PyString>()
        || states.cast::<PyMemoryView>().is_ok()
    {
        return Err(Failure::new(
            Class::Data,
            "not_a_list",
            format!(
                "states is one {} object: give a list of checkpoints' bytes \
                 (solve_many([state]) for one, or solve_checkpoint(state))",
                type_name(states)
            ),
        ));
    }
    let items = states.try_iter().map_err(|_| {
        Failure::new(
            Class::Data,
            "not_a_list",
            format!(
                "states is a {}: give a list of checkpoints' bytes",
                type_name(states)
            ),
        )
    })?;
    let mut out = Vec::new();
    for (i, item) in items.enumerate() {
        let item = item.map_err(|e| Failure::new(Class::Data, "not_a_list", e.to_string()))?;
        let bytes = if let Ok(b) = item.cast::<PyBytes>() {
            Some(b.as_bytes().to_vec())
        } else if let Ok(b) = item.cast::<PyByteArray>() {
            Some(b.to_vec())
        } else if item.cast::<PyMemoryView>().is_ok() {
            item.call_method0("tobytes")
                .ok()
                .and_then(|b| b.cast::<PyBytes>().ok().map(|b| b.as_bytes().to_vec()))
        } else {
            None
        };
        match bytes {
            Some(b) => out.push(b),
            None => {
                return Err(Failure::new(
                    Class::Data,
                    "not_bytes",
                    format!(
                        "states[{i}] is a {}: give each checkpoint's bytes (e.g. \
                         pathlib.Path(file).read_bytes())",
                        type_name(&item)
                    ),
                ));
            }
        }
    }
    Ok(out)
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
