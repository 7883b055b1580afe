//! The signals' units from where a user or a file states them: the `--input-unit` /
//! `--output-unit` flags, a model file, a plant specification, and a record's header comments
//! `# input unit = V` / `# output unit = deg` (as `hsid simulate` writes them,
//! [`crate::simulate::header`]). Every source that states them must agree.

use super::header::header_comments;
use std::fmt;
use std::path::{Path, PathBuf};

use crate::model_file::Units;

/// Where the units were stated.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum UnitsOrigin {
    /// The `--input-unit` and `--output-unit` flags.
    Flags,
    /// The `units` of a model file.
    ModelFile(PathBuf),
    /// The `units` of a plant specification.
    PlantSpec(PathBuf),
    /// A record's header comments `# input unit = …`, `# output unit = …`.
    Comment(PathBuf),
    /// A record's column names `u [V]`, `y [deg]`.
    ColumnNames(PathBuf),
}

impl fmt::Display for UnitsOrigin {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Flags => write!(f, "--input-unit/--output-unit"),
            Self::ModelFile(p) => write!(f, "the units of {}", p.display()),
            Self::PlantSpec(p) => write!(f, "the units of {}", p.display()),
            Self::Comment(p) => write!(f, "the unit comments of {}", p.display()),
            Self::ColumnNames(p) => write!(f, "the column names of {}", p.display()),
        }
    }
}

/// Units that cannot be used.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum UnitsError {
    /// A header comment `# input unit =` (or output) with nothing after the `=`.
    #[error(
        "{file} line {line}: a unit comment without a unit; write e.g. `# input unit = V` or drop the line"
    )]
    EmptyComment {
        /// The record.
        file: PathBuf,
        /// 1-based line of the comment.
        line: usize,
    },
    /// The header states one signal's unit but not the other's.
    #[error(
        "{file} line {line}: the header states the {stated} unit but not the {other} unit; \
         add `# {other} unit = …` or drop the line",
        other = other_signal(.stated)
    )]
    HalfComment {
        /// The record.
        file: PathBuf,
        /// 1-based line of the comment that is there.
        line: usize,
        /// The signal whose unit is stated (`"input"` or `"output"`).
        stated: &'static str,
    },
    /// A header comment's unit holds a character a unit may not hold.
    #[error("{file} line {line}: the {signal} unit {unit:?}: {error}")]
    BadCharacter {
        /// The record.
        file: PathBuf,
        /// 1-based line of the comment.
        line: usize,
        /// `"input"` or `"output"`.
        signal: &'static str,
        /// The unit as stated.
        unit: String,
        /// The character refused.
        error: UnitCharError,
    },
    /// The column names state one signal's unit (`u [V]`) but not the other's (`y`).
    #[error(
        "{file}: the header states a unit for \"{stated}\" but none for \"{missing}\": \
         write it as `{missing} [unit]`, or give --input-unit and --output-unit"
    )]
    HalfColumnNames {
        /// The record.
        file: PathBuf,
        /// The header name with a unit.
        stated: String,
        /// The header name without one.
        missing: String,
    },
    /// A column name's unit holds a character a unit may not hold.
    #[error("{file}: the {signal} unit {unit:?} of the header: {error}")]
    BadColumnUnit {
        /// The record.
        file: PathBuf,
        /// `"input"` or `"output"`.
        signal: &'static str,
        /// The unit as stated.
        unit: String,
        /// The character refused.
        error: UnitCharError,
    },
    /// Two sources state different units.
    #[error(
        "{} give u in {} and y in {} but {} give u in {} and y in {}; drop one or make them agree",
        .first.0, .first.1.input, .first.1.output, .second.0, .second.1.input, .second.1.output
    )]
    Disagree {
        /// The first source and its units.
        first: Box<(UnitsOrigin, Units)>,
        /// The second source and its units.
        second: Box<(UnitsOrigin, Units)>,
    },
}

/// A character a unit's name may not hold: a control character (below U+0020, or U+007F: a
/// line break, a tab) or a double quote. A unit is written into CSV header comments, JSON,
/// SVG and HTML as it is given; these characters break a line or a quoted string there, so
/// they are refused wherever a unit is stated (a flag, a model file, a header comment).
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error(
    "{}: a unit is plain text without double quotes or control characters, e.g. V or deg",
    describe_char(*.0)
)]
pub struct UnitCharError(pub char);

/// The first character of `unit` that a unit may not hold ([`UnitCharError`]).
pub fn check_unit_text(unit: &str) -> Result<(), UnitCharError> {
    match unit.chars().find(|&c| c == '"' || c < ' ' || c == '\u{7f}') {
        Some(c) => Err(UnitCharError(c)),
        None => Ok(()),
    }
}

/// `a double quote` or `the control character U+000A`.
fn describe_char(c: char) -> String {
    match c {
        '"' => "it holds a double quote (\")".to_string(),
        c => format!("it holds the control character U+{:04X}", u32::from(c)),
    }
}

/// The signal whose unit a half comment leaves out.
fn other_signal(stated: &str) -> &'static str {
    if stated == "input" { "output" } else { "input" }
}

/// The units a record's header comments state (the lines starting with `#` before the first
/// other line): `# input unit = V` and `# output unit = deg`, both or neither.
pub fn units_from_comments(source: &Path, text: &str) -> Result<Option<Units>, UnitsError> {
    let (mut input, mut output) = (None, None);
    for c in header_comments(text) {
        let (slot, signal) = match c.key {
            "input unit" => (&mut input, "input"),
            "output unit" => (&mut output, "output"),
            _ => continue,
        };
        if c.value.is_empty() {
            return Err(UnitsError::EmptyComment {
                file: source.to_path_buf(),
                line: c.line,
            });
        }
        check_unit_text(c.value).map_err(|error| UnitsError::BadCharacter {
            file: source.to_path_buf(),
            line: c.line,
            signal,
            unit: c.value.to_string(),
            error,
        })?;
        *slot = Some((c.line, c.value.to_string()));
    }
    let half = |line, stated| UnitsError::HalfComment {
        file: source.to_path_buf(),
        line,
        stated,
    };
    match (input, output) {
        (None, None) => Ok(None),
        (Some((line, _)), None) => Err(half(line, "input")),
        (None, Some((line, _))) => Err(half(line, "output")),
        (Some((_, input)), Some((_, output))) => Ok(Some(Units { input, output })),
    }
}

/// The units a record's column names state, `u [V]` and `y [deg]` (see
/// [`split_unit`](crate::io::split_unit)): both or neither; `input` and `output` are the
/// units of the input and output columns and `names` their header names, for the errors.
pub fn units_from_names(
    source: &Path,
    names: [&str; 2],
    input: Option<&str>,
    output: Option<&str>,
) -> Result<Option<Units>, UnitsError> {
    let bad = |signal: &'static str, unit: &str, error| UnitsError::BadColumnUnit {
        file: source.to_path_buf(),
        signal,
        unit: unit.to_string(),
        error,
    };
    for (signal, unit) in [("input", input), ("output", output)] {
        if let Some(unit) = unit {
            check_unit_text(unit).map_err(|e| bad(signal, unit, e))?;
        }
    }
    match (input, output) {
        (None, None) => Ok(None),
        (Some(i), Some(o)) => Ok(Some(Units {
            input: i.to_string(),
            output: o.to_string(),
        })),
        (i, _) => Err(UnitsError::HalfColumnNames {
            file: source.to_path_buf(),
            stated: names[usize::from(i.is_none())].to_string(),
            missing: names[usize::from(i.is_some())].to_string(),
        }),
    }
}

/// The units every source in `stated` agrees on (`None` when none states them), or the first
/// disagreement.
pub fn resolve_units(stated: &[(UnitsOrigin, Units)]) -> Result<Option<Units>, UnitsError> {
    let Some(first) = stated.first() else {
        return Ok(None);
    };
    match stated.iter().find(|(_, u)| *u != first.1) {
        Some(other) => Err(UnitsError::Disagree {
            first: Box::new(first.clone()),
            second: Box::new(other.clone()),
        }),
        None => Ok(Some(first.1.clone())),
    }
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;
    use crate::simulate::header;

    fn units(i: &str, o: &str) -> Units {
        Units {
            input: i.into(),
            output: o.into(),
        }
    }

    #[test]
    fn the_simulators_header_reads_back() {
        let mut text: String = header(Some(0.01), Some("V"), Some("rad/s"))
            .iter()
            .map(|l| format!("# {l}\n"))
            .collect();
        text.push_str("u,y\n1,2\n# input unit = A\n");
        let got = units_from_comments(Path::new("r.csv"), &text).unwrap();
        assert_eq!(got, Some(units("V", "rad/s")));
    }

    #[test]
    fn a_unit_with_a_quote_or_a_control_character_is_refused() {
        assert_eq!(check_unit_text("m/s²"), Ok(()));
        assert_eq!(check_unit_text("V\""), Err(UnitCharError('"')));
        assert_eq!(check_unit_text("a\tb"), Err(UnitCharError('\t')));
        assert_eq!(check_unit_text("x\u{7f}"), Err(UnitCharError('\u{7f}')));
        let text = "# input unit = V\"\n# output unit = deg\nu,y\n";
        let e = units_from_comments(Path::new("r.csv"), text).unwrap_err();
        assert_eq!(
            e.to_string(),
            "r.csv line 1: the input unit \"V\\\"\": it holds a double quote (\"): a unit is \
             plain text without double quotes or control characters, e.g. V or deg"
        );
    }

    #[test]
    fn column_names_state_both_units_or_neither() {
        let p = Path::new("r.csv");
        let names = ["u [V]", "y"];
        assert_eq!(units_from_names(p, names, None, None), Ok(None));
        assert_eq!(
            units_from_names(p, names, Some("V"), Some("mm")),
            Ok(Some(units("V", "mm")))
        );
        let e = units_from_names(p, names, Some("V"), None).unwrap_err();
        assert_eq!(
            e.to_string(),
            "r.csv: the header states a unit for \"u [V]\" but none for \"y\": write it as \
             `y [unit]`, or give --input-unit and --output-unit"
        );
    }

    #[test]
    fn no_comment_no_units() {
        let got = units_from_comments(Path::new("r.csv"), "# ts = 1 s\nu,y\n1,2\n").unwrap();
        assert_eq!(got, None);
    }

    #[test]
    fn half_or_empty_comments_are_errors() {
        let e = units_from_comments(Path::new("r.csv"), "# ts = 1 s\n# output unit = deg\nu,y\n");
        assert_eq!(
            e,
            Err(UnitsError::HalfComment {
                file: "r.csv".into(),
                line: 2,
                stated: "output"
            })
        );
        assert!(e.unwrap_err().to_string().contains("# input unit = …"));
        let e = units_from_comments(Path::new("r.csv"), "# input unit =  \nu,y\n");
        assert_eq!(
            e,
            Err(UnitsError::EmptyComment {
                file: "r.csv".into(),
                line: 1
            })
        );
    }

    #[test]
    fn sources_must_agree() {
        let a = (UnitsOrigin::Flags, units("V", "deg"));
        let b = (UnitsOrigin::Comment("r.csv".into()), units("V", "deg"));
        let c = (UnitsOrigin::ModelFile("m.json".into()), units("V", "rad"));
        assert_eq!(resolve_units(&[]), Ok(None));
        assert_eq!(
            resolve_units(&[a.clone(), b.clone()]),
            Ok(Some(units("V", "deg")))
        );
        let e = resolve_units(&[a.clone(), b, c.clone()]).unwrap_err();
        assert_eq!(
            e,
            UnitsError::Disagree {
                first: Box::new(a),
                second: Box::new(c)
            }
        );
        assert!(e.to_string().contains("m.json give u in V and y in rad"));
    }
}
