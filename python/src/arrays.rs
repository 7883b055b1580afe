//! numpy arrays in and out: a 1-D floating-point array becomes a `Vec<f64>` (other float
//! dtypes and non-contiguous arrays converted explicitly); integers, booleans, complex numbers,
//! objects, other shapes and non-finite values are refused with a [`DataError`](crate::error).

use numpy::{PyArray1, PyArrayDescrMethods, PyArrayMethods, PyUntypedArray, PyUntypedArrayMethods};
use pyo3::prelude::*;

use crate::error::{Class, Failure};

/// The values of the 1-D float array `obj`, named `name` in errors, every one finite.
pub fn vector(name: &str, obj: &Bound<'_, PyAny>) -> Result<Vec<f64>, Failure> {
    let Ok(array) = obj.cast::<PyUntypedArray>() else {
        let ty = obj
            .get_type()
            .name()
            .map_or_else(|_| "?".to_string(), |n| n.to_string());
        return Err(Failure::new(
            Class::Data,
            "not_an_array",
            format!("{name} is a {ty}, not a numpy array: give numpy.asarray({name}, dtype=float)"),
        ));
    };
    if array.ndim() != 1 {
        return Err(Failure::new(
            Class::Data,
            "shape",
            format!(
                "{name} has shape {:?}: give a 1-D array (one value per sample)",
                array.shape()
            ),
        ));
    }
    let dtype = array.dtype();
    if dtype.kind() != b'f' {
        return Err(Failure::new(
            Class::Data,
            "dtype",
            format!(
                "{name} has dtype {dtype}: give floating-point samples ({name}.astype(float) if the values are meant as numbers)"
            ),
        ));
    }
    let values = match obj.cast::<PyArray1<f64>>() {
        Ok(a) => read(a),
        Err(_) => {
            let converted = obj
                .call_method1("astype", ("float64",))
                .map_err(|e| Failure::new(Class::Data, "dtype", format!("{name}: {e}")))?;
            let a = converted
                .cast::<PyArray1<f64>>()
                .map_err(|e| Failure::new(Class::Data, "dtype", format!("{name}: {e}")))?;
            read(a)
        }
    };
    finite(name, &values)?;
    Ok(values)
}

/// The values of a float64 array, in order whatever its strides.
fn read(a: &Bound<'_, PyArray1<f64>>) -> Vec<f64> {
    a.readonly().as_array().iter().copied().collect()
}

/// Refuses the first non-finite value of `v`.
pub fn finite(name: &str, v: &[f64]) -> Result<(), Failure> {
    match v.iter().position(|x| !x.is_finite()) {
        None => Ok(()),
        Some(i) => Err(Failure::new(
            Class::Data,
            "non_finite",
            format!(
                "{name}[{i}] is {}: every sample must be finite (drop or repair the sample)",
                v[i]
            ),
        )),
    }
}

/// Refuses values of `v` outside `[lo, hi]`.
pub fn inside(name: &str, v: &[f64], lo: f64, hi: f64) -> Result<(), Failure> {
    match v.iter().position(|x| *x < lo || *x > hi) {
        None => Ok(()),
        Some(i) => Err(Failure::new(
            Class::Data,
            "input_out_of_range",
            format!(
                "{name}[{i}] = {} lies outside the model's input interval [{lo}, {hi}]",
                v[i]
            ),
        )),
    }
}

/// A float64 numpy array holding `v`.
pub fn out<'py>(py: Python<'py>, v: Vec<f64>) -> Bound<'py, PyArray1<f64>> {
    PyArray1::from_vec(py, v)
}
