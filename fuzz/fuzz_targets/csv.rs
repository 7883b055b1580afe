//! The CSV reader on arbitrary bytes: records or a line-numbered error. The first byte chooses
//! the delimiter option (sniffed, `,`, `;`, tab) and which columns are asked for; the rest is
//! the file. A line an error or a record names lies within the file; records come in
//! ascending lines, one value per requested column, all finite. The row-by-row reader
//! (`CsvStream`) must agree: the same rows on the same lines when the whole-file reader
//! accepts the file (or a `Malformed` line, for a quoted field that spans lines, which it does
//! not take), an error when the whole-file reader refuses it.
#![no_main]

use hsid_host::io::{CsvOptions, CsvStream, Decimal, Delimiter, IoError, Table, read_table_from};
use libfuzzer_sys::fuzz_target;

const NAMES: [&[&str]; 4] = [&["u", "y"], &["y"], &["a", "b", "c"], &["u", "u"]];

/// The line an error names, if it names one.
fn error_line(e: &IoError) -> Option<usize> {
    match e {
        IoError::NotUtf8 { line, .. }
        | IoError::BlankLine { line, .. }
        | IoError::MissingColumn { line, .. }
        | IoError::DuplicateColumn { line, .. }
        | IoError::TooFewFields { line, .. }
        | IoError::TooManyFields { line, .. }
        | IoError::EmptyCell { line, .. }
        | IoError::BadNumber { line, .. }
        | IoError::NonFinite { line, .. } => Some(*line),
        IoError::Malformed { line, .. } => *line,
        _ => None,
    }
}

/// The rows `CsvStream` reads, as a table, or its first error.
fn stream(text: &[u8], names: &[&str], options: &CsvOptions) -> Result<Table, IoError> {
    let mut s = CsvStream::new("fuzz.csv", text, names, options)?;
    let mut t = Table {
        columns: vec![Vec::new(); names.len()],
        lines: Vec::new(),
        units: s.units(),
    };
    while let Some((line, values)) = s.next_row()? {
        assert_eq!(values.len(), names.len());
        t.lines.push(line);
        t.columns
            .iter_mut()
            .zip(values)
            .for_each(|(c, v)| c.push(v));
    }
    Ok(t)
}

fuzz_target!(|data: &[u8]| {
    let Some((&choice, text)) = data.split_first() else {
        return;
    };
    let delimiter = match choice & 3 {
        0 => None,
        1 => Some(Delimiter::Comma),
        2 => Some(Delimiter::Semicolon),
        _ => Some(Delimiter::Tab),
    };
    let names = NAMES[usize::from(choice >> 2) % NAMES.len()];
    let lines = 1 + text.iter().filter(|&&b| b == b'\n').count();
    let decimal = match choice & 64 {
        0 => Decimal::Point,
        _ => Decimal::Comma,
    };
    let options = CsvOptions { delimiter, decimal };
    let whole = read_table_from("fuzz.csv", text, names, &options);
    match (&whole, stream(text, names, &options)) {
        (Ok(w), Ok(s)) => assert_eq!(*w, s, "the row-by-row reader differs"),
        (Ok(_), Err(e)) => assert!(
            matches!(e, IoError::Malformed { .. }),
            "the row-by-row reader refuses a file the whole-file reader reads: {e}"
        ),
        (Err(w), Ok(_)) => panic!("the row-by-row reader reads a file refused with: {w}"),
        (Err(_), Err(_)) => {}
    }
    match whole {
        Ok(t) => {
            assert_eq!(t.columns.len(), names.len());
            for c in &t.columns {
                assert_eq!(c.len(), t.lines.len());
                assert!(c.iter().all(|v| v.is_finite()));
            }
            assert!(t.lines.windows(2).all(|w| w[0] < w[1]), "{:?}", t.lines);
            assert!(
                t.lines.iter().all(|&l| 1 <= l && l <= lines),
                "{:?}",
                t.lines
            );
        }
        Err(e) => {
            if let Some(line) = error_line(&e) {
                assert!(
                    1 <= line && line <= lines,
                    "{e} but the input has {lines} lines"
                );
            }
            let message = e.to_string();
            assert!(message.starts_with("fuzz.csv"), "{message}");
        }
    }
});
