//! The input record of a simulation: the input column, and the time column when the file has
//! one (then it must increase strictly), with the line of every sample.

use std::path::{Path, PathBuf};

use super::error::SimulateError;
use crate::io::{CsvOptions, IoError, parse_table, read_source};
use crate::units::time::strictly_increasing;

/// An input record.
#[derive(Clone, Debug, PartialEq)]
pub struct InputRecord {
    /// The name of the file in messages (`<stdin>` for standard input).
    pub source: PathBuf,
    /// The input `u`.
    pub u: Vec<f64>,
    /// The time column, when the file has one.
    pub t: Option<Vec<f64>>,
    /// The 1-based line of each sample.
    pub lines: Vec<usize>,
}

/// Reads the column `input` and, if the header has it, the column `time` of a CSV file (`-`:
/// standard input).
pub fn read_input(
    path: impl AsRef<Path>,
    input: &str,
    time: &str,
    csv: &CsvOptions,
) -> Result<InputRecord, SimulateError> {
    let (source, text) = read_source(path)?;
    let (table, with_time) = match parse_table(&source, &text, &[input, time], csv) {
        Ok(t) => (t, true),
        Err(IoError::MissingColumn { column, .. }) if column == time.trim() => {
            (parse_table(&source, &text, &[input], csv)?, false)
        }
        Err(e) => return Err(e.into()),
    };
    let mut columns = table.columns.into_iter();
    let u = columns.next().unwrap_or_default();
    let t = columns.next().filter(|_| with_time);
    if let Some(t) = &t {
        strictly_increasing(&source, t, &table.lines)?;
    }
    Ok(InputRecord {
        source,
        u,
        t,
        lines: table.lines,
    })
}
