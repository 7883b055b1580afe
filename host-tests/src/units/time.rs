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
         {} %; the method needs uniform sampling (resample the record, split it \
         at the gap into several --data files, or, for a logger's jittery clock, give --ts \
         to ignore the time column)",
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
    /// A time column whose header states a unit that is not one of time read (`time [min]`).
    #[error(
        "{file}: the time column \"{column}\" is in {unit:?}, which is not s, ms or us: give \
         --time-unit s|ms|us for the numbers it holds, or --ts to ignore the column"
    )]
    UnknownUnit {
        /// The record.
        file: PathBuf,
        /// The column's header name.
        column: String,
        /// The unit it states.
        unit: String,
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

/// The unit of a time column: seconds unless its name or `--time-unit` states otherwise.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TimeUnit {
    /// Seconds (`s`).
    #[default]
    Seconds,
    /// Milliseconds (`ms`).
    Milliseconds,
    /// Microseconds (`us`, `µs`).
    Microseconds,
}

impl TimeUnit {
    /// Seconds per unit.
    pub fn seconds(self) -> f64 {
        match self {
            Self::Seconds => 1.0,
            Self::Milliseconds => 1e-3,
            Self::Microseconds => 1e-6,
        }
    }

    /// Units per second (1, 1000, 10⁶), exact: a time in the unit divided by it is the
    /// correctly rounded time in seconds.
    pub fn per_second(self) -> f64 {
        match self {
            Self::Seconds => 1.0,
            Self::Milliseconds => 1e3,
            Self::Microseconds => 1e6,
        }
    }

    /// The unit's symbol: `s`, `ms`, `us`.
    pub fn symbol(self) -> &'static str {
        match self {
            Self::Seconds => "s",
            Self::Milliseconds => "ms",
            Self::Microseconds => "us",
        }
    }

    /// The unit a symbol names: `s`, `sec`, `ms`, `us`, `µs` or `μs` (case-sensitive, as SI
    /// symbols are: `Ms` is no millisecond); `None` for any other.
    pub fn from_symbol(symbol: &str) -> Option<Self> {
        match symbol.trim() {
            "s" | "sec" => Some(Self::Seconds),
            "ms" => Some(Self::Milliseconds),
            "us" | "µs" | "μs" => Some(Self::Microseconds),
            _ => None,
        }
    }
}

/// The names a time column answers to without `--time-column`: `t` or `time` (any case),
/// alone (`t`, `Time`), with a unit suffix (`t_ms`, `time_us`, `t_s`) or with a unit in
/// brackets (`time [ms]`, `t (s)`).
pub fn is_time_name(header: &str) -> bool {
    let (name, _) = crate::io::split_unit(header);
    let lower = name.to_ascii_lowercase();
    let base = match lower.rsplit_once('_') {
        Some((base, suffix)) if TimeUnit::from_symbol(suffix).is_some() => base,
        _ => lower.as_str(),
    };
    base == "t" || base == "time"
}

/// The unit a time column's header name states: in brackets (`time [ms]`, `t (us)`) or as
/// a suffix after `_` (`t_ms`, `time_us`); `Ok(None)` when it states none (then seconds),
/// [`TimeError::UnknownUnit`] for a bracketed unit that is not `s`, `ms` or `us`.
pub fn time_unit_of(file: &Path, header: &str) -> Result<Option<TimeUnit>, TimeError> {
    let (name, unit) = crate::io::split_unit(header);
    if let Some(unit) = unit {
        return TimeUnit::from_symbol(unit)
            .map(Some)
            .ok_or_else(|| TimeError::UnknownUnit {
                file: file.to_path_buf(),
                column: header.to_string(),
                unit: unit.to_string(),
            });
    }
    Ok(name
        .rsplit_once('_')
        .and_then(|(_, suffix)| TimeUnit::from_symbol(suffix)))
}

/// How the steps of a time column spread around their mean, in seconds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Jitter {
    /// The mean step: (last − first) / (rows − 1).
    pub mean: f64,
    /// The largest |step − mean|.
    pub largest: f64,
    /// The standard deviation of the steps.
    pub std: f64,
}

impl Jitter {
    /// The spread of the steps of `t` (seconds), `None` with fewer than two rows.
    pub fn of(t: &[f64]) -> Option<Self> {
        let (first, last) = (t.first()?, t.last()?);
        if t.len() < 2 {
            return None;
        }
        let mean = (last - first) / (t.len() - 1) as f64;
        let (mut largest, mut sum2) = (0.0f64, 0.0);
        for w in t.windows(2) {
            let d = (w[1] - w[0]) - mean;
            largest = largest.max(d.abs());
            sum2 += d * d;
        }
        // Steps that differ only by the rounding of the times (1e-9 of the step) are uniform.
        let noise = 1e-9 * mean.abs();
        let std = (sum2 / (t.len() - 1) as f64).sqrt();
        Some(Self {
            mean,
            largest: if largest <= noise { 0.0 } else { largest },
            std: if std <= noise { 0.0 } else { std },
        })
    }
}

impl fmt::Display for Jitter {
    /// `mean step 10 ms, steps within ±0.5 ms of it (std 0.29 ms)`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "mean step {}, steps within ±{} of it (std {})",
            duration(self.mean),
            duration(self.largest),
            duration(self.std)
        )
    }
}

/// A duration in s, ms or µs, three significant digits.
fn duration(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v} s");
    }
    let (scale, unit) = match v.abs() {
        a if a >= 1.0 => (1.0, "s"),
        a if a >= 1e-3 => (1e3, "ms"),
        _ => (1e6, "µs"),
    };
    let x = v * scale;
    let digits = 2 - x.abs().log10().floor().clamp(-300.0, 300.0) as i32;
    format!("{:.*} {unit}", digits.max(0) as usize, x)
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
    fn time_columns_are_found_by_name_and_state_their_unit() {
        let p = Path::new("r.csv");
        for name in [
            "t", "T", "time", "Time", "t_ms", "time_us", "t [ms]", "time (s)",
        ] {
            assert!(is_time_name(name), "{name}");
        }
        for name in ["u", "temp", "t_x", "times", "tt [s]"] {
            assert!(!is_time_name(name), "{name}");
        }
        let unit = |n| time_unit_of(p, n).unwrap();
        assert_eq!(unit("t"), None);
        assert_eq!(unit("t_ms"), Some(TimeUnit::Milliseconds));
        assert_eq!(unit("time [ms]"), Some(TimeUnit::Milliseconds));
        assert_eq!(unit("time (s)"), Some(TimeUnit::Seconds));
        assert_eq!(unit("t_us"), Some(TimeUnit::Microseconds));
        assert_eq!(unit("t [µs]"), Some(TimeUnit::Microseconds));
        let e = time_unit_of(p, "time [min]").unwrap_err();
        assert!(e.to_string().contains("--time-unit s|ms|us"), "{e}");
    }

    #[test]
    fn the_jitter_of_a_column_is_its_steps_around_their_mean() {
        let t = [0.0, 0.0105, 0.0200, 0.0300];
        let j = Jitter::of(&t).unwrap();
        assert!((j.mean - 0.01).abs() < 1e-15, "{j:?}");
        assert!((j.largest - 0.0005).abs() < 1e-12, "{j:?}");
        assert_eq!(
            j.to_string(),
            "mean step 10.0 ms, steps within ±500 µs of it (std 408 µs)"
        );
        assert_eq!(Jitter::of(&[1.0]), None);
        let uniform: Vec<f64> = (0..100).map(|k| 0.01 * k as f64).collect();
        assert_eq!(
            Jitter::of(&uniform).unwrap().to_string(),
            "mean step 10.0 ms, steps within ±0 s of it (std 0 s)"
        );
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
