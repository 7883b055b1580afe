//! The Python package of hsid (`import hsid`): identification of actuators with backlash or
//! switch input nonlinearities from numpy arrays, a face of the host library `hsid-host`.

mod arrays;
mod checkpoint;
mod csv;
mod diagnose;
mod error;
mod fleet;
mod identify;
mod interrupt;
mod model;
mod regressor;
mod settings;
mod simulate;

use pyo3::prelude::*;

/// The extension module `hsid._hsid`; the package `hsid` re-exports it.
#[pymodule]
fn _hsid(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add_class::<model::Model>()?;
    m.add_function(wrap_pyfunction!(identify::identify, m)?)?;
    m.add_function(wrap_pyfunction!(simulate::excite, m)?)?;
    m.add_function(wrap_pyfunction!(simulate::simulate_plant, m)?)?;
    m.add_function(wrap_pyfunction!(regressor::regressor, m)?)?;
    m.add_function(wrap_pyfunction!(checkpoint::solve_checkpoint, m)?)?;
    m.add_function(wrap_pyfunction!(diagnose::diagnose, m)?)?;
    m.add_function(wrap_pyfunction!(fleet::solve_many, m)?)?;
    m.add_function(wrap_pyfunction!(csv::read_csv_columns, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("HsidError", py.get_type::<error::HsidError>())?;
    m.add("DataError", py.get_type::<error::DataError>())?;
    m.add("SettingsError", py.get_type::<error::SettingsError>())?;
    m.add(
        "IdentificationError",
        py.get_type::<error::IdentificationError>(),
    )?;
    Ok(())
}
