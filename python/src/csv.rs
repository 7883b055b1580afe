//! `hsid.read_csv`: a record of hsid's CSV files (what `hsid excite` and `hsid simulate`
//! write) read as the command line reads it: the host library's CSV reader, the sample time
//! of the `# ts = … s` comment and of the time column, the units of the `# input unit` and
//! `# output unit` comments.

use hsid_host::io::{CsvOptions, Delimiter, IoError, parse_table, read_source};
use hsid_host::units::{
    Origin, TimeError, UnitsError, resolve_ts, ts_from_column, ts_from_comments,
    units_from_comments,
};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::arrays::out;
use crate::error::{Class, Failure};

fn io_failure(e: IoError) -> Failure {
    let kind = match &e {
        IoError::File(_) => "csv_file",
        IoError::MissingColumn { .. } => "missing_column",
        _ => "csv",
    };
    Failure::new(Class::Data, kind, e.to_string())
}

fn time_failure(e: TimeError) -> Failure {
    let kind = match &e {
        TimeError::NotIncreasing { .. } => "time_not_increasing",
        TimeError::NotUniform { .. } => "time_not_uniform",
        TimeError::Disagree { .. } => "sample_time",
        _ => "time_column",
    };
    Failure::new(Class::Data, kind, e.to_string())
}

fn units_failure(e: UnitsError) -> Failure {
    Failure::new(Class::Data, "units", e.to_string())
}

/// The delimiter called `name` (`","`, `";"` or `"\t"`), `None` to sniff it.
fn delimiter(name: Option<&str>) -> Result<Option<Delimiter>, Failure> {
    match name {
        None => Ok(None),
        Some(",") => Ok(Some(Delimiter::Comma)),
        Some(";") => Ok(Some(Delimiter::Semicolon)),
        Some("\t") => Ok(Some(Delimiter::Tab)),
        Some(d) => Err(Failure::new(
            Class::Settings,
            "delimiter",
            format!(
                "delimiter={d:?}: give \",\", \";\", \"\\t\" or None (sniffed from the header)"
            ),
        )),
    }
}

/// Reads the record at `path` as `hsid identify --data` reads it: the columns `u` and `y`
/// (`y=None`: the input alone; the default `"y"` is read when the file has it, as in what
/// `hsid excite` writes, which has none), the sample time of the `# ts = … s` comment and of
/// the time column `time` (default `"t"`, used when present; a named one must be there),
/// checked uniform and agreeing, and the units of the `# input unit` / `# output unit`
/// comments. Returns a dict `{"u", "y", "ts", "units", "t"}` (`y`, `ts`, `units` and `t`
/// None when absent); `hsid.read_csv` wraps it in a `CsvRecord`.
#[pyfunction]
#[pyo3(signature = (path, *, u="u", y=Some("y"), time=None, delimiter=None))]
pub fn read_csv_columns<'py>(
    py: Python<'py>,
    path: std::path::PathBuf,
    u: &str,
    y: Option<&str>,
    time: Option<&str>,
    delimiter: Option<&str>,
) -> PyResult<Bound<'py, PyDict>> {
    let options = CsvOptions {
        delimiter: self::delimiter(delimiter)?,
        ..CsvOptions::default()
    };
    let y_named = y.is_some_and(|n| n != "y");
    let (time, time_named) = time.map_or(("t", false), |t| (t, true));
    let (source, text) = read_source(&path).map_err(io_failure)?;
    let mut stated: Vec<(Origin, f64)> = ts_from_comments(&source, &text)
        .map_err(time_failure)?
        .map(|v| (Origin::Comment(source.clone()), v))
        .into_iter()
        .collect();
    let units = units_from_comments(&source, &text).map_err(units_failure)?;
    // The columns wanted, the optional ones (the default y, the default time column) left
    // out one by one when the file does not have them.
    let mut want_y = y;
    let mut want_t = true;
    let table = loop {
        let names: Vec<&str> = std::iter::once(u)
            .chain(want_y)
            .chain(want_t.then_some(time))
            .collect();
        match parse_table(&source, &text, &names, &options) {
            Err(IoError::MissingColumn { column, .. })
                if want_t && !time_named && column == time.trim() =>
            {
                want_t = false;
            }
            Err(IoError::MissingColumn { column, .. })
                if want_y.is_some() && !y_named && Some(column.as_str()) == want_y =>
            {
                want_y = None;
            }
            r => break r.map_err(io_failure)?,
        }
    };
    let mut columns = table.columns.into_iter();
    let u_col = columns.next().unwrap_or_default();
    let y_col = want_y.and_then(|_| columns.next());
    let t_col = if want_t { columns.next() } else { None };
    if let Some(t) = &t_col {
        let ts = ts_from_column(source.clone(), t, &table.lines).map_err(time_failure)?;
        stated.push((Origin::TimeColumn(source.clone()), ts));
    }
    let ts = resolve_ts(&stated).map_err(time_failure)?;
    let d = PyDict::new(py);
    d.set_item("u", out(py, u_col))?;
    d.set_item("y", y_col.map(|c| out(py, c)))?;
    d.set_item("t", t_col.map(|c| out(py, c)))?;
    d.set_item("ts", ts)?;
    match units {
        Some(un) => {
            let ud = PyDict::new(py);
            ud.set_item("input", un.input)?;
            ud.set_item("output", un.output)?;
            d.set_item("units", ud)?;
        }
        None => d.set_item("units", py.None())?,
    }
    Ok(d)
}
