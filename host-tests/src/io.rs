//! CSV columns in and out, and the JSON file of an identified model.
//!
//! The CSV reader is deliberately strict: every problem is reported as an [`IoError`] that names
//! the file, the 1-based line and, where it applies, the column; nothing is silently skipped.
//! The only things tolerated are the harmless quirks of real measurement files:
//!
//! * header names and cells are trimmed of surrounding spaces and double quotes
//!   (`"uEst", "yEst"` works);
//! * trailing empty fields (`3.2567,0.97619,5.205,4.9728,4,`) and trailing empty header names;
//! * a column that is not requested may be empty or hold text (the `Ts` column of the cascaded
//!   tanks benchmark only has a value on its first row);
//! * blank lines at the very end of the file, Windows line endings and a UTF-8 byte order mark.
//!
//! A blank line *between* data rows is an error, because it usually means two files were
//! concatenated or a row was lost.

use std::fmt;
use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

/// Everything that can go wrong while reading or writing CSV and model JSON files.
///
/// `Display` gives one line that starts with the file name (and the 1-based line number where it
/// applies), e.g. `data.csv line 17: column "y": "1.2.3" is not a number`.
#[derive(Debug)]
pub enum IoError {
    /// The file could not be opened or read (not found, permission denied, ...).
    Open {
        /// File that was being read.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
    /// The file could not be created or written.
    Write {
        /// File that was being written.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
    /// The file is not valid UTF-8 text.
    NotUtf8 {
        /// File that was being read.
        path: PathBuf,
        /// 1-based line of the first invalid byte.
        line: usize,
    },
    /// The file is empty or holds only whitespace.
    Empty {
        /// File that was being read.
        path: PathBuf,
    },
    /// The file has a header row but no data rows.
    NoData {
        /// File that was being read.
        path: PathBuf,
    },
    /// A blank line where a header or data row was expected (not at the end of the file).
    BlankLine {
        /// File that was being read.
        path: PathBuf,
        /// 1-based line number.
        line: usize,
    },
    /// A requested column is not in the header.
    MissingColumn {
        /// File that was being read.
        path: PathBuf,
        /// The requested column name.
        column: String,
        /// The column names the header does have.
        available: Vec<String>,
    },
    /// A requested column name appears more than once in the header.
    DuplicateColumn {
        /// File that was being read.
        path: PathBuf,
        /// The ambiguous column name.
        column: String,
    },
    /// A data row has fewer fields than the header has columns.
    TooFewFields {
        /// File that was being read.
        path: PathBuf,
        /// 1-based line number.
        line: usize,
        /// Number of columns in the header.
        expected: usize,
        /// Number of fields in the row.
        found: usize,
    },
    /// A data row has non-empty fields beyond the last header column.
    TooManyFields {
        /// File that was being read.
        path: PathBuf,
        /// 1-based line number.
        line: usize,
        /// Number of columns in the header.
        expected: usize,
        /// Number of fields in the row (trailing empty fields not counted).
        found: usize,
    },
    /// A requested cell is empty.
    EmptyCell {
        /// File that was being read.
        path: PathBuf,
        /// 1-based line number.
        line: usize,
        /// Column name.
        column: String,
    },
    /// A requested cell is not a number.
    BadNumber {
        /// File that was being read.
        path: PathBuf,
        /// 1-based line number.
        line: usize,
        /// Column name.
        column: String,
        /// The offending text (trimmed).
        text: String,
    },
    /// A requested cell (or a value to be written) is NaN or infinite.
    NonFinite {
        /// File that was being read or written.
        path: PathBuf,
        /// 1-based line number.
        line: usize,
        /// Column name.
        column: String,
        /// The value.
        value: f64,
    },
    /// The arguments of [`write_columns`] are inconsistent (name count, column lengths, names
    /// that cannot be written).
    InvalidColumns {
        /// File that was being written.
        path: PathBuf,
        /// What is wrong.
        reason: String,
    },
    /// The JSON text is malformed or does not have the fields and types of [`ModelJson`].
    Json {
        /// File that was being read or written.
        path: PathBuf,
        /// Where in the document the problem is (e.g. `A[1][0]`), `.` for the top level.
        location: String,
        /// The underlying error.
        source: serde_json::Error,
    },
    /// The model is well-formed JSON but inconsistent (wrong matrix shape, lengths that differ,
    /// non-finite numbers).
    InvalidModel {
        /// File that was being read or written.
        path: PathBuf,
        /// The JSON key of the offending field, e.g. `A` or `border_desc`.
        field: &'static str,
        /// What is wrong.
        reason: String,
    },
}

impl fmt::Display for IoError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            IoError::Open { path, source } => {
                write!(f, "{}: cannot read file: {source}", path.display())
            }
            IoError::Write { path, source } => {
                write!(f, "{}: cannot write file: {source}", path.display())
            }
            IoError::NotUtf8 { path, line } => {
                write!(f, "{} line {line}: not valid UTF-8 text", path.display())
            }
            IoError::Empty { path } => write!(f, "{}: file is empty", path.display()),
            IoError::NoData { path } => {
                write!(
                    f,
                    "{}: file has a header row but no data rows",
                    path.display()
                )
            }
            IoError::BlankLine { path, line } => {
                write!(f, "{} line {line}: unexpected blank line", path.display())
            }
            IoError::MissingColumn {
                path,
                column,
                available,
            } => {
                let list: Vec<String> = available.iter().map(|c| format!("\"{c}\"")).collect();
                write!(
                    f,
                    "{} line 1: no column \"{column}\" (columns are {})",
                    path.display(),
                    list.join(", ")
                )
            }
            IoError::DuplicateColumn { path, column } => write!(
                f,
                "{} line 1: column \"{column}\" appears more than once",
                path.display()
            ),
            IoError::TooFewFields {
                path,
                line,
                expected,
                found,
            } => write!(
                f,
                "{} line {line}: {found} fields, expected {expected}",
                path.display()
            ),
            IoError::TooManyFields {
                path,
                line,
                expected,
                found,
            } => write!(
                f,
                "{} line {line}: {found} non-empty fields, but the header has only {expected} columns",
                path.display()
            ),
            IoError::EmptyCell { path, line, column } => {
                write!(
                    f,
                    "{} line {line}: column \"{column}\" is empty",
                    path.display()
                )
            }
            IoError::BadNumber {
                path,
                line,
                column,
                text,
            } => write!(
                f,
                "{} line {line}: column \"{column}\": \"{text}\" is not a number",
                path.display()
            ),
            IoError::NonFinite {
                path,
                line,
                column,
                value,
            } => write!(
                f,
                "{} line {line}: column \"{column}\": {value} is not a finite number",
                path.display()
            ),
            IoError::InvalidColumns { path, reason } => {
                write!(f, "{}: cannot write columns: {reason}", path.display())
            }
            IoError::Json {
                path,
                location,
                source,
            } => {
                if location == "." || location == "?" {
                    write!(f, "{}: {source}", path.display())
                } else {
                    write!(f, "{}: field {location}: {source}", path.display())
                }
            }
            IoError::InvalidModel {
                path,
                field,
                reason,
            } => write!(f, "{}: field \"{field}\": {reason}", path.display()),
        }
    }
}

impl std::error::Error for IoError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            IoError::Open { source, .. } | IoError::Write { source, .. } => Some(source),
            IoError::Json { source, .. } => Some(source),
            _ => None,
        }
    }
}

// ---------------------------------------------------------------------------------------------
// CSV reading
// ---------------------------------------------------------------------------------------------

/// Reads the named columns of a CSV file with a header row.
///
/// Returns one `Vec<f64>` per requested name, in the order of `names`, each with one value per
/// data row. Column names are case-sensitive and compared after trimming spaces and double
/// quotes. See the [module documentation](self) for what is tolerated; everything else is an
/// [`IoError`] naming the 1-based line (the header is line 1).
pub fn read_columns(path: impl AsRef<Path>, names: &[&str]) -> Result<Vec<Vec<f64>>, IoError> {
    let path = path.as_ref();
    let bytes = fs::read(path).map_err(|source| IoError::Open {
        path: path.to_path_buf(),
        source,
    })?;
    let text = match String::from_utf8(bytes) {
        Ok(t) => t,
        Err(e) => {
            let valid = e.utf8_error().valid_up_to();
            let line = 1 + e.as_bytes()[..valid]
                .iter()
                .filter(|&&b| b == b'\n')
                .count();
            return Err(IoError::NotUtf8 {
                path: path.to_path_buf(),
                line,
            });
        }
    };
    parse_columns(path, &text, names)
}

/// Parses CSV text that is already in memory; `source` is only used in error messages.
///
/// Same rules and errors as [`read_columns`].
pub fn parse_columns(
    source: impl AsRef<Path>,
    text: &str,
    names: &[&str],
) -> Result<Vec<Vec<f64>>, IoError> {
    let path = source.as_ref();
    let err_path = || path.to_path_buf();
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);

    // Physical lines with their 1-based numbers; blank lines at the end are dropped.
    let mut lines: Vec<(usize, &str)> = text
        .split('\n')
        .map(|l| l.strip_suffix('\r').unwrap_or(l))
        .enumerate()
        .map(|(i, l)| (i + 1, l))
        .collect();
    while lines.last().is_some_and(|(_, l)| l.trim().is_empty()) {
        lines.pop();
    }
    let Some(&(header_line, header_text)) = lines.first() else {
        return Err(IoError::Empty { path: err_path() });
    };
    if header_text.trim().is_empty() {
        return Err(IoError::BlankLine {
            path: err_path(),
            line: header_line,
        });
    }

    let mut header = split_fields(header_text);
    while header.last().is_some_and(|h| h.is_empty()) {
        header.pop();
    }
    let header_len = header.len();

    // Resolve the requested columns.
    let mut indices = Vec::with_capacity(names.len());
    for &name in names {
        let wanted = clean(name);
        let mut hits = header.iter().enumerate().filter(|(_, h)| **h == wanted);
        match (hits.next(), hits.next()) {
            (Some((i, _)), None) => indices.push(i),
            (Some(_), Some(_)) => {
                return Err(IoError::DuplicateColumn {
                    path: err_path(),
                    column: wanted.to_string(),
                });
            }
            (None, _) => {
                return Err(IoError::MissingColumn {
                    path: err_path(),
                    column: wanted.to_string(),
                    available: header
                        .iter()
                        .filter(|h| !h.is_empty())
                        .map(|h| h.to_string())
                        .collect(),
                });
            }
        }
    }

    let rows = &lines[1..];
    if rows.is_empty() {
        return Err(IoError::NoData { path: err_path() });
    }
    let mut columns: Vec<Vec<f64>> = vec![Vec::with_capacity(rows.len()); names.len()];
    for &(line, row_text) in rows {
        if row_text.trim().is_empty() {
            return Err(IoError::BlankLine {
                path: err_path(),
                line,
            });
        }
        let fields = split_fields(row_text);
        if fields.len() < header_len {
            return Err(IoError::TooFewFields {
                path: err_path(),
                line,
                expected: header_len,
                found: fields.len(),
            });
        }
        let non_empty = fields
            .iter()
            .rposition(|f| !f.is_empty())
            .map_or(0, |p| p + 1);
        if non_empty > header_len {
            return Err(IoError::TooManyFields {
                path: err_path(),
                line,
                expected: header_len,
                found: non_empty,
            });
        }
        for (k, &col) in indices.iter().enumerate() {
            let cell = fields[col];
            let column = || header[col].to_string();
            if cell.is_empty() {
                return Err(IoError::EmptyCell {
                    path: err_path(),
                    line,
                    column: column(),
                });
            }
            let value: f64 = cell.parse().map_err(|_| IoError::BadNumber {
                path: err_path(),
                line,
                column: column(),
                text: cell.to_string(),
            })?;
            if !value.is_finite() {
                return Err(IoError::NonFinite {
                    path: err_path(),
                    line,
                    column: column(),
                    value,
                });
            }
            columns[k].push(value);
        }
    }
    Ok(columns)
}

/// Trims surrounding whitespace and double quotes.
fn clean(s: &str) -> &str {
    s.trim().trim_matches('"').trim()
}

/// Splits one CSV line on commas that are not inside double quotes, cleaning each field.
fn split_fields(line: &str) -> Vec<&str> {
    let mut fields = Vec::new();
    let mut in_quotes = false;
    let mut start = 0;
    for (i, c) in line.char_indices() {
        match c {
            '"' => in_quotes = !in_quotes,
            ',' if !in_quotes => {
                fields.push(clean(&line[start..i]));
                start = i + 1;
            }
            _ => {}
        }
    }
    fields.push(clean(&line[start..]));
    fields
}

// ---------------------------------------------------------------------------------------------
// CSV writing
// ---------------------------------------------------------------------------------------------

/// Writes columns to a CSV file with a header row.
///
/// Values are written with the shortest text that parses back to the same `f64` (so
/// [`read_columns`] returns exactly what was written); very small or large magnitudes use
/// exponent notation (`1e-300`). All columns must have the same length and the values must be
/// finite (NaN and infinities could not be read back). Names must be non-empty and contain no
/// double quote or line break; names with a comma are quoted.
pub fn write_columns<C: AsRef<[f64]>>(
    path: impl AsRef<Path>,
    names: &[&str],
    columns: &[C],
) -> Result<(), IoError> {
    let path = path.as_ref();
    let mut text = Vec::new();
    write_columns_to(path, &mut text, names, columns)?;
    fs::write(path, text).map_err(|source| IoError::Write {
        path: path.to_path_buf(),
        source,
    })
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
        .map_err(|source| IoError::Write {
            path: path.to_path_buf(),
            source,
        })
}

/// Shortest round-tripping text of a finite `f64`, with an exponent for extreme magnitudes.
fn format_f64(v: f64) -> String {
    let a = v.abs();
    if a != 0.0 && !(1e-5..1e16).contains(&a) {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}

// ---------------------------------------------------------------------------------------------
// Model JSON
// ---------------------------------------------------------------------------------------------

/// An identified model as stored in JSON: the state-space matrices of the linear part, its
/// poles, the piecewise-linear borders of the nonlinearity and the identification settings.
///
/// The JSON keys are exactly the field names below except for the matrices, which are `A`, `B`,
/// `C` and `D`. Unknown keys are rejected; a missing `nonlinearity` reads as `None`.
/// [`save_json`] and [`load_json`] check the shapes with [`ModelJson::validate`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ModelJson {
    /// Model order n.
    pub order: usize,
    /// State matrix, n rows of n values.
    #[serde(rename = "A")]
    pub a: Vec<Vec<f64>>,
    /// Input vector, n values.
    #[serde(rename = "B")]
    pub b: Vec<f64>,
    /// Output vector, n values.
    #[serde(rename = "C")]
    pub c: Vec<f64>,
    /// Direct feed-through.
    #[serde(rename = "D")]
    pub d: f64,
    /// Eigenvalues of A as `[re, im]`, n of them.
    pub poles: Vec<[f64; 2]>,
    /// Offset μ₀ of the nonlinearity.
    pub mu0: f64,
    /// Knots of the ascending border.
    pub knots_asc: Vec<f64>,
    /// Knots of the descending border.
    pub knots_desc: Vec<f64>,
    /// Values of the ascending border at `knots_asc`.
    pub border_asc: Vec<f64>,
    /// Values of the descending border at `knots_desc`.
    pub border_desc: Vec<f64>,
    /// Singular values used for the order selection.
    pub singular_values: Vec<f64>,
    /// Lower end of the excitation range.
    pub u_min: f64,
    /// Upper end of the excitation range.
    pub u_max: f64,
    /// Kind of nonlinearity (e.g. `"switch"`, `"backlash"`), if known.
    pub nonlinearity: Option<String>,
    /// Future horizon f of the Hankel matrices.
    pub f: usize,
    /// Past horizon p of the Hankel matrices.
    pub p: usize,
    /// Number of samples used for the identification.
    pub samples: usize,
}

impl ModelJson {
    /// Checks shapes and values: `A` is order×order, `B`, `C` and `poles` have `order` entries,
    /// each knot vector has as many entries as its border, every number is finite and
    /// `u_min <= u_max`. `source` is only used in the error.
    pub fn validate(&self, source: impl AsRef<Path>) -> Result<(), IoError> {
        let path = source.as_ref();
        let bad = |field: &'static str, reason: String| IoError::InvalidModel {
            path: path.to_path_buf(),
            field,
            reason,
        };
        let n = self.order;
        if self.a.len() != n {
            return Err(bad(
                "A",
                format!("has {} rows, expected order = {n}", self.a.len()),
            ));
        }
        for (i, row) in self.a.iter().enumerate() {
            if row.len() != n {
                return Err(bad(
                    "A",
                    format!("row {i} has {} values, expected order = {n}", row.len()),
                ));
            }
        }
        for (field, len) in [
            ("B", self.b.len()),
            ("C", self.c.len()),
            ("poles", self.poles.len()),
        ] {
            if len != n {
                return Err(bad(
                    field,
                    format!("has {len} entries, expected order = {n}"),
                ));
            }
        }
        for (kf, bf, k, b) in [
            ("knots_asc", "border_asc", &self.knots_asc, &self.border_asc),
            (
                "knots_desc",
                "border_desc",
                &self.knots_desc,
                &self.border_desc,
            ),
        ] {
            if k.len() != b.len() {
                return Err(bad(
                    bf,
                    format!("has {} values but {kf} has {}", b.len(), k.len()),
                ));
            }
        }
        let finite = |field: &'static str, values: &mut dyn Iterator<Item = f64>| match values
            .enumerate()
            .find(|(_, v)| !v.is_finite())
        {
            Some((i, v)) => Err(bad(field, format!("entry {i} is {v}, not a finite number"))),
            None => Ok(()),
        };
        finite("A", &mut self.a.iter().flatten().copied())?;
        finite("B", &mut self.b.iter().copied())?;
        finite("C", &mut self.c.iter().copied())?;
        finite("D", &mut std::iter::once(self.d))?;
        finite("poles", &mut self.poles.iter().flatten().copied())?;
        finite("mu0", &mut std::iter::once(self.mu0))?;
        finite("knots_asc", &mut self.knots_asc.iter().copied())?;
        finite("knots_desc", &mut self.knots_desc.iter().copied())?;
        finite("border_asc", &mut self.border_asc.iter().copied())?;
        finite("border_desc", &mut self.border_desc.iter().copied())?;
        finite("singular_values", &mut self.singular_values.iter().copied())?;
        finite("u_min", &mut std::iter::once(self.u_min))?;
        finite("u_max", &mut std::iter::once(self.u_max))?;
        if self.u_min >= self.u_max {
            return Err(bad(
                "u_max",
                format!("{} is not above u_min = {}", self.u_max, self.u_min),
            ));
        }
        for (field, k) in [
            ("knots_asc", &self.knots_asc),
            ("knots_desc", &self.knots_desc),
        ] {
            if k.len() < 2 {
                return Err(bad(
                    field,
                    format!(
                        "has {} knots: at least two (u_min and u_max) are needed",
                        k.len()
                    ),
                ));
            }
            if let Some(i) = k.windows(2).position(|w| w[1] <= w[0]) {
                return Err(bad(
                    field,
                    format!(
                        "knot {} is not above knot {i}: knots must increase strictly",
                        i + 1
                    ),
                ));
            }
            if k[0] != self.u_min || k[k.len() - 1] != self.u_max {
                return Err(bad(
                    field,
                    format!(
                        "runs from {} to {}, but the interval is [u_min, u_max] = [{}, {}]",
                        k[0],
                        k[k.len() - 1],
                        self.u_min,
                        self.u_max
                    ),
                ));
            }
        }
        Ok(())
    }

    /// Serialises to pretty-printed JSON after [`validate`](Self::validate).
    pub fn to_json_string(&self, source: impl AsRef<Path>) -> Result<String, IoError> {
        let path = source.as_ref();
        self.validate(path)?;
        serde_json::to_string_pretty(self).map_err(|source| IoError::Json {
            path: path.to_path_buf(),
            location: ".".to_string(),
            source,
        })
    }

    /// Parses JSON text and [`validate`](Self::validate)s it; `source` is only used in errors.
    ///
    /// A type error inside a field names that field (e.g. `field A[1][0]: invalid type ...`); a
    /// missing field is reported as `missing field `A``.
    pub fn from_json_str(source: impl AsRef<Path>, text: &str) -> Result<Self, IoError> {
        let path = source.as_ref();
        let mut de = serde_json::Deserializer::from_str(text);
        let model: ModelJson = serde_path_to_error::deserialize(&mut de).map_err(|e| {
            let location = e.path().to_string();
            IoError::Json {
                path: path.to_path_buf(),
                location,
                source: e.into_inner(),
            }
        })?;
        de.end().map_err(|source| IoError::Json {
            path: path.to_path_buf(),
            location: ".".to_string(),
            source,
        })?;
        model.validate(path)?;
        Ok(model)
    }
}

/// Validates `model` and writes it as pretty-printed JSON to `path`.
pub fn save_json(path: impl AsRef<Path>, model: &ModelJson) -> Result<(), IoError> {
    let path = path.as_ref();
    let mut text = model.to_json_string(path)?;
    text.push('\n');
    fs::write(path, text).map_err(|source| IoError::Write {
        path: path.to_path_buf(),
        source,
    })
}

/// Reads a model JSON file and validates it (see [`ModelJson::validate`]).
pub fn load_json(path: impl AsRef<Path>) -> Result<ModelJson, IoError> {
    let path = path.as_ref();
    let text = fs::read_to_string(path).map_err(|source| IoError::Open {
        path: path.to_path_buf(),
        source,
    })?;
    ModelJson::from_json_str(path, &text)
}
