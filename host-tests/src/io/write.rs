//! CSV columns out: the shortest text that reads back to the same numbers.

use std::io::Write;
use std::path::Path;

use super::{FileError, IoError};

/// Writes columns to a CSV file with a header row.
///
/// Values are written with the shortest text that parses back to the same `f64` (so
/// [`read_columns`](super::read_columns) returns exactly what was written); very small or large
/// magnitudes use exponent notation (`1e-300`). All columns must have the same length and the
/// values must be finite (NaN and infinities could not be read back). Names must be non-empty
/// and contain no double quote or line break; names with a comma are quoted.
pub fn write_columns<C: AsRef<[f64]>>(
    path: impl AsRef<Path>,
    names: &[&str],
    columns: &[C],
) -> Result<(), IoError> {
    let path = path.as_ref();
    let mut text = Vec::new();
    write_columns_to(path, &mut text, names, columns)?;
    super::write_atomic(path, text).map_err(|source| FileError::write(path, source).into())
}

/// Same as [`write_columns`] but into any writer; `source` is only used in error messages.
pub fn write_columns_to<W: Write, C: AsRef<[f64]>>(
    source: impl AsRef<Path>,
    mut writer: W,
    names: &[&str],
    columns: &[C],
) -> Result<(), IoError> {
    let path = source.as_ref();
    let invalid = |reason: String| IoError::InvalidColumns {
        path: path.to_path_buf(),
        reason,
    };
    if names.len() != columns.len() {
        return Err(invalid(format!(
            "{} names but {} columns",
            names.len(),
            columns.len()
        )));
    }
    if names.is_empty() {
        return Err(invalid("no columns".to_string()));
    }
    for name in names {
        if name.trim().is_empty() || name.contains(['"', '\n', '\r']) || *name != name.trim() {
            return Err(invalid(format!(
                "column name {name:?} cannot be written (empty, surrounding spaces, quote or line break)"
            )));
        }
    }
    for (i, name) in names.iter().enumerate() {
        if names[..i].contains(name) {
            return Err(invalid(format!("column name \"{name}\" appears twice")));
        }
    }
    let rows = columns[0].as_ref().len();
    for (name, col) in names.iter().zip(columns) {
        if col.as_ref().len() != rows {
            return Err(invalid(format!(
                "column \"{name}\" has {} values, column \"{}\" has {rows}",
                col.as_ref().len(),
                names[0]
            )));
        }
    }

    let mut out = String::with_capacity(rows * names.len() * 20 + 64);
    let header: Vec<String> = names
        .iter()
        .map(|n| {
            if n.contains(',') {
                format!("\"{n}\"")
            } else {
                n.to_string()
            }
        })
        .collect();
    out.push_str(&header.join(","));
    out.push('\n');
    for r in 0..rows {
        for (k, (name, col)) in names.iter().zip(columns).enumerate() {
            let v = col.as_ref()[r];
            if !v.is_finite() {
                return Err(IoError::NonFinite {
                    path: path.to_path_buf(),
                    line: r + 2,
                    column: name.to_string(),
                    value: v,
                });
            }
            if k > 0 {
                out.push(',');
            }
            out.push_str(&format_f64(v));
        }
        out.push('\n');
    }
    writer
        .write_all(out.as_bytes())
        .and_then(|()| writer.flush())
        .map_err(|source| FileError::write(path, source).into())
}

/// Shortest round-tripping text of a finite `f64`, with an exponent for extreme magnitudes
/// (the text [`write_columns`] writes; for writers that stream rows).
pub fn format_f64(v: f64) -> String {
    let a = v.abs();
    if a != 0.0 && !(1e-5..1e16).contains(&a) {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}
