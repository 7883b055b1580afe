//! The CSV reader on arbitrary bytes: records or a line-numbered error. The first byte chooses
//! the delimiter option (sniffed, `,`, `;`, tab) and which columns are asked for; the rest is
//! the file. A line an error or a record names lies within the file; records come in
//! ascending lines, one value per requested column, all finite.
#![no_main]

use hsid_host::io::{CsvOptions, Delimiter, IoError, read_table_from};
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
    match read_table_from("fuzz.csv", text, names, &CsvOptions { delimiter }) {
        Ok(t) => {
            assert_eq!(t.columns.len(), names.len());
            for c in &t.columns {
                assert_eq!(c.len(), t.lines.len());
                assert!(c.iter().all(|v| v.is_finite()));
            }
            assert!(t.lines.windows(2).all(|w| w[0] < w[1]), "{:?}", t.lines);
            assert!(t.lines.iter().all(|&l| 1 <= l && l <= lines), "{:?}", t.lines);
        }
        Err(e) => {
            if let Some(line) = error_line(&e) {
                assert!(1 <= line && line <= lines, "{e} but the input has {lines} lines");
            }
            let message = e.to_string();
            assert!(message.starts_with("fuzz.csv"), "{message}");
        }
    }
});
