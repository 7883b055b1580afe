//! Several experiments read for one identification: each record's columns, their sample
//! time checked against `--ts` and each other, and sample positions mapped back to files.

use std::path::{Path, PathBuf};

use hsid_host::identify::IdentifyError;
use hsid_host::model::Record;
use hsid_host::model_file::Units;
use hsid_host::units::{Origin, resolve_ts};
use hsid_host::workflow::{Field, WorkflowError};

use crate::args::{Columns, CsvArgs, UnitArgs, read_record, read_uy};
use crate::failure::{Failure, note};
use crate::locate;
use hsid_host::hold::read_hold;

/// The records of one identification, concatenated in the order given.
pub struct Records {
    /// The files.
    pub paths: Vec<PathBuf>,
    /// Index of each record's first sample in `u` and `y`.
    pub starts: Vec<usize>,
    /// The 1-based line of each record's rows in its file.
    pub lines: Vec<Vec<usize>>,
    /// All inputs.
    pub u: Vec<f64>,
    /// All outputs.
    pub y: Vec<f64>,
    /// The reference column's values (`--reference-column`), empty without it.
    pub r: Vec<f64>,
    /// The sample time, from `--ts` and the records' time columns, when known.
    pub ts: Option<f64>,
    /// The units, from `--input-unit`/`--output-unit` and the records' header comments, when
    /// known.
    pub units: Option<Units>,
}

impl Records {
    /// Reads every file of `paths` (and the column `reference`, when named); the sample times
    /// stated by `--ts` and by the time columns must agree, and so must the units stated by the
    /// flags and the header comments.
    pub fn read(
        paths: &[PathBuf],
        columns: &Columns,
        reference: Option<&str>,
        csv: &CsvArgs,
        units: &UnitArgs,
    ) -> Result<Self, String> {
        let mut stated: Vec<(Origin, f64)> =
            units.ts()?.map(|v| (Origin::Flag, v)).into_iter().collect();
        let mut r = Records {
            paths: paths.to_vec(),
            starts: Vec::new(),
            lines: Vec::new(),
            u: Vec::new(),
            y: Vec::new(),
            r: Vec::new(),
            ts: None,
            units: None,
        };
        let mut unit_comments = Vec::new();
        for path in paths {
            let rec = match reference {
                Some(name) => {
                    let names = [
                        columns.input_column.as_str(),
                        columns.output_column.as_str(),
                        name,
                    ];
                    read_record(path, &names, csv, units)?
                }
                None => read_uy(path, columns, csv, units)?,
            };
            stated.extend(rec.ts);
            unit_comments.extend(rec.units);
            let mut cols = rec.table.columns.into_iter();
            r.starts.push(r.u.len());
            append(&mut r.u, cols.next());
            append(&mut r.y, cols.next());
            append(&mut r.r, cols.next());
            r.lines.push(rec.table.lines);
        }
        r.ts = resolve_ts(&stated).map_err(|e| e.to_string())?;
        r.units = units.resolve_units(unit_comments)?;
        Ok(r)
    }

    /// [`Records::read`], then [`Records::check_junctions`] at `(u_min, settle)`.
    pub fn read_joined(
        paths: &[PathBuf],
        columns: &Columns,
        reference: Option<&str>,
        csv: &CsvArgs,
        units: &UnitArgs,
        (u_min, settle): (f64, usize),
    ) -> Result<Self, String> {
        let records = Self::read(paths, columns, reference, csv, units)?;
        records.check_junctions(u_min, settle)?;
        Ok(records)
    }

    /// Checks that the records join without mixing: a record that starts at `u_min` (with a
    /// hold, the plant at rest) must follow one that ends with at least `settle` samples (at
    /// least one) at `u_min`, where the plant has come to rest too; otherwise the settling at
    /// the end of the one would be read as the rest of the other. A record that starts
    /// elsewhere is taken as the continuation of the one before (a record split into files).
    pub fn check_junctions(&self, u_min: f64, settle: usize) -> Result<(), String> {
        let parts = self.parts();
        for (k, pair) in parts.windows(2).enumerate() {
            let (before, after) = (pair[0].0, pair[1].0);
            if after.first() != Some(&u_min) {
                continue;
            }
            let tail = settle.max(1).min(before.len());
            if before[before.len() - tail..].iter().any(|&v| v != u_min) {
                return Err(format!(
                    "{} starts at rest at u_min = {u_min} but {} does not end with {tail} samples \
                     (the settling, --settle) at u_min: joined, the plant's settling after the one \
                     would be read as the rest of the other; end each experiment with a hold at \
                     u_min or record them in one file",
                    self.paths[k + 1].display(),
                    self.paths[k].display()
                ));
            }
        }
        Ok(())
    }

    /// Checks the hold, the first `hold` inputs of the first record, against `u_min`
    /// ([`read_hold`]): within `--hold-tolerance` (default 0) they are read as `u_min`, with a
    /// note when any was not exactly there; beyond it the error names the lines and the cause
    /// (noise on the hold, or the excitation starting inside it).
    pub fn read_hold(
        &mut self,
        u_min: f64,
        hold: usize,
        tolerance: Option<f64>,
    ) -> Result<(), String> {
        let end = self.starts.get(1).copied().unwrap_or(self.u.len());
        let (path, lines) = (&self.paths[0], &self.lines[0]);
        let line = |i: usize| format!("line {}", lines.get(i).copied().unwrap_or(i + 1));
        let read = read_hold(&mut self.u[..end], u_min, hold, tolerance.unwrap_or(0.0))
            .map_err(|e| format!("{} {}", path.display(), e.describe(&line)))?;
        if let (Some(largest), true) = (read.largest, read.replaced > 0) {
            note(&format!(
                "{}: {} inputs of the hold are within --hold-tolerance {} of u_min = {u_min} \
                 (the largest deviation {:.2e}, {}) and are read as u_min",
                path.display(),
                read.replaced,
                tolerance.unwrap_or(0.0),
                largest.deviation,
                line(largest.index)
            ));
        }
        Ok(())
    }

    /// The samples of each record, `(u, y)`.
    pub fn parts(&self) -> Vec<(&[f64], &[f64])> {
        let ends = self.starts.iter().skip(1).copied().chain([self.u.len()]);
        self.starts
            .iter()
            .zip(ends)
            .map(|(&a, b)| (&self.u[a..b], &self.y[a..b]))
            .collect()
    }

    /// The record holding sample `index` of the concatenation.
    fn record_of(&self, index: usize) -> usize {
        self.starts.iter().rposition(|&s| s <= index).unwrap_or(0)
    }

    /// The first file's name, for errors about the records as a whole.
    pub fn first(&self) -> &Path {
        self.paths.first().map_or(Path::new("-"), PathBuf::as_path)
    }

    /// The library's record: the samples, the reference when read, the sample time and
    /// units, the hold and where each file starts. The samples move into it: the records keep
    /// what their messages need (paths, lines, starts), and a long record is not held twice.
    pub fn take_record(&mut self, hold: usize) -> Record {
        let time = (0..self.u.len()).map(|t| t as f64).collect();
        Record {
            u: std::mem::take(&mut self.u),
            y: std::mem::take(&mut self.y),
            time,
            reference: (!self.r.is_empty()).then(|| std::mem::take(&mut self.r)),
            ts: self.ts,
            units: self.units.clone(),
            hold,
            starts: self.starts.clone(),
        }
    }

    /// A workflow error in the command line's words, a sample as a line of its file.
    pub fn workflow_error(&self, e: WorkflowError) -> Failure {
        let first = self.first().display();
        match e {
            WorkflowError::Request(e) if e.field == Field::Hold => format!("{first}: {e}"),
            WorkflowError::Request(e) => e.message,
            WorkflowError::Sample { error, index } => self.sample_error(&error, index),
            WorkflowError::ClosedLoop { name, error } => {
                format!("{first} (reference column {name}): {error}")
            }
            e @ (WorkflowError::ElementFit { .. } | WorkflowError::Interrupted(_)) => e.to_string(),
            WorkflowError::Choose(e) => format!("{first}: {e}"),
        }
        .into()
    }

    /// A core error about sample `index` (0 = the first of all records) as a position in the
    /// file it came from.
    pub fn sample_error(&self, e: &IdentifyError, index: usize) -> String {
        let k = self.record_of(index);
        // Lines of the record k placed at its offset in the concatenation.
        let mut lines = vec![0; self.starts[k]];
        lines.extend(&self.lines[k]);
        locate::sample_error(&self.paths[k], &lines, e)
    }
}

/// Appends a file's column to the joined one: moved when it is the first (a long record is not
/// copied), else copied after the others.
fn append(joined: &mut Vec<f64>, column: Option<Vec<f64>>) {
    let column = column.unwrap_or_default();
    match joined.is_empty() {
        true => *joined = column,
        false => joined.extend(column),
    }
}
