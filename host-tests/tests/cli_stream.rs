//! `hsid identify --stream` (row by row, bounded memory) against the whole-record reader, and
//! the whole-record reader's refusal of a file larger than it holds.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::fs::File;

use hsid_host::io::MAX_RECORD_BYTES;
use hsid_host::model_file::ModelFile;
use hsid_host::paper::{Case, PaperConfig, experiment};

use crate::common;

use common::{Scratch, identify, p};

/// The paper's settings, fixed (segments and horizons are otherwise chosen from the data).
const FIXED: [&str; 8] = ["--segments", "7", "--f", "10", "--p", "10", "--hold", "300"];

/// The paper's backlash experiment (run 0, 10 dB SNR) as `u,y` text, with a comment line
/// between rows and Windows line ends, so that the two readers' tolerances are exercised.
fn record() -> String {
    let e = experiment(Case::Backlash, &PaperConfig::default(), 0).unwrap();
    let mut text = String::from("# the paper's backlash case\r\nu,y\r\n");
    for (k, (u, y)) in e.u.iter().zip(&e.y).enumerate() {
        if k == 1000 {
            text.push_str("# a comment between rows\r\n");
        }
        text.push_str(&format!("{u:?},{y:?}\r\n"));
    }
    text
}

#[test]
fn streamed_model_equals_the_whole_record_subspace_model_bit_for_bit() {
    let dir = Scratch::new("stream-equal");
    let data = dir.write("data.csv", &record());
    let (whole, streamed) = (dir.join("whole.json"), dir.join("streamed.json"));

    let mut args = FIXED.to_vec();
    args.extend(["--no-refine", "--json", p(&whole)]);
    identify(&data, &args).success();
    let mut args = FIXED.to_vec();
    args.extend(["--stream", "--json", p(&streamed)]);
    let run = identify(&data, &args).success();
    assert!(
        run.stdout.contains("streamed 4319 samples"),
        "{}",
        run.stdout
    );

    let (a, b) = (
        ModelFile::load(&whole).unwrap(),
        ModelFile::load(&streamed).unwrap(),
    );
    assert_eq!(a.order, 2);
    // The whole-record command also fits a noise model to the residual (a second pass).
    assert!(a.noise.is_some() && b.noise.is_none());
    let a = ModelFile { noise: None, ..a };
    assert_eq!(a, b, "the streamed model differs from the whole-record one");
}

#[test]
fn a_bad_row_stops_the_stream_with_its_line_and_writes_no_model() {
    let dir = Scratch::new("stream-bad-row");
    let mut text = record();
    // A bad row inserted as line 2003 (comment on 1, header on 2, comment on 1003).
    let at = text.match_indices("\r\n").nth(2001).unwrap().0 + 2;
    text.insert_str(at, "0.5,oops\r\n");
    let data = dir.write("data.csv", &text);
    let model = dir.join("model.json");
    let mut args = FIXED.to_vec();
    args.extend(["--stream", "--json", p(&model)]);
    identify(&data, &args).clean_error(&["data.csv", "line 2003", "oops"]);
    assert!(
        !model.exists(),
        "a model was written from part of the record"
    );
}

#[test]
fn a_file_beyond_the_whole_record_limit_is_refused_with_its_size_and_the_way_out() {
    let dir = Scratch::new("stream-too-large");
    let data = dir.join("big.csv");
    // Sparse: no disk is used, and nothing of it may be read.
    File::create(&data)
        .unwrap()
        .set_len(MAX_RECORD_BYTES + 1)
        .unwrap();
    let size = format!("{} bytes", MAX_RECORD_BYTES + 1);
    let limit = format!("{MAX_RECORD_BYTES} bytes");
    identify(&data, &FIXED).clean_error(&["big.csv", &size, &limit, "--stream"]);
    // Row by row, a file without line breaks is refused at its first line, in bounded memory.
    let mut args = FIXED.to_vec();
    args.push("--stream");
    identify(&data, &args).clean_error(&["big.csv", "line 1", "longer than 1048576 bytes"]);
}

#[test]
fn stream_refuses_what_needs_the_whole_record() {
    let dir = Scratch::new("stream-refusals");
    let data = dir.write("data.csv", "u,y\n0,0\n");
    let mut args = FIXED.to_vec();
    args.extend(["--stream", "--data", p(&data)]);
    identify(&data, &args).clean_error(&["--stream reads one record, 2 given"]);
    let args = ["--stream", "--segments", "auto"];
    identify(&data, &args).clean_error(&["--segments auto", "--stream"]);
    let args = ["--stream", "--fit", "simulation"];
    identify(&data, &args).clean_error(&["--fit simulation needs the whole record"]);
    // The increments need the whole record: refused, not silently identified as they are.
    let args = ["--stream", "--integrating", "yes"];
    identify(&data, &args).clean_error(&["--integrating yes", "not --stream"]);
}
