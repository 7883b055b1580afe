//! The wear report scored against a simulated fleet's truth.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::num::{ParseFloatError, ParseIntError};
use std::path::{Path, PathBuf};

use super::MAX_TABLE_BYTES;
use super::device_wear::{DeviceWear, split_id};
use crate::io::read_text_bounded;

/// Why the truth table could not be read or does not fit the report.
#[derive(Debug, thiserror::Error)]
pub enum ScoreError {
    /// The truth file could not be read.
    #[error("{path}: {source}")]
    Read {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// A row without the five fields.
    #[error("{path} line {line}: expected device,week,wearing,gap,damage")]
    Fields {
        /// The file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
    },
    /// A device id that is not `DEVICE-wWEEK`.
    #[error("{path} line {line}: device id {id:?}")]
    DeviceId {
        /// The file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// The id.
        id: String,
    },
    /// A week that is not a whole number.
    #[error("{path} line {line}: week: {source}")]
    Week {
        /// The file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// The parser's error.
        source: ParseIntError,
    },
    /// A gap that is not a number.
    #[error("{path} line {line}: gap: {source}")]
    Gap {
        /// The file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// The parser's error.
        source: ParseFloatError,
    },
    /// A device with a trend that the truth table does not list.
    #[error("device {0} is not in the truth table")]
    UnknownDevice(String),
}

/// A device's truth: whether it wears, and its true gap per week.
struct Truth {
    wearing: bool,
    gaps: BTreeMap<usize, f64>,
}

fn read_truth(path: &Path) -> Result<BTreeMap<String, Truth>, ScoreError> {
    let text = read_text_bounded(path, MAX_TABLE_BYTES).map_err(|source| ScoreError::Read {
        path: path.to_path_buf(),
        source,
    })?;
    let mut out: BTreeMap<String, Truth> = BTreeMap::new();
    for (i, row) in text.lines().enumerate().skip(1) {
        let line = i + 1;
        let f: Vec<&str> = row.split(',').collect();
        let [id, week, wearing, gap, _damage] = f.as_slice() else {
            return Err(ScoreError::Fields {
                path: path.to_path_buf(),
                line,
            });
        };
        let (device, _) = split_id(id).ok_or_else(|| ScoreError::DeviceId {
            path: path.to_path_buf(),
            line,
            id: (*id).to_owned(),
        })?;
        let week: usize = week.parse().map_err(|source| ScoreError::Week {
            path: path.to_path_buf(),
            line,
            source,
        })?;
        let gap: f64 = gap.parse().map_err(|source| ScoreError::Gap {
            path: path.to_path_buf(),
            line,
            source,
        })?;
        let wearing = *wearing == "true";
        let t = out.entry(device.to_owned()).or_insert(Truth {
            wearing,
            gaps: BTreeMap::new(),
        });
        t.gaps.insert(week, gap);
    }
    Ok(out)
}

/// Detection rate on wearing devices, false-flag rate on the others, and how far the
/// estimated gaps and slopes are from the true ones.
pub fn score(devices: &[DeviceWear], truth: &Path) -> Result<String, ScoreError> {
    let truth = read_truth(truth)?;
    let (mut hit, mut worn, mut false_flags, mut sound) = (0, 0, 0, 0);
    let (mut gap_err, mut slope_err) = (Vec::new(), Vec::new());
    for d in devices.iter().filter(|d| d.trend.is_some()) {
        let Some(t) = truth.get(&d.device) else {
            return Err(ScoreError::UnknownDevice(d.device.clone()));
        };
        if t.wearing {
            worn += 1;
            hit += usize::from(d.wearing);
        } else {
            sound += 1;
            false_flags += usize::from(d.wearing);
        }
        for (w, g) in &d.gaps {
            if let Some(tg) = t.gaps.get(&(*w as usize)) {
                gap_err.push(g - tg);
            }
        }
        let true_slope = match (t.gaps.first_key_value(), t.gaps.last_key_value()) {
            (Some((w0, g0)), Some((w1, g1))) if w1 > w0 => (g1 - g0) / (w1 - w0) as f64,
            _ => 0.0,
        };
        if let Some(tr) = d.trend {
            slope_err.push(tr.slope - true_slope);
        }
    }
    // "3 of 4 (75.0 %)"; of none, "0 of 0 (none in the truth table)" rather than NaN %.
    let rate = |a: usize, b: usize, digits: usize| match b {
        0 => format!("{a} of 0 (none in the truth table)"),
        b => format!("{a} of {b} ({:.*} %)", digits, 100.0 * a as f64 / b as f64),
    };
    let (gm, gs) = mean_std(&gap_err);
    let (sm, ss) = mean_std(&slope_err);
    let mut out = String::new();
    let _ = writeln!(
        out,
        "wearing devices flagged: {}; devices that do not wear flagged: {}",
        rate(hit, worn, 1),
        rate(false_flags, sound, 2)
    );
    let _ = writeln!(
        out,
        "weekly gap minus true gap: mean {gm:+.4}, std {gs:.4}; slope minus true slope: mean {sm:+.5}, std {ss:.5} per week"
    );
    Ok(out)
}

fn mean_std(x: &[f64]) -> (f64, f64) {
    let n = x.len() as f64;
    let m = x.iter().sum::<f64>() / n;
    let v = x.iter().map(|v| (v - m).powi(2)).sum::<f64>() / (n - 1.0);
    (m, v.sqrt())
}
