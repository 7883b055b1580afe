//! numpy arrays in and out: a 1-D floating-point array becomes a `Vec<f64>` (other float
//! dtypes and non-contiguous arrays converted explicitly; lists, pandas Series and other
//! array-likes read through `numpy.asarray` first); integers, booleans, complex numbers,
//! objects, text, other shapes and non-finite values are refused with a
//! [`DataError`](crate::error).

use numpy::{PyArray1, PyArrayDescrMethods, PyArrayMethods, PyUntypedArray, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyString};

use crate::error::{Class, Failure};

/// The values of the 1-D float array `obj`, named `name` in errors, every one finite. Anything
/// else numpy reads as an array (a list, a pandas Series, a memoryview, any object with
/// `__array__`) is taken through `numpy.asarray(obj)` first, then checked as an array is.
pub fn vector(name: &str, obj: &Bound<'_, PyAny>) -> Result<Vec<f64>, Failure> {
    let converted;
    let obj = match obj.cast::<PyUntypedArray>() {
        Ok(_) => obj,
        Err(_) => {
            converted = as_array(name, obj)?;
            &converted
        }
    };
    let Ok(array) = obj.cast::<PyUntypedArray>() else {
        return Err(not_an_array(name, obj, None));
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

/// `numpy.asarray(obj)`, or a `not_an_array` failure saying why numpy could not read it.
fn as_array<'py>(name: &str, obj: &Bound<'py, PyAny>) -> Result<Bound<'py, PyAny>, Failure> {
    // A str or bytes object is one value to numpy (a 0-d array of text), never samples.
    if obj.is_instance_of::<PyString>() || obj.is_instance_of::<PyBytes>() {
        return Err(not_an_array(name, obj, None));
    }
    let py = obj.py();
    let array = py
        .import("numpy")
        .and_then(|np| np.call_method1("asarray", (obj,)))
        .map_err(|e| not_an_array(name, obj, Some(e.value(py).to_string())))?;
    // numpy makes a 0-d array of anything (None, a dict, a number): one value, not samples.
    match array.cast::<PyUntypedArray>() {
        Ok(a) if a.ndim() > 0 => Ok(array),
        _ => Err(not_an_array(name, obj, None)),
    }
}

/// `name` is not something numpy reads as an array of numbers.
fn not_an_array(name: &str, obj: &Bound<'_, PyAny>, why: Option<String>) -> Failure {
    let ty = obj
        .get_type()
        .name()
        .map_or_else(|_| "?".to_string(), |n| n.to_string());
    let why = why.map_or_else(String::new, |w| format!(" (numpy.asarray: {w})"));
    Failure::new(
        Class::Data,
        "not_an_array",
        format!(
            "{name} is a {ty}, which numpy does not read as an array of samples{why}: give a 1-D \
             sequence of numbers (a numpy array, a list, a pandas Series)"
        ),
    )
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
