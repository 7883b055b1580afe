//! CSV rows one at a time, in memory that does not grow with the file: for records too large
//! to hold (10⁸ rows), pushed sample by sample into the streaming identifier.
//!
//! The rules are those of [`read_table`](super::read_table) (comments, a blank line only at
//! the end, trailing empty fields, unrequested columns that may be empty, a byte order mark,
//! Windows line ends, the same errors with the same lines) with one restriction: a record is
//! one line, so a quoted field that runs past the end of its line is an
//! [`IoError::Malformed`] naming that line.

use std::io::{BufRead, Read};
use std::path::{Path, PathBuf};

use super::read::{Cells, LONE_CR, clean, resolve, units_of};
use super::{CsvOptions, Decimal, Delimiter, FileError, IoError};

/// The longest line read (1 MiB): memory stays bounded even for a file without line breaks.
pub const MAX_LINE_BYTES: u64 = 1 << 20;

/// A CSV file read row by row ([`CsvStream::next_row`]); memory is one line and the requested
/// values.
pub struct CsvStream<R> {
    path: PathBuf,
    reader: R,
    delimiter: u8,
    decimal: Decimal,
    header: Vec<String>,
    indices: Vec<usize>,
    /// Line number of the last line read.
    line: usize,
    /// The first blank line not yet followed by content.
    blank: Option<usize>,
    /// Data rows read so far.
    rows: u64,
    buf: Vec<u8>,
    unquote: Unquote,
    values: Vec<Vec<f64>>,
}

impl<R: BufRead> CsvStream<R> {
    /// Reads up to the header and resolves `names` in it; `source` names the file in errors.
    pub fn new(
        source: impl AsRef<Path>,
        reader: R,
        names: &[&str],
        options: &CsvOptions,
    ) -> Result<Self, IoError> {
        let mut s = Self {
            path: source.as_ref().to_path_buf(),
            reader,
            delimiter: b',',
            decimal: options.decimal,
            header: Vec::new(),
            indices: Vec::new(),
            line: 0,
            blank: None,
            rows: 0,
            buf: Vec::new(),
            unquote: Unquote::new(b','),
            values: vec![Vec::with_capacity(1); names.len()],
        };
        if !s.next_content()? {
            return Err(IoError::Empty { path: s.path });
        }
        let text = s.text();
        let delimiter = options.delimiter_for(&s.path, text)?;
        s.delimiter = match delimiter {
            Delimiter::Comma => b',',
            Delimiter::Semicolon => b';',
            Delimiter::Tab => b'\t',
        };
        s.unquote = Unquote::new(s.delimiter);
        let text = trim_line(&s.buf, s.line);
        let mut header: Vec<String> = match s.unquote.fields(text) {
            Ok(fields) => fields.into_iter().map(|f| clean(f).to_string()).collect(),
            Err(reason) => return Err(s.malformed(reason)),
        };
        while header.last().is_some_and(|h| h.is_empty()) {
            header.pop();
        }
        s.indices = resolve(&s.path, s.line, &header, names)?;
        s.header = header;
        Ok(s)
    }

    /// The next data row: its 1-based line and the requested values in the order of the
    /// names; `None` at the end of the file, [`IoError::NoData`] if the file has no data row.
    pub fn next_row(&mut self) -> Result<Option<(usize, Vec<f64>)>, IoError> {
        if !self.next_content()? {
            if self.rows == 0 {
                return Err(IoError::NoData {
                    path: self.path.clone(),
                });
            }
            return Ok(None);
        }
        self.rows += 1;
        let mut values = std::mem::take(&mut self.values);
        values.iter_mut().for_each(Vec::clear);
        let text = trim_line(&self.buf, self.line);
        let fields = match self.unquote.fields(text) {
            Ok(fields) => fields,
            Err(reason) => {
                return Err(IoError::Malformed {
                    path: self.path.clone(),
                    line: Some(self.line),
                    reason: reason.to_string(),
                });
            }
        };
        let fields: Vec<&str> = fields.into_iter().map(clean).collect();
        let (path, line) = (&self.path, self.line);
        let cells = Cells {
            header: &self.header,
            indices: &self.indices,
            decimal: self.decimal,
        };
        let checked = cells.row(path, line, &fields, &mut values);
        let out = values.iter().filter_map(|c| c.first().copied()).collect();
        self.values = values;
        checked?;
        Ok(Some((line, out)))
    }

    /// The unit the header states for each requested column (`u [V]`), in the order of the
    /// names; `None` where it states none.
    pub fn units(&self) -> Vec<Option<String>> {
        units_of(&self.header, &self.indices)
    }

    /// The line [`Self::next_content`] found (checked UTF-8 there).
    fn text(&self) -> &str {
        std::str::from_utf8(trim_line(&self.buf, self.line)).unwrap_or_default()
    }

    fn malformed(&self, reason: &str) -> IoError {
        IoError::Malformed {
            path: self.path.clone(),
            line: Some(self.line),
            reason: reason.to_string(),
        }
    }

    /// Reads the next line that is neither a comment nor blank (then [`Self::text`]); a blank
    /// line before it is an error. `false` at the end of the file.
    fn next_content(&mut self) -> Result<bool, IoError> {
        loop {
            self.buf.clear();
            let n = (&mut self.reader)
                .take(MAX_LINE_BYTES + 1)
                .read_until(b'\n', &mut self.buf)
                .map_err(|e| FileError::read(&self.path, e))?;
            if n == 0 {
                return Ok(false);
            }
            self.line += 1;
            if n as u64 > MAX_LINE_BYTES && !self.buf.ends_with(b"\n") {
                return Err(self.malformed(&format!(
                    "line longer than {MAX_LINE_BYTES} bytes (a CSV row of numbers is short; is \
                     this a text file with line breaks?)"
                )));
            }
            // Checked before a comment is skipped: the whole-file reader refuses a file that is
            // not UTF-8 wherever the bad byte is.
            let bytes = trim_line(&self.buf, self.line);
            let Ok(text) = std::str::from_utf8(bytes) else {
                return Err(IoError::NotUtf8 {
                    path: self.path.clone(),
                    line: self.line,
                });
            };
            if text.contains('\r') {
                return Err(self.malformed(LONE_CR));
            }
            if text.starts_with('#') {
                continue;
            }
            if text.trim().is_empty() {
                self.blank.get_or_insert(self.line);
                continue;
            }
            if let Some(line) = self.blank {
                return Err(IoError::BlankLine {
                    path: self.path.clone(),
                    line,
                });
            }
            return Ok(true);
        }
    }
}

/// The line's bytes without a leading byte order mark (line 1), the line end and a `\r`.
fn trim_line(buf: &[u8], line: usize) -> &[u8] {
    let mut bytes = buf;
    if line == 1 {
        bytes = bytes.strip_prefix("\u{feff}".as_bytes()).unwrap_or(bytes);
    }
    // A `\r` is part of the line end only before a `\n` (at the end of the file it is a
    // carriage return that ends no line, refused by the caller).
    match bytes.strip_suffix(b"\n") {
        Some(line) => line.strip_suffix(b"\r").unwrap_or(line),
        None => bytes,
    }
}

/// The fields of one line as the whole-file reader gets them: the `csv` crate's own parser
/// (`csv-core`) over the line, so quoting follows the same rules (a quote opens a quoted field
/// only at its start, `""` inside one is a quote, text after the closing quote is kept).
struct Unquote {
    delimiter: u8,
    /// The parser, built on first use (building it compiles its state machine: once per
    /// stream, not once per delimiter tried).
    parser: Option<csv_core::Reader>,
    out: Vec<u8>,
    ends: Vec<usize>,
}

impl Unquote {
    fn new(delimiter: u8) -> Self {
        Self {
            delimiter,
            parser: None,
            out: Vec::new(),
            ends: Vec::new(),
        }
    }

    /// The unquoted fields of `line` (valid UTF-8, no line end). A quote left open at the end
    /// of the line is an error: a record is one line here.
    fn fields(&mut self, line: &[u8]) -> Result<Vec<&str>, &'static str> {
        // Unquoting only shortens the text; the line end may join an open quoted field, and a
        // line has at most one field more than bytes.
        self.out.clear();
        self.out.resize(line.len() + 1, 0);
        self.ends.clear();
        self.ends.resize(line.len() + 2, 0);
        let delimiter = self.delimiter;
        let parser = self
            .parser
            .get_or_insert_with(|| csv_core::ReaderBuilder::new().delimiter(delimiter).build());
        parser.reset();
        let (res, _, o1, e1) = parser.read_record(line, &mut self.out, &mut self.ends);
        if !matches!(res, csv_core::ReadRecordResult::InputEmpty) {
            return Err("the line did not parse as one CSV record");
        }
        // The line end ends the record, unless the parser takes it into a quoted field.
        let (res, _, o2, e2) = parser.read_record(b"\n", &mut self.out[o1..], &mut self.ends[e1..]);
        if !matches!(res, csv_core::ReadRecordResult::Record) {
            return Err("a quoted field runs past the end of its line (a record is one line here)");
        }
        let (out, ends) = (&self.out[..o1 + o2], &self.ends[..e1 + e2]);
        let mut start = 0;
        let mut fields = Vec::with_capacity(ends.len());
        for &end in ends {
            let field = std::str::from_utf8(out.get(start..end).unwrap_or_default())
                .map_err(|_| "a field is not UTF-8 after unquoting")?;
            fields.push(field);
            start = end;
        }
        Ok(fields)
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use crate::io::parse_table;

    fn stream_all(text: &str, names: &[&str]) -> Result<(Vec<Vec<f64>>, Vec<usize>), IoError> {
        let opts = CsvOptions::default();
        let mut s = CsvStream::new("s.csv", text.as_bytes(), names, &opts)?;
        let (mut rows, mut lines) = (Vec::new(), Vec::new());
        while let Some((line, values)) = s.next_row()? {
            rows.push(values);
            lines.push(line);
        }
        Ok((rows, lines))
    }

    #[test]
    fn rows_and_lines_are_those_of_the_whole_file_reader() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../examples/data/servo.csv");
        let text = std::fs::read_to_string(path).unwrap();
        let whole = parse_table("s.csv", &text, &["y", "u"], &CsvOptions::default()).unwrap();
        let (rows, lines) = stream_all(&text, &["y", "u"]).unwrap();
        assert_eq!(lines, whole.lines);
        assert_eq!(rows.len(), whole.columns[0].len());
        for (i, r) in rows.iter().enumerate() {
            assert_eq!(r, &vec![whole.columns[0][i], whole.columns[1][i]]);
        }
        assert!(rows.len() > 1000, "{} rows", rows.len());
    }

    #[test]
    fn quirks_and_errors_name_the_lines_the_whole_file_reader_names() {
        let ok = "\u{feff}# c\r\n\"u\"; \"y\"\r\n1;2;\r\n# mid\r\n3;\"4\"\r\n\r\n  \r\n";
        assert_eq!(
            stream_all(ok, &["u", "y"]).unwrap(),
            (vec![vec![1.0, 2.0], vec![3.0, 4.0]], vec![3, 5])
        );
        for bad in [
            "u,y\n1,2\n\n3,4\n",
            "u,y\n1,2\n3,x\n",
            "u,y\n1\n",
            "u,y\n1,2,3\n",
            "u,y\n1,inf\n",
            "u,y\n",
            "# only\n\n",
            "a,b\n1,2\n",
        ] {
            let whole = parse_table("s.csv", bad, &["u", "y"], &CsvOptions::default());
            let streamed = stream_all(bad, &["u", "y"]);
            assert_eq!(
                streamed.unwrap_err().to_string(),
                whole.unwrap_err().to_string(),
                "{bad:?}"
            );
        }
    }

    /// Found by fuzzing (the `csv` target): a lone `\r` inside a line, which the whole-file
    /// reader took for a line end.
    #[test]
    fn a_carriage_return_that_ends_no_line_is_refused_with_its_line() {
        let e = stream_all("u;y\r\n1;2\r3;4\r\n", &["y"]).unwrap_err();
        assert!(
            matches!(e, IoError::Malformed { line: Some(2), .. }),
            "{e:?}"
        );
    }

    /// Found by fuzzing (the `csv` target): a `\r` at the very end of the file, after a
    /// comment, was taken for a line end here and refused by the whole-file reader.
    #[test]
    fn a_carriage_return_ending_the_file_is_refused_with_its_line() {
        let e = stream_all("u;y\r\n1;2\r\n# c\r", &["y"]).unwrap_err();
        assert!(
            matches!(e, IoError::Malformed { line: Some(3), .. }),
            "{e:?}"
        );
    }

    /// Found by fuzzing (the `csv` target): a quote inside a field opened a quoted field
    /// here, so the delimiter after it was not seen; the `csv` crate reads it as a character.
    #[test]
    fn a_quote_inside_a_field_is_a_character() {
        let mut u = Unquote::new(b',');
        assert_eq!(u.fields(b"-1\",`\"").unwrap(), vec!["-1\"", "`\""]);
        assert_eq!(u.fields(b"\"a,b\"\"c\",d").unwrap(), vec!["a,b\"c", "d"]);
        let (rows, _) = stream_all("u,y\n-1\",2\n", &["u", "y"]).unwrap();
        assert_eq!(rows, vec![vec![-1.0, 2.0]]);
    }

    /// Found by fuzzing (the `csv` target): text after a closing quote was kept by the
    /// whole-file reader (`"4"0` is 40) and made the field "not a number" here.
    #[test]
    fn text_after_a_closing_quote_is_kept_as_the_whole_file_reader_keeps_it() {
        let text = "u,y\n1,\"4\"0\n";
        let whole = parse_table("s.csv", text, &["u", "y"], &CsvOptions::default()).unwrap();
        assert_eq!(whole.columns[1], vec![40.0]);
        let (rows, _) = stream_all(text, &["u", "y"]).unwrap();
        assert_eq!(rows, vec![vec![1.0, 40.0]]);
    }

    /// Found by fuzzing (the `csv` target): a comment line that is not UTF-8 was skipped here
    /// and refused by the whole-file reader.
    #[test]
    fn a_comment_that_is_not_utf8_is_refused_with_its_line() {
        let text = b"u;y\r\n1;2\r\n#}\xff\xff c\r\n3;4\r\n";
        let opts = CsvOptions::default();
        let mut s = CsvStream::new("s.csv", &text[..], &["y"], &opts).unwrap();
        assert_eq!(s.next_row().unwrap(), Some((2, vec![2.0])));
        let e = s.next_row().unwrap_err();
        assert!(matches!(e, IoError::NotUtf8 { line: 3, .. }), "{e:?}");
    }

    #[test]
    fn an_open_quote_and_an_endless_line_are_refused_with_their_line() {
        let e = stream_all("u,y\n1,\"2\n3\"\n", &["u", "y"]).unwrap_err();
        assert!(matches!(e, IoError::Malformed { line: Some(2), .. }), "{e}");
        let long = format!("u,y\n{}", "1".repeat(MAX_LINE_BYTES as usize + 10));
        let e = stream_all(&long, &["u", "y"]).unwrap_err();
        assert!(matches!(e, IoError::Malformed { line: Some(2), .. }), "{e}");
    }
}
