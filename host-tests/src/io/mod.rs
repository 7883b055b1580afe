//! CSV columns in and out. A path `-` reads standard input (named `<stdin>` in errors).
//!
//! The CSV reader (on the `csv` crate) is deliberately strict: every problem is reported as an
//! [`IoError`] that names the file, the 1-based line and, where it applies, the column; nothing
//! is silently skipped. The only things tolerated are the harmless quirks of real measurement
//! files:
//!
//! * the delimiter `,`, `;` or tab: given ([`CsvOptions::delimiter`]) or sniffed from the
//!   header line ([`Delimiter::sniff`]: tab if the header has a tab, else `;` if it has a `;`
//!   and no `,`, else `,`); numbers take a decimal point, or with [`Decimal::Comma`] a
//!   decimal comma (`3,25`, the fields then separated by `;` unless the header has tabs); a
//!   number in the other notation is refused with the option to give, never guessed;
//! * a header name `name [unit]` or `name (unit)` ([`split_unit`]) answers to its name
//!   (`u [V]` is the column `u`), and its unit is kept ([`Table::units`]);
//! * comment lines starting with `#` (before the header or between rows), skipped;
//! * header names and cells are trimmed of surrounding spaces and double quotes
//!   (`"uEst", "yEst"` works), and quoted fields may hold the delimiter;
//! * trailing empty fields (`3.2567,0.97619,5.205,4.9728,4,`) and trailing empty header names;
//! * a column that is not requested may be empty or hold text (the `Ts` column of the cascaded
//!   tanks benchmark only has a value on its first row);
//! * blank lines at the very end of the file, Windows line endings and a UTF-8 byte order mark.
//!
//! A blank line *between* data rows is an error, because it usually means two files were
//! concatenated or a row was lost.

mod atomic;
mod error;
mod file_error;
mod limited;
mod partial;
mod read;
mod stream;
mod write;

pub use atomic::{AtomicFile, StagedDir, write_atomic};
pub use error::IoError;
pub use file_error::{FileAction, FileError};
pub use limited::{
    LimitedReadError, TooLarge, open_regular, read_file_limited, read_limited, read_text_bounded,
    read_to_string_limited,
};
pub use partial::{abandon, in_progress};
pub use read::{
    CsvOptions, Decimal, Delimiter, MAX_COLUMNS, MAX_RECORD_BYTES, STDIN_NAME, STDIN_PATH, Table,
    header_names, parse_columns, parse_table, read_columns, read_source, read_table,
    read_table_from, split_unit,
};
pub use stream::{CsvStream, MAX_LINE_BYTES};
pub use write::{format_f64, write_columns, write_columns_to};
