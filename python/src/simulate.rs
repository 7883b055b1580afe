//! `hsid.excite` and `hsid.simulate_plant`: the method's excitation and a true plant's
//! response, as `hsid excite` and `hsid simulate --plant` make them.

use hsid::Excitation;
use hsid_host::simulate::{PlantSpec, check_excitation_length, simulate_plant as plant};
use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::PyString;
use rand_core::SeedableRng;
use rand_pcg::Pcg32;

use crate::arrays::{out, vector};
use crate::error::{Class, Failure};

/// The most samples `excite` makes (2³⁰, 8 GiB of float64): a bound on the array, not on the
/// method.
pub const MAX_EXCITATION: usize = 1 << 30;

/// The method's excitation (Table I of the paper): `samples` inputs in [umin, umax], the
/// first `hold` at umin, random runs after it (PCG32 seeded with `seed`); equal to
/// `hsid excite` with the same arguments. `samples` must exceed `hold` (else
/// `SettingsError` of kind `excitation_too_short`, as `hsid excite` refuses it).
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
    let excitation =
        Excitation::new(umin, umax, hold, Pcg32::seed_from_u64(seed)).map_err(Failure::from)?;
    check_excitation_length(samples, hold)
        .map_err(|e| Failure::new(Class::Settings, "excitation_too_short", e.to_string()))?;
    if samples > MAX_EXCITATION {
        return Err(Failure::new(
            Class::Settings,
            "too_large",
            format!(
                "samples={samples}: more than the {MAX_EXCITATION} samples an array is made of here; \
                 generate the excitation in parts (hsid excite streams any length)"
            ),
        )
        .into());
    }
    let u: Vec<f64> = excitation.take(samples).collect();
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
