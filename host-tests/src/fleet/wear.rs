//! The wear report: per device the gap of every week's model, its trend ([`fit`]) and two
//! flags, and on a simulated fleet the detection rate on wearing devices and the false-flag
//! rate on the others.
//!
//! The gap of a week is the mean of the model's play after a descent to `u = 0` and after an
//! ascent to `u = 0` ([`HostModel::gap_at`]), in input units. A device is flagged as *wearing* when its
//! gap grows by more than `k` standard errors of the slope (a one-sided test of "no growth";
//! with 8 weeks and `k = 3` a device that does not wear is flagged with probability about 1 %
//! if the weekly estimates are independent and normal), and as *over the limit* when the
//! trend's gap in its last week exceeds an absolute limit.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use hsid::Direction;
use serde_json::Value;

use super::MAX_TABLE_BYTES;
use super::device_wear::{DeviceWear, device_csv, split_id};
use super::score::{ScoreError, score};
use super::trend::fit;
use crate::identify::HostModel;
use crate::io::read_text_bounded;
use crate::model_file::{ModelFile, ModelFileError};

/// The flags' thresholds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ReportOptions {
    /// Flag growth beyond `k` standard errors of the slope.
    pub k: f64,
    /// Flag a trend gap above this in the last week.
    pub limit: Option<f64>,
}

impl HostModel {
    /// The model's gap at `u = 0`: the mean of the play after a descent and after an ascent.
    pub fn gap(&self) -> Option<f64> {
        let d = self.gap_at(Direction::Descending, 0.0)?;
        let a = self.gap_at(Direction::Ascending, 0.0)?;
        Some(0.5 * (d + a))
    }
}

/// Why the report could not be made.
#[derive(Debug, thiserror::Error)]
pub enum WearError {
    /// The models file could not be read.
    #[error("{path}: {source}")]
    Read {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// A line of the models file does not hold what the report needs.
    #[error("{path}: {source}")]
    Line {
        /// The file.
        path: PathBuf,
        /// What is wrong with the line.
        source: LineError,
    },
    /// The truth table could not be read or does not fit.
    #[error(transparent)]
    Score(#[from] ScoreError),
    /// No line of the models file holds a device's weekly model or error: the fleet's
    /// directory held no checkpoint (or none the report can follow).
    #[error(
        "{path}: no model of a checkpoint named DEVICE-wWEEK.bin ({lines} lines), so no device to \
         follow over the weeks: the report reads the JSON lines of `hsid fleet --states DIR`, \
         whose checkpoints must be named DEVICE-wWEEK.bin (e.g. pump17-w3.bin: device pump17, \
         week 3); check that DIR holds them"
    )]
    NoDevices {
        /// The models file.
        path: PathBuf,
        /// Its non-blank lines (all errors when non-zero).
        lines: usize,
    },
    /// The per-device table could not be written.
    #[error("{path}: {source}")]
    WriteCsv {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
}

/// What is wrong with one JSON line of `hsid fleet`.
#[derive(Debug, thiserror::Error)]
pub enum LineError {
    /// Not JSON.
    #[error("line {line}: {source}")]
    Json {
        /// 1-based line.
        line: usize,
        /// The parser's error.
        source: serde_json::Error,
    },
    /// No `"device"` string.
    #[error("line {line}: no \"device\"")]
    NoDevice {
        /// 1-based line.
        line: usize,
    },
    /// A device id that is not `DEVICE-wWEEK.bin`.
    #[error(
        "line {line}: device id {id:?} is not DEVICE-wWEEK.bin (e.g. pump17-w3.bin: device \
         pump17, week 3): the report follows each device over the weeks by its checkpoints' \
         file names; rename them so in the directory of `hsid fleet --states` and solve again"
    )]
    DeviceId {
        /// 1-based line.
        line: usize,
        /// The id.
        id: String,
    },
    /// The model is not a valid model file (its message names the line).
    #[error(transparent)]
    Model(#[from] ModelFileError),
}

/// What one JSON line of `hsid fleet` holds for the report.
enum Line {
    /// A week's gap of a device (`None`: the model has no gap at `u = 0`).
    Gap(String, usize, Option<f64>),
    /// A device's error kind.
    Error(String),
}

fn parse_line(line: &str, at: usize) -> Result<Line, LineError> {
    let v: Value =
        serde_json::from_str(line).map_err(|source| LineError::Json { line: at, source })?;
    let id = v["device"]
        .as_str()
        .ok_or(LineError::NoDevice { line: at })?;
    if let Some(kind) = v["error"]["kind"].as_str() {
        return Ok(Line::Error(kind.to_owned()));
    }
    let (device, week) = split_id(id).ok_or_else(|| LineError::DeviceId {
        line: at,
        id: id.to_owned(),
    })?;
    let text = v["model"].to_string();
    let model = ModelFile::from_json_str(format!("line {at}"), &text)?;
    Ok(Line::Gap(
        device.to_owned(),
        week,
        HostModel::from_json(&model).gap(),
    ))
}

/// Reads the JSON lines of `hsid fleet`: the devices' weekly gaps and the count of each
/// error kind.
pub(crate) fn read_models(
    path: &Path,
) -> Result<(Vec<DeviceWear>, BTreeMap<String, usize>), WearError> {
    let text = read_text_bounded(path, MAX_TABLE_BYTES).map_err(|source| WearError::Read {
        path: path.to_path_buf(),
        source,
    })?;
    let mut devices: BTreeMap<String, Vec<(f64, f64)>> = BTreeMap::new();
    let mut errors: BTreeMap<String, usize> = BTreeMap::new();
    for (i, line) in text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty())
    {
        let line = parse_line(line, i + 1).map_err(|source| WearError::Line {
            path: path.to_path_buf(),
            source,
        })?;
        match line {
            Line::Gap(d, w, Some(g)) => devices.entry(d).or_default().push((w as f64, g)),
            Line::Gap(d, _, None) => {
                devices.entry(d).or_default();
                *errors.entry("no_gap_at_0".into()).or_default() += 1;
            }
            Line::Error(kind) => *errors.entry(kind).or_default() += 1,
        }
    }
    let wear = devices
        .into_iter()
        .map(|(device, gaps)| DeviceWear {
            trend: fit(&gaps),
            device,
            gaps,
            wearing: false,
            over_limit: false,
        })
        .collect();
    Ok((wear, errors))
}

/// Sets the flags of every device.
pub fn flag(devices: &mut [DeviceWear], opts: &ReportOptions) {
    for d in devices {
        let last = d.gaps.iter().map(|g| g.0).fold(f64::NEG_INFINITY, f64::max);
        if let Some(t) = d.trend {
            d.wearing = t.slope > opts.k * t.slope_se;
            d.over_limit = opts.limit.is_some_and(|l| t.at(last) > l);
        }
    }
}

/// The report: read, flag, compare with the truth if given, write the per-device CSV if
/// asked; returns the summary text.
pub fn wear_report(
    models: &Path,
    truth: Option<&Path>,
    opts: &ReportOptions,
    csv: Option<&Path>,
) -> Result<String, WearError> {
    let (mut devices, errors) = read_models(models)?;
    if devices.is_empty() {
        return Err(WearError::NoDevices {
            path: models.to_path_buf(),
            lines: errors.values().sum(),
        });
    }
    flag(&mut devices, opts);
    let mut out = String::new();
    let weeks: usize = devices.iter().map(|d| d.gaps.len()).sum();
    let _ = writeln!(
        out,
        "{} devices, {weeks} weekly models; errors: {}",
        devices.len(),
        if errors.is_empty() {
            "none".to_string()
        } else {
            errors
                .iter()
                .map(|(k, n)| format!("{k} {n}"))
                .collect::<Vec<_>>()
                .join(", ")
        }
    );
    let no_trend = devices.iter().filter(|d| d.trend.is_none()).count();
    let flagged = devices.iter().filter(|d| d.wearing).count();
    let over = devices.iter().filter(|d| d.over_limit).count();
    let _ = writeln!(
        out,
        "flagged wearing (growth > {} σ of the slope): {flagged}; over the limit: {over}; too few weeks for a trend: {no_trend}",
        opts.k
    );
    if let Some(t) = truth {
        out.push_str(&score(&devices, t)?);
    }
    if let Some(path) = csv {
        crate::io::write_atomic(path, device_csv(&devices)).map_err(|source| {
            WearError::WriteCsv {
                path: path.to_path_buf(),
                source,
            }
        })?;
        let _ = writeln!(out, "wrote {}", path.display());
    }
    Ok(out)
}
