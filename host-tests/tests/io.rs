//! Tests of the CSV I/O, on the shared measurement files and on small texts.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::path::PathBuf;

use hsid_host::io::{
    CsvOptions, CsvStream, Decimal, Delimiter, FileAction, FileError, IoError, header_names,
    parse_columns, parse_table, read_columns, split_unit, write_columns, write_columns_to,
};

const TANKS: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../shared/data/cascaded-tanks/dataBenchmark.csv"
);
const MOTOR: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../shared/data/dc-motor-deadzone/run_minimal.csv"
);

/// A fresh scratch directory under the system temp dir, unique per test, removed on drop.
struct Scratch(PathBuf);

impl Scratch {
    fn join(&self, name: &str) -> PathBuf {
        self.0.join(name)
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

fn scratch(test: &str) -> Scratch {
    let dir = std::env::temp_dir().join(format!("hsid-io-test-{}-{test}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    Scratch(dir)
}

fn parse(text: &str, names: &[&str]) -> Result<Vec<Vec<f64>>, IoError> {
    parse_columns("data.csv", text, names)
}

// ----- the shared measurement files ---------------------------------------------------------

#[test]
fn cascaded_tanks_benchmark() {
    let cols = read_columns(TANKS, &["uEst", "uVal", "yEst", "yVal"]).unwrap();
    assert_eq!(cols.len(), 4);
    for c in &cols {
        assert_eq!(c.len(), 1024);
    }
    assert_eq!(
        [cols[0][0], cols[1][0], cols[2][0], cols[3][0]],
        [3.2567, 0.97619, 5.205, 4.9728]
    );
    assert_eq!(cols[0][1], 3.2466);
    // The last data row: 3.2615,0.94805,3.6831,3.7179,,
    assert_eq!(
        [cols[0][1023], cols[1][1023], cols[2][1023], cols[3][1023]],
        [3.2615, 0.94805, 3.6831, 3.7179]
    );
    // Order of the result follows the request, not the file.
    let swapped = read_columns(TANKS, &["yVal", "uEst"]).unwrap();
    assert_eq!(swapped[0], cols[3]);
    assert_eq!(swapped[1], cols[0]);
}

#[test]
fn cascaded_tanks_ts_is_only_on_the_first_row() {
    let err = read_columns(TANKS, &["uEst", "Ts"]).unwrap_err();
    match &err {
        IoError::EmptyCell { line, column, .. } => {
            assert_eq!(*line, 3);
            assert_eq!(column, "Ts");
        }
        other => panic!("unexpected error {other:?}"),
    }
    assert!(
        err.to_string()
            .ends_with("dataBenchmark.csv line 3: column \"Ts\" is empty")
    );
}

#[test]
fn dc_motor_numeric_columns() {
    let cols = read_columns(MOTOR, &["voltage", "rpm"]).unwrap();
    assert_eq!(cols[0].len(), 6601);
    assert_eq!(cols[1].len(), 6601);
    let vmax = cols[0].iter().copied().fold(f64::MIN, f64::max);
    let vmin = cols[0].iter().copied().fold(f64::MAX, f64::min);
    // The file stores the top level as 8.8100004196167 (a float32 value printed in full).
    assert!((vmax - 8.81).abs() < 1e-6, "{vmax}");
    assert!((vmin + 8.81).abs() < 1e-6, "{vmin}");
    let t = read_columns(MOTOR, &["time"]).unwrap();
    assert_eq!(t[0][0], 0.0);
    assert_eq!(t[0][1], 0.01);
}

#[test]
fn dc_motor_direction_is_text() {
    let err = read_columns(MOTOR, &["voltage", "direction"]).unwrap_err();
    match &err {
        IoError::BadNumber {
            line, column, text, ..
        } => {
            assert_eq!(*line, 2);
            assert_eq!(column, "direction");
            assert_eq!(text, "up");
        }
        other => panic!("unexpected error {other:?}"),
    }
    assert!(
        err.to_string()
            .ends_with("run_minimal.csv line 2: column \"direction\": \"up\" is not a number"),
        "{err}"
    );
}

#[test]
fn missing_column_lists_the_columns() {
    let err = read_columns(TANKS, &["uEst", "yest"]).unwrap_err();
    match &err {
        IoError::MissingColumn {
            column, available, ..
        } => {
            assert_eq!(column, "yest");
            assert_eq!(available, &["uEst", "uVal", "yEst", "yVal", "Ts"]);
        }
        other => panic!("unexpected error {other:?}"),
    }
    let msg = err.to_string();
    assert!(msg.contains("no column \"yest\""), "{msg}");
    assert!(
        msg.contains("\"uEst\", \"uVal\", \"yEst\", \"yVal\", \"Ts\""),
        "{msg}"
    );
}

#[test]
fn file_not_found() {
    let err = read_columns("/nonexistent/dir/data.csv", &["a"]).unwrap_err();
    assert!(
        matches!(
            err,
            IoError::File(FileError {
                action: FileAction::Read,
                ..
            })
        ),
        "{err:?}"
    );
    let msg = err.to_string();
    assert!(
        msg.starts_with("/nonexistent/dir/data.csv: cannot read file"),
        "{msg}"
    );
    assert!(std::error::Error::source(&err).is_some());
}

#[test]
fn not_utf8() {
    let dir = scratch("utf8");
    let p = dir.join("bad.csv");
    std::fs::write(&p, b"a,b\n1,2\n3,\xff\n").unwrap();
    let err = read_columns(&p, &["a"]).unwrap_err();
    assert!(matches!(err, IoError::NotUtf8 { line: 3, .. }), "{err:?}");
}

// ----- tolerated quirks ---------------------------------------------------------------------

#[test]
fn quotes_spaces_trailing_fields_crlf_bom() {
    let text = "\u{feff} \"a\" , \"b\",c,\r\n 1 ,\"2.5\",x,\r\n-3, 4e-3 ,,\r\n\r\n\n";
    let cols = parse(text, &["b", "a"]).unwrap();
    assert_eq!(cols, vec![vec![2.5, 0.004], vec![1.0, -3.0]]);
    // The request is trimmed the same way as the header.
    let cols = parse(text, &[" \"a\""]).unwrap();
    assert_eq!(cols, vec![vec![1.0, -3.0]]);
}

#[test]
fn quoted_commas_stay_in_one_field() {
    let text = "\"t, s\",y\n0,1\n1,2\n";
    let cols = parse(text, &["t, s", "y"]).unwrap();
    assert_eq!(cols, vec![vec![0.0, 1.0], vec![1.0, 2.0]]);
}

#[test]
fn no_columns_requested_still_checks_rows() {
    assert_eq!(parse("a,b\n1,2\n", &[]).unwrap(), Vec::<Vec<f64>>::new());
    assert!(matches!(
        parse("a,b\n1\n", &[]),
        Err(IoError::TooFewFields { .. })
    ));
}

// ----- errors -------------------------------------------------------------------------------

#[test]
fn empty_file() {
    for text in ["", "\n\n", "  \r\n \n"] {
        let err = parse(text, &["a"]).unwrap_err();
        assert!(matches!(err, IoError::Empty { .. }), "{err:?}");
        assert_eq!(err.to_string(), "data.csv: file is empty");
    }
}

#[test]
fn header_only() {
    for text in ["a,b", "a,b\n", "a,b\n\n  \n"] {
        let err = parse(text, &["a"]).unwrap_err();
        assert!(matches!(err, IoError::NoData { .. }), "{err:?}");
        assert_eq!(
            err.to_string(),
            "data.csv: file has a header row but no data rows"
        );
    }
}

#[test]
fn malformed_number() {
    let mut text = String::from("x,y\n");
    for i in 0..15 {
        text.push_str(&format!("{i},{i}.5\n"));
    }
    text.push_str("15,1.2.3\n16,0\n");
    let err = parse(&text, &["x", "y"]).unwrap_err();
    match &err {
        IoError::BadNumber {
            line, column, text, ..
        } => {
            assert_eq!((*line, column.as_str(), text.as_str()), (17, "y", "1.2.3"));
        }
        other => panic!("unexpected error {other:?}"),
    }
    assert_eq!(
        err.to_string(),
        "data.csv line 17: column \"y\": \"1.2.3\" is not a number"
    );
    // The same text in a column that is not requested is fine.
    assert_eq!(parse(&text, &["x"]).unwrap()[0].len(), 17);
}

#[test]
fn too_few_fields() {
    let err = parse("a,b,c\n1,2,3\n4,5\n", &["a"]).unwrap_err();
    match &err {
        IoError::TooFewFields {
            line,
            expected,
            found,
            ..
        } => assert_eq!((*line, *expected, *found), (3, 3, 2)),
        other => panic!("unexpected error {other:?}"),
    }
    assert_eq!(err.to_string(), "data.csv line 3: 2 fields, expected 3");
}

#[test]
fn too_many_fields() {
    let err = parse("a,b\n1,2\n4,5,6\n", &["a"]).unwrap_err();
    assert!(
        matches!(
            err,
            IoError::TooManyFields {
                line: 3,
                expected: 2,
                found: 3,
                ..
            }
        ),
        "{err:?}"
    );
    // Extra *empty* fields are fine.
    assert_eq!(parse("a,b\n1,2,,\n", &["b"]).unwrap(), vec![vec![2.0]]);
}

#[test]
fn empty_requested_cell() {
    let err = parse("a,b\n1,2\n,3\n", &["a", "b"]).unwrap_err();
    assert!(matches!(err, IoError::EmptyCell { line: 3, .. }), "{err:?}");
    assert_eq!(err.to_string(), "data.csv line 3: column \"a\" is empty");
}

#[test]
fn non_finite_values() {
    for (cell, what) in [
        ("NaN", "NaN"),
        ("nan", "NaN"),
        ("inf", "inf"),
        ("-Infinity", "-inf"),
        ("1e400", "inf"),
    ] {
        let text = format!("a,b\n1,2\n3,{cell}\n");
        let err = parse(&text, &["a", "b"]).unwrap_err();
        match &err {
            IoError::NonFinite { line, column, .. } => {
                assert_eq!((*line, column.as_str()), (3, "b"));
            }
            other => panic!("unexpected error {other:?} for {cell}"),
        }
        assert_eq!(
            err.to_string(),
            format!("data.csv line 3: column \"b\": {what} is not a finite number")
        );
    }
}

#[test]
fn blank_lines_inside_data() {
    let err = parse("a\n1\n\n2\n", &["a"]).unwrap_err();
    assert!(matches!(err, IoError::BlankLine { line: 3, .. }), "{err:?}");
    let err = parse("\na\n1\n", &["a"]).unwrap_err();
    assert!(matches!(err, IoError::BlankLine { line: 1, .. }), "{err:?}");
}

#[test]
fn duplicate_requested_column() {
    let err = parse("a,b,a\n1,2,3\n", &["a"]).unwrap_err();
    assert!(matches!(err, IoError::DuplicateColumn { .. }), "{err:?}");
    // A duplicate that is not requested does no harm.
    assert_eq!(parse("a,b,a\n1,2,3\n", &["b"]).unwrap(), vec![vec![2.0]]);
}

// ----- writing ------------------------------------------------------------------------------

#[test]
fn write_read_round_trip_is_exact() {
    let dir = scratch("roundtrip");
    let p = dir.join("out.csv");
    let mut x = vec![
        0.0,
        -0.0,
        1.0 / 3.0,
        -2.0 / 7.0,
        1e-300,
        -1e300,
        f64::MAX,
        f64::MIN_POSITIVE,
        5e-324,
        0.1 + 0.2,
        123_456_789.123_456_78,
        1e-5,
        9_999_999_999_999_998.0,
    ];
    let mut state = 0x2545_f491_4f6c_dd1d_u64;
    for _ in 0..200 {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        let bits = state;
        let v = f64::from_bits(bits);
        if v.is_finite() {
            x.push(v);
        }
        x.push((bits >> 11) as f64 / (1u64 << 53) as f64 * 20.0 - 10.0);
    }
    let y: Vec<f64> = x.iter().map(|v| -v * 0.5).collect();
    write_columns(&p, &["x", "y, scaled"], &[&x[..], &y[..]]).unwrap();
    let back = read_columns(&p, &["x", "y, scaled"]).unwrap();
    assert_eq!(back[0].len(), x.len());
    for (a, b) in back[0].iter().zip(&x).chain(back[1].iter().zip(&y)) {
        assert_eq!(a.to_bits(), b.to_bits(), "{a} vs {b}");
    }
    let text = std::fs::read_to_string(&p).unwrap();
    assert!(text.starts_with("x,\"y, scaled\"\n0,-0\n"), "{text}");
    assert!(text.contains("\n1e-300,-5e-301\n"), "no exponent form");
}

#[test]
fn write_to_a_writer() {
    let mut buf = Vec::new();
    let cols = vec![vec![1.0, 2.5], vec![-3.0, 0.125]];
    write_columns_to("mem", &mut buf, &["u", "y"], &cols).unwrap();
    assert_eq!(String::from_utf8(buf).unwrap(), "u,y\n1,-3\n2.5,0.125\n");
}

#[test]
fn write_errors() {
    let mut buf = Vec::new();
    let err =
        write_columns_to("o.csv", &mut buf, &["a", "b"], &[vec![1.0, 2.0], vec![1.0]]).unwrap_err();
    assert!(matches!(err, IoError::InvalidColumns { .. }), "{err:?}");
    let err = write_columns_to("o.csv", &mut buf, &["a"], &[vec![1.0], vec![1.0]]).unwrap_err();
    assert!(matches!(err, IoError::InvalidColumns { .. }), "{err:?}");
    let err = write_columns_to("o.csv", &mut buf, &["a\"b"], &[vec![1.0]]).unwrap_err();
    assert!(matches!(err, IoError::InvalidColumns { .. }), "{err:?}");
    let err =
        write_columns_to("o.csv", &mut buf, &["a", "a"], &[vec![1.0], vec![1.0]]).unwrap_err();
    assert!(matches!(err, IoError::InvalidColumns { .. }), "{err:?}");
    let err = write_columns_to(
        "o.csv",
        &mut buf,
        &["a", "b"],
        &[vec![1.0, 2.0], vec![1.0, f64::NAN]],
    )
    .unwrap_err();
    assert!(matches!(err, IoError::NonFinite { line: 3, .. }), "{err:?}");
    assert_eq!(
        err.to_string(),
        "o.csv line 3: column \"b\": NaN is not a finite number"
    );
    let err = write_columns("/nonexistent/dir/o.csv", &["a"], &[vec![1.0]]).unwrap_err();
    assert!(
        matches!(
            err,
            IoError::File(FileError {
                action: FileAction::Write,
                ..
            })
        ),
        "{err:?}"
    );
}

// ----- delimiters and comments --------------------------------------------------------------

fn parse_with(text: &str, delimiter: Option<Delimiter>) -> Result<Vec<Vec<f64>>, IoError> {
    let options = CsvOptions {
        delimiter,
        ..CsvOptions::default()
    };
    parse_table("data.csv", text, &["u", "y"], &options).map(|t| t.columns)
}

#[test]
fn a_decimal_comma_reads_with_semicolons_and_the_other_notation_is_refused() {
    let comma = CsvOptions {
        decimal: Decimal::Comma,
        ..CsvOptions::default()
    };
    let text = "# a logger\nt;u [V];y\n0,00;-1;0,5\n0,01;1,25;-2,5e-1\n";
    let t = parse_table("d.csv", text, &["u", "y", "t"], &comma).unwrap();
    assert_eq!(
        t.columns,
        vec![vec![-1.0, 1.25], vec![0.5, -0.25], vec![0.0, 0.01]]
    );
    assert_eq!(t.units, vec![Some("V".to_string()), None, None]);
    // Tabs in the header are kept as the delimiter.
    let tabs = "u\ty\n1,5\t2\n";
    let t = parse_table("d.csv", tabs, &["u", "y"], &comma).unwrap();
    assert_eq!(t.columns, vec![vec![1.5], vec![2.0]]);
    // Read with a decimal point, the comma is named with the option.
    let e = parse_table("d.csv", text, &["u", "y"], &CsvOptions::default()).unwrap_err();
    assert!(matches!(e, IoError::DecimalComma { line: 3, .. }), "{e}");
    assert_eq!(
        e.to_string(),
        "d.csv line 3: column \"y\": \"0,5\" has a decimal comma: give --decimal comma \
         (fields then separated by `;`), or write the number as 3.25"
    );
    // A point under --decimal comma (a thousands separator, or the other notation).
    let e = parse_table("d.csv", "u;y\n1.250,5;2\n", &["u", "y"], &comma).unwrap_err();
    assert!(matches!(e, IoError::DecimalPoint { line: 2, .. }), "{e}");
    // `,` as the delimiter cannot hold decimal commas.
    let both = CsvOptions {
        delimiter: Some(Delimiter::Comma),
        decimal: Decimal::Comma,
    };
    let e = parse_table("d.csv", "u,y\n1,2\n", &["u", "y"], &both).unwrap_err();
    assert!(matches!(e, IoError::DecimalCommaDelimiter { .. }), "{e}");
}

#[test]
fn a_column_name_with_a_unit_answers_to_its_name() {
    assert_eq!(split_unit("u [V]"), ("u", Some("V")));
    assert_eq!(split_unit(" time (ms) "), ("time", Some("ms")));
    assert_eq!(split_unit("y [m/s²]"), ("y", Some("m/s²")));
    assert_eq!(split_unit("[V]"), ("[V]", None));
    assert_eq!(split_unit("u []"), ("u []", None));
    assert_eq!(split_unit("u"), ("u", None));
    let text = "u [V],y (deg),t\n1,2,0\n";
    let o = CsvOptions::default();
    let t = parse_table("d.csv", text, &["y", "u"], &o).unwrap();
    assert_eq!(t.columns, vec![vec![2.0], vec![1.0]]);
    assert_eq!(
        t.units,
        vec![Some("deg".to_string()), Some("V".to_string())]
    );
    // Asked for as written, the unit is still read.
    let t = parse_table("d.csv", text, &["u [V]"], &o).unwrap();
    assert_eq!(t.units, vec![Some("V".to_string())]);
    // Two columns of the same name in different units are ambiguous.
    let e = parse_table("d.csv", "u [V],u [mV],y\n1,2,3\n", &["u"], &o).unwrap_err();
    assert!(matches!(e, IoError::DuplicateColumn { .. }), "{e}");
    // The row-by-row reader reads the same units and decimal commas.
    let mut s = CsvStream::new(
        "d.csv",
        "u [V];y [mm]\n1,5;2\n".as_bytes(),
        &["u", "y"],
        &CsvOptions {
            decimal: Decimal::Comma,
            ..CsvOptions::default()
        },
    )
    .unwrap();
    assert_eq!(
        s.units(),
        vec![Some("V".to_string()), Some("mm".to_string())]
    );
    assert_eq!(s.next_row().unwrap(), Some((2, vec![1.5, 2.0])));
    assert_eq!(
        header_names("d.csv", "# c\n\"a\";b [s]\n1;2\n", &o).unwrap(),
        vec!["a".to_string(), "b [s]".to_string()]
    );
}

#[test]
fn delimiter_is_sniffed_from_the_header() {
    let want = vec![vec![1.5, -2.0], vec![3.25, 4.0]];
    for text in [
        "u,y\n1.5,3.25\n-2,4\n",
        "u;y\n1.5;3.25\n-2;4\n",
        "u\ty\n1.5\t3.25\n-2\t4\n",
        "\"u\";\"y\"\r\n1.5;3.25\r\n-2;4\r\n",
    ] {
        assert_eq!(parse_with(text, None).unwrap(), want, "{text:?}");
    }
    assert_eq!(Delimiter::sniff("a\tb,c"), Delimiter::Tab);
    assert_eq!(Delimiter::sniff("a;b,c"), Delimiter::Comma);
    assert_eq!(Delimiter::sniff("a;b"), Delimiter::Semicolon);
    assert_eq!(Delimiter::sniff("a b"), Delimiter::Comma);
}

#[test]
fn a_given_delimiter_overrides_the_sniffing() {
    // A header with a comma inside a name would sniff as `,`; given `;`, it is one name.
    let text = "\"u, V\";y\n1;2\n";
    let cols = parse_table(
        "d.csv",
        text,
        &["u, V", "y"],
        &CsvOptions {
            delimiter: Some(Delimiter::Semicolon),
            ..CsvOptions::default()
        },
    )
    .unwrap();
    assert_eq!(cols.columns, vec![vec![1.0], vec![2.0]]);
    // The wrong delimiter: one column named "u;y", so "u" is missing, named with the header.
    let err = parse_with("u;y\n1;2\n", Some(Delimiter::Comma)).unwrap_err();
    assert_eq!(
        err.to_string(),
        "data.csv line 1: no column \"u\" (columns are \"u;y\")"
    );
}

#[test]
fn decimal_commas_are_not_numbers_but_name_the_option_that_reads_them() {
    let err = parse_with("u;y\n1,5;2\n", None).unwrap_err();
    assert_eq!(
        err.to_string(),
        "data.csv line 2: column \"u\": \"1,5\" has a decimal comma: give --decimal comma \
         (fields then separated by `;`), or write the number as 3.25"
    );
    // A comma that makes no number in either notation is not a number.
    let err = parse_with("u;y\n1,5,5;2\n", None).unwrap_err();
    assert_eq!(
        err.to_string(),
        "data.csv line 2: column \"u\": \"1,5,5\" is not a number"
    );
}

#[test]
fn comment_lines_are_skipped_and_lines_still_counted() {
    let text = "# rig 3, 2024-05-01\n# u in V\nu,y\n1,2\n# a note\n3,4\n5,x\n";
    let err = parse_with(text, None).unwrap_err();
    assert_eq!(
        err.to_string(),
        "data.csv line 7: column \"y\": \"x\" is not a number"
    );
    let ok = "# rig 3\nu;y\n1;2\n# a note\n3;4\n# end\n\n";
    let t = parse_table("d.csv", ok, &["u", "y"], &CsvOptions::default()).unwrap();
    assert_eq!(t.columns, vec![vec![1.0, 3.0], vec![2.0, 4.0]]);
    assert_eq!(t.lines, vec![3, 5]);
    // Only comments: as empty as an empty file.
    let err = parse_with("# nothing\n# here\n", None).unwrap_err();
    assert!(matches!(err, IoError::Empty { .. }), "{err:?}");
    // The header after comments: a missing column names the header's line.
    let err = parse_with("# c\nu,z\n1,2\n", None).unwrap_err();
    assert!(
        err.to_string()
            .starts_with("data.csv line 2: no column \"y\""),
        "{err}"
    );
}

#[test]
fn a_blank_line_between_rows_is_an_error_with_comments_too() {
    let err = parse_with("u\ty\n1\t2\n# c\n\n3\t4\n", None).unwrap_err();
    assert_eq!(err.to_string(), "data.csv line 4: unexpected blank line");
}

#[test]
fn an_unterminated_quote_is_a_clean_error() {
    let r = parse_with("u,y\n1,\"2\n3,4\n", None);
    let err = r.unwrap_err();
    assert!(err.to_string().starts_with("data.csv line "), "{err}");
}
