//! The sample time: positive, uniform over a time column, and the same in every source that
//! states it (a flag, the record's time column, a model file, a plant specification).

use super::header::header_comments;
use std::fmt;
use std::path::{Path, PathBuf};

/// Relative tolerance of a time column's steps around their mean, and of two sources of the
/// sample time against each other: 0.1 %.
pub const TS_TOLERANCE: f64 = 1e-3;

/// Where a sample time was stated.
#[derive(Clone, Debug, PartialEq)]
pub enum Origin {
    /// The `--ts` flag.
    Flag,
    /// The time column of a record.
    TimeColumn(PathBuf),
    /// The `sample_time` of a model file.
    ModelFile(PathBuf),
    /// The `ts` of a plant specification.
    PlantSpec(PathBuf),
    /// A record's header comment `# ts = … s` (as `hsid simulate` writes it).
    Comment(PathBuf),
}

impl fmt::Display for Origin {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Flag => write!(f, "--ts"),
            Self::TimeColumn(p) => write!(f, "the time column of {}", p.display()),
            Self::ModelFile(p) => write!(f, "the sample_time of {}", p.display()),
            Self::PlantSpec(p) => write!(f, "the ts of {}", p.display()),
            Self::Comment(p) => write!(f, "the `# ts` comment of {}", p.display()),
        }
    }
}

/// A sample time that cannot be used.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum TimeError {
    /// Zero, negative or not finite.
    #[error("{origin}: sample time {value} s; it must be a positive number of seconds")]
    NotPositive {
        /// Where it was stated.
        origin: Origin,
        /// The value.
        value: f64,
    },
    /// A time column with fewer than two rows.
    #[error("{file}: the time column has fewer than two rows, so it gives no sample time")]
    TooShort {
        /// The record.
        file: PathBuf,
    },
    /// A time column that does not increase strictly.
    #[error(
        "{file} line {line}: time {value} does not increase (the row before has {previous}); \
         sort the record or drop the time column"
    )]
    NotIncreasing {
        /// The record.
        file: PathBuf,
        /// 1-based line of the offending row.
        line: usize,
        /// Its time.
        value: f64,
        /// The time of the row before.
        previous: f64,
    },
    /// A time column whose step differs from the mean step by more than [`TS_TOLERANCE`].
    #[error(
        "{file} line {line}: time step {} differs from the mean step {} by more than \
         {} %; the method needs uniform sampling (resample the record, or split it \
         at the gap into several --data files)",
        significant(*.step),
        significant(*.ts),
        TS_TOLERANCE * 100.0
    )]
    NotUniform {
        /// The record.
        file: PathBuf,
        /// 1-based line of the offending row.
        line: usize,
        /// The step to that row.
        step: f64,
        /// The mean step.
        ts: f64,
    },
    /// A header comment `# ts = … s` whose value is not a number.
    #[error(
        "{file} line {line}: the comment `{text}` states no sample time: write it as \
         `# ts = 0.01 s` (seconds) or remove it"
    )]
    BadComment {
        /// The record.
        file: PathBuf,
        /// 1-based line of the comment.
        line: usize,
        /// The comment's text.
        text: String,
    },
    /// Two sources state different sample times.
    #[error(
        "{} gives a sample time of {} s but {} gives {} s; drop one or make them agree",
        .first.0, .first.1, .second.0, .second.1
    )]
    Disagree {
        /// The first source and its value.
        first: (Origin, f64),
        /// The second source and its value.
        second: (Origin, f64),
    },
}

/// `v` with six significant digits (a time step read from text carries rounding noise).
fn significant(v: f64) -> String {
    let digits = 5 - v.abs().log10().floor().clamp(-300.0, 300.0) as i32;
    format!("{:.*}", digits.max(0) as usize, v)
}

/// `ts` if it is a positive finite number.
pub fn checked_ts(ts: f64, origin: Origin) -> Result<f64, TimeError> {
    if ts.is_finite() && ts > 0.0 {
        Ok(ts)
    } else {
        Err(TimeError::NotPositive { origin, value: ts })
    }
}

/// The sample time of a time column `t` (the mean step), checked strictly increasing and
/// uniform within [`TS_TOLERANCE`]; `lines` are the rows' 1-based lines, for the errors.
pub fn ts_from_column(source: PathBuf, t: &[f64], lines: &[usize]) -> Result<f64, TimeError> {
    let (Some(first), Some(last)) = (t.first(), t.last()) else {
        return Err(TimeError::TooShort { file: source });
    };
    if t.len() < 2 {
        return Err(TimeError::TooShort { file: source });
    }
    strictly_increasing(&source, t, lines)?;
    let line = |i: usize| lines.get(i).copied().unwrap_or(i + 1);
    let ts = (last - first) / (t.len() - 1) as f64;
    if let Some(i) = (1..t.len()).find(|&i| ((t[i] - t[i - 1]) - ts).abs() > TS_TOLERANCE * ts) {
        return Err(TimeError::NotUniform {
            file: source,
            line: line(i),
            step: t[i] - t[i - 1],
            ts,
        });
    }
    Ok(ts)
}

/// The sample time a record states in its header comments, the lines starting with `#`
/// before the first other line: `# ts = 0.01 s`, as `hsid simulate` writes it
/// ([`crate::simulate::header`]). `None` without such a line; a `# ts = … s` line whose value
/// is not a positive number is an error, not ignored.
pub fn ts_from_comments(source: &Path, text: &str) -> Result<Option<f64>, TimeError> {
    let Some(c) = header_comments(text).find(|c| c.key == "ts") else {
        return Ok(None);
    };
    let bad = || TimeError::BadComment {
        file: source.to_path_buf(),
        line: c.line,
        text: c.text.to_string(),
    };
    let number = c.value.strip_suffix('s').ok_or_else(bad)?;
    let ts: f64 = number.trim().parse().map_err(|_| bad())?;
    checked_ts(ts, Origin::Comment(source.to_path_buf())).map(Some)
}

/// Checks that a time column `t` increases strictly; `lines` are the rows' 1-based lines, for
/// the error.
pub(crate) fn strictly_increasing(
    source: &Path,
    t: &[f64],
    lines: &[usize],
) -> Result<(), TimeError> {
    match (1..t.len()).find(|&i| t[i] <= t[i - 1]) {
        None => Ok(()),
        Some(i) => Err(TimeError::NotIncreasing {
            file: source.to_path_buf(),
            line: lines.get(i).copied().unwrap_or(i + 1),
            value: t[i],
            previous: t[i - 1],
        }),
    }
}

/// The one sample time of all stated ones (each already checked positive): `None` when none
/// is stated, the first when all agree within [`TS_TOLERANCE`], else [`TimeError::Disagree`]
/// naming the first two that differ.
pub fn resolve_ts(stated: &[(Origin, f64)]) -> Result<Option<f64>, TimeError> {
    let Some((origin, ts)) = stated.first() else {
        return Ok(None);
    };
    match stated
        .iter()
        .find(|(_, v)| (v - ts).abs() > TS_TOLERANCE * ts.abs())
    {
        Some(other) => Err(TimeError::Disagree {
            first: (origin.clone(), *ts),
            second: other.clone(),
        }),
        None => Ok(Some(*ts)),
    }
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;

    fn lines(n: usize) -> Vec<usize> {
        (2..n + 2).collect()
    }

    #[test]
    fn a_uniform_column_gives_its_step() {
        let t: Vec<f64> = (0..101).map(|k| 0.5 + 0.01 * k as f64).collect();
        let ts = ts_from_column("r.csv".into(), &t, &lines(101)).unwrap();
        assert!((ts - 0.01).abs() < 1e-12, "{ts}");
    }

    #[test]
    fn a_repeated_time_is_not_increasing_and_names_its_line() {
        let t = [0.0, 0.1, 0.1, 0.3];
        let e = ts_from_column("r.csv".into(), &t, &lines(4)).unwrap_err();
        assert!(matches!(e, TimeError::NotIncreasing { line: 4, .. }), "{e}");
    }

    #[test]
    fn a_missing_sample_is_not_uniform_and_names_its_line() {
        // Steps 0.1, 0.1, 0.2, 0.1: mean 0.125, the first step already 20 % off.
        let t = [0.0, 0.1, 0.2, 0.4, 0.5];
        let e = ts_from_column("r.csv".into(), &t, &lines(5)).unwrap_err();
        assert!(matches!(e, TimeError::NotUniform { line: 3, .. }), "{e}");
        assert_eq!(e.to_string().lines().count(), 1);
    }

    #[test]
    fn zero_and_negative_sample_times_are_refused() {
        for v in [0.0, -0.01, f64::NAN] {
            assert!(checked_ts(v, Origin::Flag).is_err());
        }
        assert_eq!(checked_ts(0.01, Origin::Flag), Ok(0.01));
    }

    #[test]
    fn sources_must_agree_within_the_tolerance() {
        let col = Origin::TimeColumn("r.csv".into());
        assert_eq!(resolve_ts(&[]), Ok(None));
        let near = [(Origin::Flag, 0.01), (col.clone(), 0.010_000_5)];
        assert_eq!(resolve_ts(&near), Ok(Some(0.01)));
        let far = [(Origin::Flag, 0.01), (col, 0.02)];
        let e = resolve_ts(&far).unwrap_err();
        assert!(
            e.to_string().contains("--ts gives a sample time of 0.01 s"),
            "{e}"
        );
    }

    #[test]
    fn the_header_comment_of_a_simulated_record_states_its_sample_time() {
        let p = Path::new("sim.csv");
        let header = crate::simulate::header(Some(0.01), Some("V"), Some("deg"));
        let text = format!(
            "# {}\n# {}\n# {}\nu,y\n-1,0\n",
            header[0], header[1], header[2]
        );
        assert_eq!(ts_from_comments(p, &text), Ok(Some(0.01)));
        // Only the comments before the header count; other comments are free text.
        assert_eq!(
            ts_from_comments(p, "# a servo\n\n#ts=2e-3 s\nu,y\n"),
            Ok(Some(0.002))
        );
        assert_eq!(ts_from_comments(p, "u,y\n# ts = 0.01 s\n1,2\n"), Ok(None));
        assert_eq!(
            ts_from_comments(p, "# tsunami\n# units = V\nu,y\n"),
            Ok(None)
        );
        let e = ts_from_comments(p, "# note\n# ts = 10 ms\nu,y\n").unwrap_err();
        assert!(matches!(e, TimeError::BadComment { line: 2, .. }), "{e}");
        assert!(e.to_string().contains("# ts = 0.01 s"), "{e}");
        let e = ts_from_comments(p, "# ts = -1 s\n").unwrap_err();
        assert!(
            e.to_string().contains("the `# ts` comment of sim.csv"),
            "{e}"
        );
    }
}
