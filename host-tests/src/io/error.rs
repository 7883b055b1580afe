//! What can go wrong while reading or writing CSV files.

use std::path::PathBuf;

use super::FileError;

/// Everything that can go wrong while reading or writing CSV files.
///
/// `Display` gives one line that starts with the file name (and the 1-based line number where it
/// applies), e.g. `data.csv line 17: column "y": "1.2.3" is not a number`.
#[derive(Debug, thiserror::Error)]
pub enum IoError {
    /// The file could not be opened, read, created or written (not found, permission denied,
    /// ...).
    #[error("{0}")]
    File(#[from] FileError),
    /// The file is larger than [`MAX_RECORD_BYTES`](super::MAX_RECORD_BYTES), the most a
    /// whole-record reader holds in memory; nothing of it was kept.
    #[error(
        "{0} for a record read whole (parsing holds it in memory several times over): \
         `hsid identify --stream` reads a CSV of any length row by row in bounded \
         memory; otherwise shorten or decimate the record"
    )]
    TooLarge(#[source] super::TooLarge),
    /// The file is not valid UTF-8 text.
    #[error("{path} line {line}: not valid UTF-8 text")]
    NotUtf8 {
        /// File that was being read.
        path: PathBuf,
        /// 1-based line of the first invalid byte.
        line: usize,
    },
    /// The file is empty or holds only whitespace and comment lines.
    #[error("{path}: file is empty")]
    Empty {
        /// File that was being read.
        path: PathBuf,
    },
    /// The file has a header row but no data rows.
    #[error("{path}: file has a header row but no data rows")]
    NoData {
        /// File that was being read.
        path: PathBuf,
    },
    /// A blank line where a header or data row was expected (not at the end of the file).
    #[error("{path} line {line}: unexpected blank line")]
    BlankLine {
        /// File that was being read.
        path: PathBuf,
        /// 1-based line number.
        line: usize,
    },
    /// A requested column is not in the header.
    #[error(
        "{path} line {line}: no column \"{column}\" (columns are {})",
        quoted(.available)
    )]
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
    /// The header has more columns than [`MAX_COLUMNS`](super::MAX_COLUMNS).
    #[error(
        "{path} line {line}: the header has {columns} columns, more than the {limit} read: \
         give a file of the columns needed (e.g. cut -d, -f …)"
    )]
    TooManyColumns {
        /// File that was being read.
        path: PathBuf,
        /// 1-based line of the header.
        line: usize,
        /// Columns of the header.
        columns: usize,
        /// The most read.
        limit: usize,
    },
    /// A requested column name appears more than once in the header.
    #[error("{path} line {line}: column \"{column}\" appears more than once")]
    DuplicateColumn {
        /// File that was being read.
        path: PathBuf,
        /// 1-based line of the header.
        line: usize,
        /// The ambiguous column name.
        column: String,
    },
    /// A data row has fewer fields than the header has columns.
    #[error("{path} line {line}: {found} fields, expected {expected}")]
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
    #[error(
        "{path} line {line}: {found} non-empty fields, but the header has only {expected} columns"
    )]
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
    #[error("{path} line {line}: column \"{column}\" is empty")]
    EmptyCell {
        /// File that was being read.
        path: PathBuf,
        /// 1-based line number.
        line: usize,
        /// Column name.
        column: String,
    },
    /// A requested cell is not a number.
    #[error("{path} line {line}: column \"{column}\": \"{text}\" is not a number")]
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
    /// A requested cell holds a number with a decimal comma (`3,25`) where the numbers take
    /// a decimal point ([`Decimal::Point`](super::Decimal::Point)).
    #[error(
        "{path} line {line}: column \"{column}\": \"{text}\" has a decimal comma: give \
         --decimal comma (fields then separated by `;`), or write the number as 3.25"
    )]
    DecimalComma {
        /// File that was being read.
        path: PathBuf,
        /// 1-based line number.
        line: usize,
        /// Column name.
        column: String,
        /// The cell (trimmed).
        text: String,
    },
    /// A requested cell holds a decimal point where the numbers take a decimal comma
    /// ([`Decimal::Comma`](super::Decimal::Comma)): a thousands separator or a file of the
    /// other notation, refused rather than guessed.
    #[error(
        "{path} line {line}: column \"{column}\": \"{text}\" has a decimal point, but \
         --decimal comma reads numbers as 3,25: drop --decimal comma for this file, and \
         remove any thousands separators"
    )]
    DecimalPoint {
        /// File that was being read.
        path: PathBuf,
        /// 1-based line number.
        line: usize,
        /// Column name.
        column: String,
        /// The cell (trimmed).
        text: String,
    },
    /// A decimal comma with `,` as the field delimiter: a number's comma would split it.
    #[error(
        "{path}: a decimal comma needs another field delimiter than `,`: give --delimiter \
         semicolon or tab (or leave --delimiter out: `;` is then taken)"
    )]
    DecimalCommaDelimiter {
        /// File that was being read.
        path: PathBuf,
    },
    /// A requested cell (or a value to be written) is NaN or infinite.
    #[error("{path} line {line}: column \"{column}\": {value} is not a finite number")]
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
    #[error("{path}{}: malformed CSV: {reason}", line_text(*.line))]
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
    #[error("{path}: cannot write columns: {reason}")]
    InvalidColumns {
        /// File that was being written.
        path: PathBuf,
        /// What is wrong.
        reason: String,
    },
}

/// The column names quoted and separated by commas.
fn quoted(columns: &[String]) -> String {
    let list: Vec<String> = columns.iter().map(|c| format!("\"{c}\"")).collect();
    list.join(", ")
}

/// ` line 7` after the file name, or nothing when the line is unknown.
fn line_text(line: Option<usize>) -> String {
    line.map_or_else(String::new, |l| format!(" line {l}"))
}
