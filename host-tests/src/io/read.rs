//! CSV columns in: the requested columns of a file with a header, as numbers, with the line of
//! every sample.

use std::borrow::Cow;
use std::fs;
use std::io::Read;
use std::path::{Path, PathBuf};

use super::limited::read_limited;
use super::{FileError, IoError, LimitedReadError};

/// The largest CSV file read whole (256 MiB, some 8·10⁶ rows of `t,u,y`): parsing holds the
/// text and its columns in memory, several times the file's size. A larger file is
/// [`IoError::TooLarge`]; [`CsvStream`](super::CsvStream) reads any length row by row.
pub const MAX_RECORD_BYTES: u64 = 256 << 20;

/// The most columns a CSV header may have (65,536): measurement logs hold tens or hundreds;
/// a wider header is refused before its names are copied.
pub const MAX_COLUMNS: usize = 1 << 16;

/// A CSV field delimiter.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Delimiter {
    /// `,`
    Comma,
    /// `;`
    Semicolon,
    /// A tab character.
    Tab,
}

impl Delimiter {
    /// The delimiter of a header line: tab if it holds a tab, else `;` if it holds a `;` and
    /// no `,`, else `,`.
    pub fn sniff(header: &str) -> Self {
        if header.contains('\t') {
            Self::Tab
        } else if header.contains(';') && !header.contains(',') {
            Self::Semicolon
        } else {
            Self::Comma
        }
    }

    fn byte(self) -> u8 {
        match self {
            Self::Comma => b',',
            Self::Semicolon => b';',
            Self::Tab => b'\t',
        }
    }
}

/// The decimal separator of the numbers of a CSV file.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Decimal {
    /// `3.25`, the default.
    #[default]
    Point,
    /// `3,25`, as European loggers write; the fields are then separated by `;` (or tabs).
    Comma,
}

/// How a CSV file is read.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CsvOptions {
    /// The field delimiter; `None` sniffs it from the header line ([`Delimiter::sniff`]), or
    /// with a decimal comma takes `;` (a tab when the header has one).
    pub delimiter: Option<Delimiter>,
    /// The decimal separator of the numbers.
    pub decimal: Decimal,
}

impl CsvOptions {
    /// The delimiter of a file whose header line is `header`: the one given, else sniffed
    /// ([`Delimiter::sniff`]); with a decimal comma `;` unless the header has a tab, and `,`
    /// refused ([`IoError::DecimalCommaDelimiter`]).
    pub fn delimiter_for(&self, path: &Path, header: &str) -> Result<Delimiter, IoError> {
        match (self.decimal, self.delimiter) {
            (Decimal::Comma, Some(Delimiter::Comma)) => Err(IoError::DecimalCommaDelimiter {
                path: path.to_path_buf(),
            }),
            (Decimal::Comma, None) if header.contains('\t') => Ok(Delimiter::Tab),
            (Decimal::Comma, None) => Ok(Delimiter::Semicolon),
            (Decimal::Point, None) => Ok(Delimiter::sniff(header)),
            (_, Some(d)) => Ok(d),
        }
    }
}

/// The requested columns of a CSV file.
#[derive(Clone, Debug, PartialEq)]
pub struct Table {
    /// One column per requested name, in the order of the names, one value per data row.
    pub columns: Vec<Vec<f64>>,
    /// The 1-based line of each data row in the file (comment lines make it differ from the
    /// row index + 2).
    pub lines: Vec<usize>,
    /// The unit each requested column's header states as `name [unit]` or `name (unit)`
    /// ([`split_unit`]), in the order of the names; `None` where it states none.
    pub units: Vec<Option<String>>,
}

/// A header name's name and unit: `u [V]` and `u (V)` are `("u", Some("V"))`, `u` is
/// `("u", None)`. The unit is what the brackets hold, trimmed; empty brackets or a name
/// that is nothing but brackets state no unit.
pub fn split_unit(header: &str) -> (&str, Option<&str>) {
    let header = header.trim();
    for (open, close) in [('[', ']'), ('(', ')')] {
        if let Some(inner) = header.strip_suffix(close)
            && let Some((name, unit)) = inner.rsplit_once(open)
        {
            let (name, unit) = (name.trim(), unit.trim());
            if !name.is_empty() && !unit.is_empty() {
                return (name, Some(unit));
            }
        }
    }
    (header, None)
}

/// The first line with content of a CSV text (not blank, not a `#` comment), split into its
/// cleaned names: the header, read without the data (to find a time column among its
/// names). [`IoError::Empty`] when there is none.
pub fn header_names(
    source: impl AsRef<Path>,
    text: &str,
    options: &CsvOptions,
) -> Result<Vec<String>, IoError> {
    let path = source.as_ref();
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let Some((_, line)) = layout_header(text) else {
        return Err(IoError::Empty {
            path: path.to_path_buf(),
        });
    };
    let delimiter = options.delimiter_for(path, line)?;
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .delimiter(delimiter.byte())
        .from_reader(line.as_bytes());
    let mut record = csv::StringRecord::new();
    reader
        .read_record(&mut record)
        .map_err(|e| IoError::Malformed {
            path: path.to_path_buf(),
            line: None,
            reason: e.to_string(),
        })?;
    let mut header: Vec<String> = record.iter().map(|f| clean(f).to_string()).collect();
    while header.last().is_some_and(|h| h.is_empty()) {
        header.pop();
    }
    Ok(header)
}

/// The first line with content (1-based) and its text, without its line end.
fn layout_header(text: &str) -> Option<(usize, &str)> {
    text.split('\n').enumerate().find_map(|(i, line)| {
        let line = line.strip_suffix('\r').unwrap_or(line);
        (!line.trim().is_empty() && !line.starts_with('#')).then_some((i + 1, line))
    })
}

/// Reads the named columns of a CSV file with a header row, the delimiter sniffed.
///
/// Returns one `Vec<f64>` per requested name, in the order of `names`, each with one value per
/// data row. Column names are case-sensitive and compared after trimming spaces and double
/// quotes. See the [module documentation](super) for what is tolerated; everything else is an
/// [`IoError`] naming the 1-based line.
pub fn read_columns(path: impl AsRef<Path>, names: &[&str]) -> Result<Vec<Vec<f64>>, IoError> {
    read_table(path, names, &CsvOptions::default()).map(|t| t.columns)
}

/// Parses CSV text that is already in memory; `source` is only used in error messages.
///
/// Same rules and errors as [`read_columns`].
pub fn parse_columns(
    source: impl AsRef<Path>,
    text: &str,
    names: &[&str],
) -> Result<Vec<Vec<f64>>, IoError> {
    parse_table(source, text, names, &CsvOptions::default()).map(|t| t.columns)
}

/// The name standing for standard input: a path `-` is read from standard input, and errors
/// name it `<stdin>`.
pub const STDIN_PATH: &str = "-";

/// The name errors give to standard input.
pub const STDIN_NAME: &str = "<stdin>";

/// [`read_columns`] with options, keeping the line of each row. The path `-`
/// ([`STDIN_PATH`]) reads standard input (see [`read_source`]).
pub fn read_table(
    path: impl AsRef<Path>,
    names: &[&str],
    options: &CsvOptions,
) -> Result<Table, IoError> {
    let (name, text) = read_source(path)?;
    parse_table(name, &text, names, options)
}

/// [`read_table`] over any reader (a pipe, a socket, a buffer); `source` names it in errors.
pub fn read_table_from<R: Read>(
    source: impl AsRef<Path>,
    reader: R,
    names: &[&str],
    options: &CsvOptions,
) -> Result<Table, IoError> {
    let source = source.as_ref();
    let text = read_text(source, reader, None)?;
    parse_table(source, &text, names, options)
}

/// The whole text of a file, or of standard input for the path `-`, with the name errors
/// should give it (the path, or `<stdin>`).
pub fn read_source(path: impl AsRef<Path>) -> Result<(PathBuf, String), IoError> {
    let path = path.as_ref();
    if path == Path::new(STDIN_PATH) {
        let name = PathBuf::from(STDIN_NAME);
        let text = read_text(&name, std::io::stdin().lock(), None)?;
        return Ok((name, text));
    }
    let file = fs::File::open(path).map_err(|source| FileError::read(path, source))?;
    let meta = file
        .metadata()
        .map_err(|source| FileError::read(path, source))?;
    let size = meta.is_file().then_some(meta.len());
    Ok((path.to_path_buf(), read_text(path, file, size)?))
}

/// All bytes of a reader as UTF-8 text, at most [`MAX_RECORD_BYTES`] (a larger file, `size`
/// when the file system reports it, is [`IoError::TooLarge`] before it is read); an invalid
/// byte is reported with its line.
fn read_text<R: Read>(path: &Path, reader: R, size: Option<u64>) -> Result<String, IoError> {
    let bytes = read_limited(path, reader, size, MAX_RECORD_BYTES).map_err(|e| match e {
        LimitedReadError::File(e) => IoError::File(e),
        LimitedReadError::TooLarge(e) => IoError::TooLarge(e),
    })?;
    String::from_utf8(bytes).map_err(|e| {
        let valid = e.utf8_error().valid_up_to();
        let line = 1 + e.as_bytes()[..valid]
            .iter()
            .filter(|&&b| b == b'\n')
            .count();
        IoError::NotUtf8 {
            path: path.to_path_buf(),
            line,
        }
    })
}

/// What the lines of the text are, before the CSV parser sees them.
struct Layout {
    /// 1-based lines that are blank (whitespace only), ascending.
    blank: Vec<usize>,
    /// The last line with content (not blank, not a comment); 0 when there is none.
    last: usize,
    /// The first line with content, if any.
    header: Option<(usize, String)>,
}

fn layout(text: &str) -> Layout {
    let mut l = Layout {
        blank: Vec::new(),
        last: 0,
        header: None,
    };
    for (i, line) in text.split('\n').enumerate() {
        let line = line.strip_suffix('\r').unwrap_or(line);
        if line.trim().is_empty() {
            l.blank.push(i + 1);
        } else if !line.starts_with('#') {
            l.last = i + 1;
            l.header.get_or_insert_with(|| (i + 1, line.to_string()));
        }
    }
    l
}

/// Why a line holding a carriage return that does not end it is refused.
pub(super) const LONE_CR: &str = "a carriage return (\\r) that is not followed by a line feed: \
     lines must end with \\n or \\r\\n (convert old Mac line ends)";

/// The 1-based line of the first `\r` not followed by `\n`: the parser would end a record
/// there, where no line ends, and every line number after it would be wrong.
fn lone_carriage_return(text: &str) -> Option<usize> {
    let bytes = text.as_bytes();
    let at = bytes
        .iter()
        .enumerate()
        .position(|(i, &b)| b == b'\r' && bytes.get(i + 1) != Some(&b'\n'))?;
    Some(1 + bytes[..at].iter().filter(|&&b| b == b'\n').count())
}

/// [`parse_columns`] with options, keeping the line of each row.
pub fn parse_table(
    source: impl AsRef<Path>,
    text: &str,
    names: &[&str],
    options: &CsvOptions,
) -> Result<Table, IoError> {
    let path = source.as_ref();
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    if let Some(line) = lone_carriage_return(text) {
        return Err(IoError::Malformed {
            path: path.to_path_buf(),
            line: Some(line),
            reason: LONE_CR.to_string(),
        });
    }
    let lay = layout(text);
    let Some((_, header_text)) = &lay.header else {
        return Err(IoError::Empty {
            path: path.to_path_buf(),
        });
    };
    let delimiter = options.delimiter_for(path, header_text)?;
    // Comment lines are emptied rather than left to the parser's comment option, which does
    // not count them in its line numbers; empty lines it skips and counts.
    // The copy is made only when there are comments, at its final size (a long record's text
    // is not held three times over).
    let uncommented: Cow<str> = match text.starts_with('#') || text.contains("\n#") {
        false => Cow::Borrowed(text),
        true => {
            let mut u = String::with_capacity(text.len());
            for l in text.split_inclusive('\n') {
                u.push_str(if l.starts_with('#') { "\n" } else { l });
            }
            Cow::Owned(u)
        }
    };
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .delimiter(delimiter.byte())
        .from_reader(uncommented.as_bytes());
    // The vectors of one entry a line are made at their final size: a record of a million
    // lines does not grow them by doubling.
    let line_count = uncommented.bytes().filter(|&b| b == b'\n').count() + 1;
    let mut starts: Vec<usize> = Vec::with_capacity(line_count);
    starts.push(0);
    starts.extend(uncommented.match_indices('\n').map(|(i, _)| i + 1));
    let empty: Vec<usize> = uncommented
        .split('\n')
        .enumerate()
        .filter(|(_, l)| l.is_empty() || *l == "\r")
        .map(|(i, _)| i + 1)
        .collect();
    let mut rows = Rows {
        path,
        starts: &starts,
        empty: &empty,
        blank: &lay.blank,
        last: lay.last,
        reader: &mut reader,
        record: csv::StringRecord::new(),
    };
    let Some(header_line) = rows.next_row()? else {
        return Err(IoError::Empty {
            path: path.to_path_buf(),
        });
    };
    // Checked before the names are copied: a header of millions of columns is no record.
    if rows.record.len() > MAX_COLUMNS {
        return Err(IoError::TooManyColumns {
            path: path.to_path_buf(),
            line: header_line,
            columns: rows.record.len(),
            limit: MAX_COLUMNS,
        });
    }
    let mut header: Vec<String> = rows.record.iter().map(|f| clean(f).to_string()).collect();
    while header.last().is_some_and(|h| h.is_empty()) {
        header.pop();
    }
    let indices = resolve(path, header_line, &header, names)?;
    let mut table = Table {
        columns: (0..names.len())
            .map(|_| Vec::with_capacity(line_count))
            .collect(),
        lines: Vec::with_capacity(line_count),
        units: units_of(&header, &indices),
    };
    while let Some(line) = rows.next_row()? {
        let fields: Vec<&str> = rows.record.iter().map(clean).collect();
        let cells = Cells {
            header: &header,
            indices: &indices,
            decimal: options.decimal,
        };
        cells.row(path, line, &fields, &mut table.columns)?;
        table.lines.push(line);
    }
    if table.lines.is_empty() {
        return Err(IoError::NoData {
            path: path.to_path_buf(),
        });
    }
    Ok(table)
}

/// The CSV records up to the last line with content, refusing a blank line before any of them.
struct Rows<'a, R> {
    path: &'a Path,
    /// Byte offset of the start of each line.
    starts: &'a [usize],
    /// 1-based lines that are empty (nothing but the line end) for the parser.
    empty: &'a [usize],
    /// 1-based lines that are blank (whitespace only), ascending.
    blank: &'a [usize],
    last: usize,
    reader: &'a mut csv::Reader<R>,
    record: csv::StringRecord,
}

impl<R: std::io::Read> Rows<'_, R> {
    /// The 1-based line of a record the parser placed at byte `byte`. The parser's line count
    /// leaves out the empty lines it skips, and its offset points before them: the line is the
    /// first at or after `byte` that is not empty. After a `\r\n` line end the offset is that
    /// of its `\n` (the parser ends the record at the `\r`), the end of the line before: a
    /// `\n` counts as the start of the line that follows it.
    fn line_of(&self, byte: u64) -> usize {
        let byte = usize::try_from(byte).unwrap_or(usize::MAX);
        let byte = match self.starts.binary_search(&byte.saturating_add(1)) {
            Ok(_) => byte.saturating_add(1),
            Err(_) => byte,
        };
        let mut line = self.starts.partition_point(|&s| s <= byte);
        while line < self.starts.len() && self.empty.binary_search(&line).is_ok() {
            line += 1;
        }
        line
    }

    /// Reads the next record into `self.record` and returns its line, `None` at the end.
    fn next_row(&mut self) -> Result<Option<usize>, IoError> {
        let more = self.reader.read_record(&mut self.record);
        let more = more.map_err(|e| IoError::Malformed {
            path: self.path.to_path_buf(),
            line: e.position().map(|p| self.line_of(p.byte())),
            reason: e.to_string(),
        })?;
        let line = self
            .record
            .position()
            .map_or(usize::MAX, |p| self.line_of(p.byte()));
        if !more || line > self.last {
            return Ok(None);
        }
        if let Some(&b) = self.blank.first().filter(|&&b| b <= line) {
            return Err(IoError::BlankLine {
                path: self.path.to_path_buf(),
                line: b,
            });
        }
        Ok(Some(line))
    }
}

/// The index of each requested column in the header.
pub(super) fn resolve(
    path: &Path,
    line: usize,
    header: &[String],
    names: &[&str],
) -> Result<Vec<usize>, IoError> {
    let mut indices = Vec::with_capacity(names.len());
    for &name in names {
        let wanted = clean(name);
        // The name as written (`u [V]`), else the name part of `name [unit]` headers.
        let exact = header.iter().any(|h| h == wanted);
        let matches = |h: &String| match exact {
            true => h == wanted,
            false => split_unit(h).0 == wanted,
        };
        let mut hits = header.iter().enumerate().filter(|(_, h)| matches(h));
        match (hits.next(), hits.next()) {
            (Some((i, _)), None) => indices.push(i),
            (Some(_), Some(_)) => {
                return Err(IoError::DuplicateColumn {
                    path: path.to_path_buf(),
                    line,
                    column: wanted.to_string(),
                });
            }
            (None, _) => {
                return Err(IoError::MissingColumn {
                    path: path.to_path_buf(),
                    line,
                    column: wanted.to_string(),
                    available: header.iter().filter(|h| !h.is_empty()).cloned().collect(),
                });
            }
        }
    }
    Ok(indices)
}

/// The unit the header states for each resolved column ([`split_unit`]).
pub(super) fn units_of(header: &[String], indices: &[usize]) -> Vec<Option<String>> {
    indices
        .iter()
        .map(|&i| split_unit(&header[i]).1.map(str::to_string))
        .collect()
}

/// How the requested cells of a row are found and read.
pub(super) struct Cells<'a> {
    /// The header's names.
    pub header: &'a [String],
    /// The index of each requested column in the header.
    pub indices: &'a [usize],
    /// The decimal separator.
    pub decimal: Decimal,
}

/// A cell as a number with the decimal separator `decimal`; the error to give otherwise.
fn number(cell: &str, decimal: Decimal) -> Result<f64, NumberError> {
    match decimal {
        Decimal::Point => cell.parse().map_err(|_| {
            let comma = cell.contains(',') && cell.replace(',', ".").parse::<f64>().is_ok();
            match comma {
                true => NumberError::Comma,
                false => NumberError::Bad,
            }
        }),
        Decimal::Comma if cell.contains('.') => Err(NumberError::Point),
        Decimal::Comma => cell.replace(',', ".").parse().map_err(|_| NumberError::Bad),
    }
}

/// Why a cell is not a number.
enum NumberError {
    /// Not a number in any notation.
    Bad,
    /// A number with a decimal comma, read with a decimal point.
    Comma,
    /// A number with a decimal point, read with a decimal comma.
    Point,
}

impl Cells<'_> {
    /// Checks one data row and appends its requested cells to `columns`.
    pub(super) fn row(
        &self,
        path: &Path,
        line: usize,
        fields: &[&str],
        columns: &mut [Vec<f64>],
    ) -> Result<(), IoError> {
        row(path, line, self, fields, columns)
    }
}

fn row(
    path: &Path,
    line: usize,
    cells: &Cells<'_>,
    fields: &[&str],
    columns: &mut [Vec<f64>],
) -> Result<(), IoError> {
    let (header, indices) = (cells.header, cells.indices);
    let err_path = || path.to_path_buf();
    let expected = header.len();
    if fields.len() < expected {
        return Err(IoError::TooFewFields {
            path: err_path(),
            line,
            expected,
            found: fields.len(),
        });
    }
    let non_empty = fields
        .iter()
        .rposition(|f| !f.is_empty())
        .map_or(0, |p| p + 1);
    if non_empty > expected {
        return Err(IoError::TooManyFields {
            path: err_path(),
            line,
            expected,
            found: non_empty,
        });
    }
    for (k, &col) in indices.iter().enumerate() {
        let cell = fields[col];
        let column = || header[col].clone();
        if cell.is_empty() {
            return Err(IoError::EmptyCell {
                path: err_path(),
                line,
                column: column(),
            });
        }
        let value: f64 = number(cell, cells.decimal).map_err(|e| {
            let (path, column, text) = (err_path(), column(), cell.to_string());
            match e {
                NumberError::Bad => IoError::BadNumber {
                    path,
                    line,
                    column,
                    text,
                },
                NumberError::Comma => IoError::DecimalComma {
                    path,
                    line,
                    column,
                    text,
                },
                NumberError::Point => IoError::DecimalPoint {
                    path,
                    line,
                    column,
                    text,
                },
            }
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
    Ok(())
}

/// Trims surrounding whitespace and double quotes.
pub(super) fn clean(s: &str) -> &str {
    s.trim().trim_matches('"').trim()
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    #[test]
    fn a_reader_is_read_like_a_file_and_named_in_errors() {
        let text = "# ts = 0.01 s\nu,y\n1,2\n3,4\n";
        let t = read_table_from(STDIN_NAME, text.as_bytes(), &["y"], &CsvOptions::default());
        let t = t.unwrap();
        assert_eq!(t.columns, vec![vec![2.0, 4.0]]);
        assert_eq!(t.lines, vec![3, 4]);
        let bad = "u,y\n1,2\n3,x\n";
        let e = read_table_from(STDIN_NAME, bad.as_bytes(), &["y"], &CsvOptions::default());
        assert_eq!(
            e.unwrap_err().to_string(),
            "<stdin> line 3: column \"y\": \"x\" is not a number"
        );
    }

    /// Found by fuzzing (the `csv` target, which compares this reader with `CsvStream`): with
    /// Windows line ends every data row and every error was given the line before its own.
    #[test]
    fn windows_line_ends_give_each_row_its_own_line() {
        let text = "u;y\r\n1;2\r\n# c\r\n3;\"4\"\r\n\r\n";
        let t = read_table_from("a.csv", text.as_bytes(), &["y"], &CsvOptions::default());
        let t = t.unwrap();
        assert_eq!(t.columns, vec![vec![2.0, 4.0]]);
        assert_eq!(t.lines, vec![2, 4]);
        let bad = "u,y\r\n1,2\r\n\r\n3,x\r\n";
        let e = read_table_from("a.csv", bad.as_bytes(), &["y"], &CsvOptions::default());
        assert!(
            matches!(e, Err(IoError::BlankLine { line: 3, .. })),
            "{e:?}"
        );
        let bad = "u,y\r\n1,2\r\n3,x\r\n";
        let e = read_table_from("a.csv", bad.as_bytes(), &["y"], &CsvOptions::default());
        assert_eq!(
            e.unwrap_err().to_string(),
            "a.csv line 3: column \"y\": \"x\" is not a number"
        );
    }

    /// Found by fuzzing (the `csv` target): a lone `\r` ended a record for the parser but not
    /// a line, so rows were read that the line numbers did not describe.
    #[test]
    fn a_carriage_return_that_ends_no_line_is_refused_with_its_line() {
        let text = "u;y\r\n1;2\r3;4\r\n";
        let e = read_table_from("a.csv", text.as_bytes(), &["y"], &CsvOptions::default());
        assert!(
            matches!(e, Err(IoError::Malformed { line: Some(2), .. })),
            "{e:?}"
        );
    }
}
