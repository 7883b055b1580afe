//! The messages of the errors whose text depends on an optional part or a list, byte for byte:
//! the user reads them, and other tests and the docs compare them.
#![allow(clippy::unwrap_used)]

use std::path::PathBuf;

use hsid_host::choose::ChooseError;
use hsid_host::diagnose::error::DiagnoseError;
use hsid_host::identify::IdentifyError;
use hsid_host::io::{FileError, IoError, TooLarge};
use hsid_host::model_file::{FORMAT, ModelFileError};
use hsid_host::plot::PlotError;
use hsid_host::units::{Origin, TimeError, UnitsError};

fn path() -> PathBuf {
    PathBuf::from("data/r.csv")
}

#[test]
fn optional_parts_are_written_or_left_out() {
    let series = |label: Option<&str>| PlotError::LengthMismatch {
        series: 2,
        label: label.map(str::to_owned),
        detail: "x has 10 values, y has 9".into(),
    };
    assert_eq!(
        series(Some("fit")).to_string(),
        "series 2 (\"fit\"): x has 10 values, y has 9"
    );
    assert_eq!(
        series(None).to_string(),
        "series 2: x has 10 values, y has 9"
    );

    let big = |bytes| TooLarge {
        path: path(),
        bytes,
        limit: 100,
    };
    assert_eq!(
        big(Some(101)).to_string(),
        "data/r.csv: 101 bytes, larger than the 100 bytes accepted"
    );
    assert_eq!(
        big(None).to_string(),
        "data/r.csv: more than the 100 bytes accepted"
    );

    let malformed = |line| IoError::Malformed {
        path: path(),
        line,
        reason: "unclosed quote".into(),
    };
    assert_eq!(
        malformed(Some(7)).to_string(),
        "data/r.csv line 7: malformed CSV: unclosed quote"
    );
    assert_eq!(
        malformed(None).to_string(),
        "data/r.csv: malformed CSV: unclosed quote"
    );
    let missing = IoError::MissingColumn {
        path: path(),
        line: 1,
        column: "y".into(),
        available: vec!["t".into(), "u".into()],
    };
    assert_eq!(
        missing.to_string(),
        "data/r.csv line 1: no column \"y\" (columns are \"t\", \"u\")"
    );

    let read = FileError::read(&path(), std::io::Error::other("gone"));
    assert_eq!(read.to_string(), "data/r.csv: cannot read file: gone");
    let write = FileError::write(&path(), std::io::Error::other("full"));
    assert_eq!(write.to_string(), "data/r.csv: cannot write file: full");

    let version = |found: Option<&str>| ModelFileError::Version {
        path: "m.json".into(),
        found: found.map(str::to_owned),
    };
    assert_eq!(
        version(None).to_string(),
        format!(
            "m.json: no \"format\" key: the file is of the unversioned model layout, this hsid reads \"{FORMAT}\"; identify the model again with this hsid (its --json)"
        )
    );
    assert_eq!(
        version(Some("hsid-model/9")).to_string(),
        format!(
            "m.json: model format \"hsid-model/9\", this hsid reads \"{FORMAT}\"; write the model with the hsid that reads it, or identify it again with this one"
        )
    );
    let json = |location: Option<&str>| ModelFileError::Json {
        path: "m.json".into(),
        location: location.map(str::to_owned),
        source: serde_json::from_str::<u8>("x").unwrap_err(),
    };
    let cause = serde_json::from_str::<u8>("x").unwrap_err().to_string();
    assert_eq!(json(None).to_string(), format!("m.json: {cause}"));
    assert_eq!(
        json(Some("A[1][0]")).to_string(),
        format!("m.json: field A[1][0]: {cause}")
    );

    let knot = |value, segment| DiagnoseError::KnotNotVisited {
        knot: 3,
        value,
        segment,
    };
    assert_eq!(
        knot(Some(0.5), Some((0.5, 1.0))).to_string(),
        "static nonlinearity: the basis function of knot 3 (u = 0.5) is never excited: the input never visits [0.5, 1]; move or remove that knot (--knots, --segments, --select-segments), or record data whose input covers that range"
    );
    assert_eq!(
        knot(None, None).to_string(),
        "static nonlinearity: the basis function of knot 3 is never excited: the input never visits the segments next to it; move or remove that knot (--knots, --segments, --select-segments), or record data whose input covers that range"
    );
}

#[test]
fn lists_and_advice_are_written_as_before() {
    let refine = ChooseError::Refine(vec![(2, "diverged".into()), (3, "singular".into())]);
    assert_eq!(
        refine.to_string(),
        "the refinement failed at every candidate order (order 2: diverged; order 3: singular): identify without refinement (--no-refine) to see the subspace model"
    );

    let integrating = hsid::Error::IntegratingModel;
    assert_eq!(
        IdentifyError::Core(integrating).to_string(),
        format!(
            "{integrating}; if the plant integrates (voltage → position, a level loop), identify its stable part on the output's increments y(t) − y(t − 1) with one pole fixed at z = 1 (hsid identify --integrating; the borders are then the output's rate per sample)"
        )
    );
    let zero = hsid::Error::ZeroStaticGain;
    assert_eq!(
        IdentifyError::Core(zero).to_string(),
        format!(
            "{zero}; an estimate of more states than the record supports (a slowly sampled plant, an output curve) can also put a zero near z = 1: try a lower --order"
        )
    );

    let half = UnitsError::HalfComment {
        file: path(),
        line: 2,
        stated: "output",
    };
    assert_eq!(
        half.to_string(),
        "data/r.csv line 2: the header states the output unit but not the input unit; add `# input unit = …` or drop the line"
    );

    let uneven = TimeError::NotUniform {
        file: path(),
        line: 3,
        step: 0.0123456789,
        ts: 0.02,
    };
    assert_eq!(
        uneven.to_string(),
        "data/r.csv line 3: time step 0.0123457 differs from the mean step 0.0200000 by more than 0.1 %; the method needs uniform sampling (resample the record, split it at the gap into several --data files, or, for a logger's jittery clock, give --ts to ignore the time column)"
    );
    let disagree = TimeError::Disagree {
        first: (Origin::Flag, 0.01),
        second: (Origin::ModelFile("m.json".into()), 0.02),
    };
    assert_eq!(
        disagree.to_string(),
        "--ts gives a sample time of 0.01 s but the sample_time of m.json gives 0.02 s; drop one or make them agree"
    );
}
