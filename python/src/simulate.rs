//! `hsid.excite` and `hsid.simulate_plant`: the method's excitation and a true plant's
//! response, as `hsid excite` and `hsid simulate --plant` make them.

use hsid::Excitation;
use hsid_host::simulate::{PlantSpec, simulate_plant as plant};
use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::PyString;
use rand_core::SeedableRng;
use rand_pcg::Pcg32;

use crate::arrays::{out, vector};
use crate::error::Failure;

/// The method's excitation (Table I of the paper): `samples` inputs in [umin, umax], the
/// first `hold` at umin, random runs after it (PCG32 seeded with `seed`); equal to
/// `hsid excite` with the same arguments.
#[pyfunction]
#[pyo3(signature = (umin, umax, samples, *, hold=300, seed=1))]
pub fn excite(
    py: Python<'_>,
    umin: f64,
    umax: f64,
    samples: usize,
    hold: usize,
    seed: u64,
) -> PyResult<Bound<'_, PyArray1<f64>>> {
    let u: Vec<f64> = Excitation::new(umin, umax, hold, Pcg32::seed_from_u64(seed))
        .map_err(Failure::from)?
        .take(samples)
        .collect();
    Ok(out(py, u))
}

/// The output of the true plant `spec` (a dict, or its JSON text, in the format of
/// `hsid simulate --plant`) driven by `u` (1-D float array) from rest; `seed` replaces the
/// specification's noise seed.
#[pyfunction]
#[pyo3(signature = (spec, u, *, seed=None))]
pub fn simulate_plant<'py>(
    py: Python<'py>,
    spec: &Bound<'py, PyAny>,
    u: &Bound<'py, PyAny>,
    seed: Option<u64>,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let text: String = match spec.cast::<PyString>() {
        Ok(s) => s.extract()?,
        Err(_) => py
            .import("json")?
            .call_method1("dumps", (spec,))?
            .extract()?,
    };
    let spec = PlantSpec::from_json_str(&text).map_err(Failure::from)?;
    let u = vector("u", u)?;
    let output = plant(&spec, &u, seed).map_err(Failure::from)?;
    Ok(out(py, output.y))
}
