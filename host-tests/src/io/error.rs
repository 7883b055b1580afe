//! What can go wrong while reading or writing CSV files.

use std::fmt;
use std::path::PathBuf;

use super::FileError;

/// Everything that can go wrong while reading or writing CSV files.
///
/// `Display` gives one line that starts with the file name (and the 1-based line number where it
/// applies), e.g. `data.csv line 17: column "y": "1.2.3" is not a number`.
#[derive(Debug)]
pub enum IoError {
    /// The file could not be opened, read, created or written (not found, permission denied,
    /// ...).
    File(FileError),
    /// The file is larger than [`MAX_RECORD_BYTES`](super::MAX_RECORD_BYTES), the most a
    /// whole-record reader holds in memory; nothing of it was kept.
    TooLarge(super::TooLarge),
    /// The file is not valid UTF-8 text.
    NotUtf8 {
        /// File that was being read.
        path: PathBuf,
        /// 1-based line of the first invalid byte.
        line: usize,
    },
    /// The file is empty or holds only whitespace and comment lines.
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
        /// 1-based line of the header.
        line: usize,
        /// The requested column name.
        column: String,
        /// The column names the header does have.
        available: Vec<String>,
    },
    /// A requested column name appears more than once in the header.
    DuplicateColumn {
        /// File that was being read.
        path: PathBuf,
        /// 1-based line of the header.
        line: usize,
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
    /// The CSV parser refused the text (e.g. a quoted field that never ends).
    Malformed {
        /// File that was being read.
        path: PathBuf,
        /// 1-based line where the parser stopped, when it knows.
        line: Option<usize>,
        /// The parser's message.
        reason: String,
    },
    /// The arguments of [`write_columns`](super::write_columns) are inconsistent (name count, column lengths, names
    /// that cannot be written).
    InvalidColumns {
        /// File that was being written.
        path: PathBuf,
        /// What is wrong.
        reason: String,
    },
}

impl fmt::Display for IoError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            IoError::File(e) => e.fmt(f),
            IoError::TooLarge(e) => write!(
                f,
                "{e} for a record read whole (parsing holds it in memory several times over): \
                 `hsid identify --stream` reads a CSV of any length row by row in bounded \
                 memory; otherwise shorten or decimate the record"
            ),
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
                line,
                column,
                available,
            } => {
                let list: Vec<String> = available.iter().map(|c| format!("\"{c}\"")).collect();
                write!(
                    f,
                    "{} line {line}: no column \"{column}\" (columns are {})",
                    path.display(),
                    list.join(", ")
                )
            }
            IoError::DuplicateColumn { path, line, column } => write!(
                f,
                "{} line {line}: column \"{column}\" appears more than once",
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
            IoError::Malformed {
                path,
                line: Some(line),
                reason,
            } => write!(f, "{} line {line}: malformed CSV: {reason}", path.display()),
            IoError::Malformed {
                path,
                line: None,
                reason,
            } => write!(f, "{}: malformed CSV: {reason}", path.display()),
            IoError::InvalidColumns { path, reason } => {
                write!(f, "{}: cannot write columns: {reason}", path.display())
            }
        }
    }
}

impl std::error::Error for IoError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            IoError::File(e) => Some(e),
            IoError::TooLarge(e) => Some(e),
            _ => None,
        }
    }
}

impl From<FileError> for IoError {
    fn from(e: FileError) -> Self {
        IoError::File(e)
    }
}
