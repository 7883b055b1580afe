//! `hsid.Model`: an identified model, held as the model file (format hsid-model/1) it is.

use std::ffi::CString;

use hsid::Direction;
use hsid_host::identify::HostModel;
use hsid_host::model::{FileModel, MemoryElement, Simulate, Syntax, for_input};
use hsid_host::model_file::ModelFile;
use numpy::{Complex64, PyArray1, PyArray2};
use pyo3::exceptions::{PyImportError, PyUserWarning};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat};

use crate::arrays::{inside, out, vector};
use crate::error::{Class, Failure};

/// An identified Hammerstein model: an input element with two borders (ascending and
/// descending paths, piecewise linear on their knots), then linear dynamics `x(t+1) = A x(t) +
/// B h(t)`, `y(t) = C x(t) + D h(t)`. It is the model file hsid-model/1 that `hsid identify
/// --json` writes: `to_json()` gives that file, `Model.from_json(text)` reads one.
#[pyclass(module = "hsid", name = "Model", frozen)]
pub struct Model {
    file: ModelFile,
    model: HostModel,
    /// The model as it simulates (the play or relay itself for a file with `"element"`).
    simulated: FileModel,
    /// What the identification chose and did, one line each (empty for a model read back).
    notes: Vec<String>,
}

impl Model {
    /// The model of a model file.
    pub fn new(file: ModelFile) -> Self {
        Self::with_notes(file, Vec::new())
    }

    /// The model of a model file, with what its identification said.
    pub fn with_notes(file: ModelFile, notes: Vec<String>) -> Self {
        let model = HostModel::from_json(&file);
        let simulated = FileModel::from_file(&file);
        Self {
            file,
            model,
            simulated,
            notes,
        }
    }

    /// The model file as compact JSON: what `==` compares and `hash` hashes.
    fn key(&self) -> Result<String, Failure> {
        serde_json::to_string(&self.file).map_err(to_data)
    }

    /// Whether the element has two paths (a gap); `None` (a solved checkpoint's two paths)
    /// counts as two.
    fn two_path(&self) -> bool {
        self.file.nonlinearity.is_none_or(|n| n.two_path())
    }

    /// The standard deviation of the mean gap: the file's (from the refinement's whole
    /// covariance of the borders, as `hsid identify` prints it), else, in a file written
    /// without it, from the borders' standard deviations taken as uncorrelated.
    fn mean_gap_std(&self) -> Option<f64> {
        let std = self.file.std.as_ref()?;
        if !self.two_path() {
            return None;
        }
        if let Some(s) = std.mean_gap {
            return Some(s);
        }
        let cov = self.model.border_covariance_of_std(std)?;
        self.model.mean_gap_std(&cov)
    }

    /// `A, B (n × 1), C (1 × n), D (1 × 1)` as numpy arrays, and `dt` (the sample time, or
    /// True: discrete with the sample time unknown).
    #[allow(clippy::type_complexity)]
    fn abcd<'py>(
        &self,
        py: Python<'py>,
    ) -> PyResult<(
        Bound<'py, PyArray2<f64>>,
        Bound<'py, PyArray2<f64>>,
        Bound<'py, PyArray2<f64>>,
        Bound<'py, PyArray2<f64>>,
        Bound<'py, PyAny>,
    )> {
        let f = &self.file;
        let col: Vec<Vec<f64>> = f.b.iter().map(|&v| vec![v]).collect();
        let a = if f.order == 0 {
            PyArray2::zeros(py, [0, 0], false)
        } else {
            PyArray2::from_vec2(py, &f.a)?
        };
        let b = if f.order == 0 {
            PyArray2::zeros(py, [0, 1], false)
        } else {
            PyArray2::from_vec2(py, &col)?
        };
        let c = if f.order == 0 {
            PyArray2::zeros(py, [1, 0], false)
        } else {
            PyArray2::from_vec2(py, std::slice::from_ref(&f.c))?
        };
        let d = PyArray2::from_vec2(py, &[vec![f.d]])?;
        let dt = match f.sample_time {
            Some(ts) => PyFloat::new(py, ts).into_any(),
            None => PyBool::new(py, true).to_owned().into_any(),
        };
        Ok((a, b, c, d, dt))
    }

    fn check_u(&self, name: &str, u: &[f64]) -> Result<(), Failure> {
        inside(name, u, self.model.u_min(), self.model.u_max())
    }
}

/// `"ascending"` or `"descending"`.
fn direction(d: &str) -> Result<Direction, Failure> {
    match d {
        "ascending" => Ok(Direction::Ascending),
        "descending" => Ok(Direction::Descending),
        _ => Err(Failure::new(
            Class::Settings,
            "direction",
            format!("direction {d:?}: give \"ascending\" or \"descending\""),
        )),
    }
}

/// Applies `f` to a float or to each value of a 1-D array (`name` in errors).
fn map<'py>(
    py: Python<'py>,
    name: &str,
    u: &Bound<'py, PyAny>,
    mut f: impl FnMut(&[f64]) -> Result<Vec<f64>, Failure>,
) -> PyResult<Bound<'py, PyAny>> {
    if u.is_instance_of::<PyFloat>() || u.extract::<i64>().is_ok() {
        let v: f64 = u.extract()?;
        let r = f(&[v])?;
        return Ok(PyFloat::new(py, r[0]).into_any());
    }
    let v = vector(name, u)?;
    Ok(out(py, f(&v)?).into_any())
}

/// A JSON value as a Python object (`None` for JSON null).
fn json_to_py<'py>(py: Python<'py>, text: &str) -> PyResult<Bound<'py, PyAny>> {
    py.import("json")?.call_method1("loads", (text,))
}

/// What `__reduce__` gives pickle: the class and the arguments that make the model again.
type Reduced<'py> = (Bound<'py, PyAny>, (String, Vec<String>));

/// An optional package a conversion needs, or an `ImportError` naming what to install.
fn needs<'py>(
    py: Python<'py>,
    module: &str,
    package: &str,
    what: &str,
) -> PyResult<Bound<'py, PyModule>> {
    py.import(module).map_err(|e| {
        PyImportError::new_err(format!(
            "{what} needs {package} (pip install {package}): {e}"
        ))
    })
}

#[pymethods]
impl Model {
    /// `Model(text)`: the model of a model file's JSON text, as `Model.from_json(text)`;
    /// `notes` are what its identification said (pickling keeps them).
    #[new]
    #[pyo3(signature = (text, notes=None))]
    fn py_new(text: &str, notes: Option<Vec<String>>) -> PyResult<Self> {
        let file = ModelFile::from_json_str("<string>", text).map_err(Failure::from)?;
        Ok(Self::with_notes(file, notes.unwrap_or_default()))
    }

    /// Pickling (and `copy.copy`, `copy.deepcopy`) through the model file's JSON text and the
    /// notes: `Model(text, notes)`.
    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<Reduced<'py>> {
        let m = slf.get();
        let text = m.file.to_json_string("<model>").map_err(Failure::from)?;
        Ok((slf.get_type().into_any(), (text, m.notes.clone())))
    }

    /// Equal when the model files are: every number, knot, setting, sample time and unit
    /// (not the notes). `Model.from_json(m.to_json()) == m`.
    fn __eq__(&self, other: &Bound<'_, PyAny>) -> PyResult<Py<PyAny>> {
        let py = other.py();
        match other.cast::<Model>() {
            Ok(o) => {
                let equal = self.key()? == o.get().key()?;
                Ok(PyBool::new(py, equal).to_owned().into_any().unbind())
            }
            Err(_) => Ok(py.NotImplemented()),
        }
    }

    /// The hash of the model file's contents, consistent with `==`.
    fn __hash__(&self) -> PyResult<u64> {
        use std::hash::{Hash, Hasher};
        let mut h = std::collections::hash_map::DefaultHasher::new();
        self.key()?.hash(&mut h);
        Ok(h.finish())
    }

    /// Reads a model file (format hsid-model/1) from its JSON text.
    #[staticmethod]
    fn from_json(text: &str) -> PyResult<Self> {
        let file = ModelFile::from_json_str("<string>", text).map_err(Failure::from)?;
        Ok(Self::new(file))
    }

    /// The model file (format hsid-model/1) as JSON text: what `hsid identify --json` writes.
    fn to_json(&self) -> PyResult<String> {
        Ok(self.file.to_json_string("<model>").map_err(Failure::from)?)
    }

    /// What the identification chose and did, one line each, as `hsid identify` prints
    /// them (segments, horizons, order, the refinement, the element's fit); empty for a model
    /// read from JSON.
    #[getter]
    fn notes(&self) -> Vec<String> {
        self.notes.clone()
    }

    /// Model order n (states of the linear part).
    #[getter]
    fn order(&self) -> usize {
        self.file.order
    }

    /// Poles of the linear part (eigenvalues of A), complex.
    #[getter]
    fn poles<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<Complex64>> {
        let p: Vec<Complex64> = self
            .model
            .poles()
            .into_iter()
            .map(|(re, im)| Complex64::new(re, im))
            .collect();
        PyArray1::from_vec(py, p)
    }

    /// State matrix A (order × order).
    #[getter(A)]
    fn a<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        Ok(PyArray2::from_vec2(py, &self.file.a)?)
    }

    /// Input vector B (order), 1-D; `to_dlti()` and `to_control()` give it as a column.
    #[getter(B)]
    fn b<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        out(py, self.file.b.clone())
    }

    /// Output vector C (order), 1-D; `to_dlti()` and `to_control()` give it as a row.
    #[getter(C)]
    fn c<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        out(py, self.file.c.clone())
    }

    /// Feedthrough D.
    #[getter(D)]
    fn d(&self) -> f64 {
        self.file.d
    }

    /// μ0 = H(u_min), the element's output at the lower end of the interval.
    #[getter]
    fn mu0(&self) -> f64 {
        self.file.mu0
    }

    /// Lower end of the input interval.
    #[getter]
    fn u_min(&self) -> f64 {
        self.file.u_min
    }

    /// Upper end of the input interval.
    #[getter]
    fn u_max(&self) -> f64 {
        self.file.u_max
    }

    /// Knots of the ascending border.
    #[getter]
    fn knots_asc<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        out(py, self.file.knots_asc.clone())
    }

    /// Knots of the descending border.
    #[getter]
    fn knots_desc<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        out(py, self.file.knots_desc.clone())
    }

    /// The input element: "backlash", "switch", "static", or None when not recorded.
    #[getter]
    fn nonlinearity(&self) -> Option<&'static str> {
        self.file.nonlinearity.map(|n| n.name())
    }

    /// Standard deviations of the refined model (poles, mu0, border_asc, border_desc, and
    /// gap: of `mean_gap`, None where it is not defined) as a dict, or None for a model that
    /// was not refined.
    #[getter]
    fn std<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let d = json_to_py(py, &serde_json::to_string(&self.file.std).map_err(to_data)?)?;
        if !d.is_none() {
            // The file's `mean_gap` is `gap` here, with the fallback of an older file.
            if d.contains("mean_gap")? {
                d.del_item("mean_gap")?;
            }
            d.set_item("gap", self.mean_gap_std())?;
        }
        Ok(d)
    }

    /// The mean gap of the borders (input units), as `hsid identify` reports it: the mean of
    /// the defined gaps (`gap_at`) after an ascent and after a descent at 5 equally spaced
    /// interior inputs of [u_min, u_max]; None for a static element or where no gap is
    /// defined. Its standard deviation is `std["gap"]`.
    #[getter]
    fn mean_gap(&self) -> Option<f64> {
        if self.two_path() {
            self.model.mean_gap()
        } else {
            None
        }
    }

    /// The linear part as `scipy.signal.dlti(A, B, C, D, dt=ts)`, B a column (n × 1) and C a
    /// row (1 × n); `dt=True` when the sample time is not known. Its input is the element's
    /// output `element(u)`; for an integrating model it is the stable part. Needs scipy.
    fn to_dlti<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let signal = needs(py, "scipy.signal", "scipy", "Model.to_dlti")?;
        let (a, b, c, d, dt) = self.abcd(py)?;
        let kwargs = PyDict::new(py);
        kwargs.set_item("dt", dt)?;
        signal.getattr("dlti")?.call((a, b, c, d), Some(&kwargs))
    }

    /// The linear part as a python-control `StateSpace(A, B, C, D, dt)`, `dt` the sample
    /// time (True when not known); as `to_dlti`. Needs the `control` package.
    fn to_control<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let control = needs(py, "control", "control", "Model.to_control")?;
        let (a, b, c, d, dt) = self.abcd(py)?;
        control.getattr("ss")?.call1((a, b, c, d, dt))
    }

    /// The element's output h(t) for the input `u` (a float or a 1-D array): the signal the
    /// linear part (`to_dlti`) is driven by when the model simulates `u` from rest at u_min —
    /// the ascending or descending border by each sample's direction, or the play's or relay's
    /// output. Outside [u_min, u_max] as `simulate` (a `UserWarning`, or `DataError` with
    /// `strict_interval=True`).
    #[pyo3(signature = (u, *, strict_interval = false))]
    fn element<'py>(
        &self,
        py: Python<'py>,
        u: &Bound<'py, PyAny>,
        strict_interval: bool,
    ) -> PyResult<Bound<'py, PyAny>> {
        let mut warning = None;
        let r = map(py, "u", u, |v| {
            if strict_interval {
                self.check_u("u", v)?;
            }
            let (model, outside) = for_input(&self.simulated, v);
            warning = outside.map(|o| o.note(Syntax::Python));
            Ok(model.model.element_output(v, model.u_start))
        })?;
        if let Some(w) = warning {
            let text = CString::new(w).unwrap_or_default();
            PyErr::warn(py, py.get_type::<PyUserWarning>().as_any(), &text, 1)?;
        }
        Ok(r)
    }

    /// Sample time in seconds, or None.
    #[getter]
    fn ts(&self) -> Option<f64> {
        self.file.sample_time
    }

    /// Units of the signals as {"input": ..., "output": ...}, or None.
    #[getter]
    fn units<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        json_to_py(
            py,
            &serde_json::to_string(&self.file.units).map_err(to_data)?,
        )
    }

    /// The border of `direction` ("ascending" or "descending") at `u` (a float or a 1-D
    /// array inside [u_min, u_max]).
    fn border<'py>(
        &self,
        py: Python<'py>,
        direction: &str,
        u: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let dir = self::direction(direction)?;
        map(py, "u", u, |v| {
            self.check_u("u", v)?;
            Ok(v.iter()
                .map(|&x| match dir {
                    Direction::Ascending => self.model.border_asc_at(x),
                    Direction::Descending => self.model.border_desc_at(x),
                })
                .collect())
        })
    }

    /// The play at `u` after the input arrived on path `direction`: how far the input must
    /// travel back before the element's output moves (the firmware's `Model::gap_at`). NaN
    /// where the other border never reaches the value.
    fn gap_at<'py>(
        &self,
        py: Python<'py>,
        direction: &str,
        u: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let dir = self::direction(direction)?;
        map(py, "u", u, |v| {
            self.check_u("u", v)?;
            Ok(v.iter()
                .map(|&x| self.model.gap_at(dir, x).unwrap_or(f64::NAN))
                .collect())
        })
    }

    /// The model's output for the input `u` (1-D float array), from rest at u_min. For an
    /// integrating model (`integrating` true) the plant's output: the stable part's increments
    /// summed from 0. Where `u` leaves [u_min, u_max] the borders continue linearly on their
    /// end segments' lines (both borders; a play or relay keeps its gap), with a
    /// `UserWarning` saying how many samples lie outside; `strict_interval=True` refuses such
    /// an input instead (`DataError` of kind `input_out_of_range`).
    #[pyo3(signature = (u, *, strict_interval = false))]
    fn simulate<'py>(
        &self,
        py: Python<'py>,
        u: &Bound<'py, PyAny>,
        strict_interval: bool,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let v = vector("u", u)?;
        if strict_interval {
            self.check_u("u", &v)?;
        }
        let (model, outside) = for_input(&self.simulated, &v);
        if let Some(o) = outside {
            let text = CString::new(o.note(Syntax::Python)).unwrap_or_default();
            PyErr::warn(py, py.get_type::<PyUserWarning>().as_any(), &text, 1)?;
        }
        Ok(out(py, model.simulate(&v)))
    }

    /// True when the model is the stable part of an integrating plant (identified on the
    /// output's increments with one pole at z = 1; the model file's `"integrating"`).
    #[getter]
    fn integrating(&self) -> bool {
        self.file.integrating
    }

    fn __repr__(&self) -> String {
        let kind = self.file.nonlinearity.map_or("two-path", |n| n.name());
        // An element model (play or relay) is fitted by simulation error, not refined by the
        // prediction-error method: say which, rather than `refined=False`.
        let how = match self.file.element {
            Some(MemoryElement::Play) => "element='play', fit='simulation-error'".to_string(),
            Some(MemoryElement::Relay) => "element='relay', fit='simulation-error'".to_string(),
            None if self.file.std.is_some() => "refined=True".to_string(),
            None => "refined=False".to_string(),
        };
        format!(
            "Model(order={}, nonlinearity='{kind}', u=({:?}, {:?}), segments=({}, {}), mu0={:.6}, {how})",
            self.file.order,
            self.file.u_min,
            self.file.u_max,
            self.file.knots_asc.len().saturating_sub(1),
            self.file.knots_desc.len().saturating_sub(1),
            self.file.mu0,
        )
    }
}

fn to_data(e: serde_json::Error) -> Failure {
    Failure::new(Class::Data, "json", e.to_string())
}
