//! Argument groups shared by several subcommands (`#[command(flatten)]`) and the value enums.

use std::path::{Path, PathBuf};

use clap::{Args, ValueEnum};
use hsid::Basis;
use hsid_host::io::{CsvOptions, Delimiter, IoError, Table, parse_table, read_source};
use hsid_host::model_file::Units;
use hsid_host::units::{
    Origin, UnitsOrigin, check_unit_text, checked_ts, resolve_units, ts_from_column,
    ts_from_comments, units_from_comments,
};

/// The value parser of every number flag: a number that is finite. `NaN` and the infinities
/// parse as `f64` but are no interval end, gain, noise level or sample time, so they are
/// refused at the flag, before any work.
pub fn finite_f64(s: &str) -> Result<f64, String> {
    let v: f64 = s
        .trim()
        .parse()
        .map_err(|_| format!("{s:?} is not a number"))?;
    match v.is_finite() {
        true => Ok(v),
        false => Err(format!("{s} is not a finite number: give a finite value")),
    }
}

/// How the CSV files are read.
#[derive(Args, Clone, Debug)]
pub struct CsvArgs {
    /// Field delimiter of the CSV files (default: sniffed from the header line: tab if it has a
    /// tab, else `;` if it has a `;` and no `,`, else `,`).
    #[arg(long, value_enum)]
    pub delimiter: Option<DelimiterArg>,
}

impl CsvArgs {
    /// The delimiter to use, `None` to sniff it.
    pub fn delimiter(&self) -> Option<Delimiter> {
        self.delimiter.map(|d| match d {
            DelimiterArg::Comma => Delimiter::Comma,
            DelimiterArg::Semicolon => Delimiter::Semicolon,
            DelimiterArg::Tab => Delimiter::Tab,
        })
    }
}

/// An answer to a yes-or-no flag that may also be left out (then the data decide).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum YesNo {
    /// Yes.
    Yes,
    /// No.
    No,
}

/// A CSV field delimiter.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum DelimiterArg {
    /// `,`
    Comma,
    /// `;`
    Semicolon,
    /// A tab character.
    Tab,
}

/// The input and output columns of a record.
#[derive(Args, Clone, Debug)]
pub struct Columns {
    /// Input column name.
    #[arg(long, default_value = "u")]
    pub input_column: String,
    /// Output column name.
    #[arg(long, default_value = "y")]
    pub output_column: String,
}

/// Knots given per path.
#[derive(Args, Clone, Debug)]
pub struct KnotArgs {
    /// Ascending knots, comma separated, u_min first and u_max last.
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true, value_parser = finite_f64)]
    pub knots_asc: Option<Vec<f64>>,
    /// Descending knots, comma separated, u_min first and u_max last.
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true, value_parser = finite_f64)]
    pub knots_desc: Option<Vec<f64>>,
}

/// The initial hold at u_min.
#[derive(Args, Clone, Debug)]
pub struct HoldArgs {
    /// Samples of the initial hold at u_min (0: no hold).
    #[arg(long, default_value_t = 300)]
    pub hold: usize,
    /// Samples of the hold skipped while the plant settles (default: half the hold).
    #[arg(long)]
    pub settle: Option<usize>,
}

impl HoldArgs {
    /// The settle length: given, or half the hold.
    pub fn settle(&self) -> usize {
        self.settle.unwrap_or(self.hold / 2)
    }
}

/// The horizons of the Hankel matrices.
#[derive(Args, Clone, Debug)]
pub struct Horizons {
    /// Future horizon f (default: from the data for `identify`, shortened where the input's
    /// Hankel Gram is rank deficient, 10 for `diagnose`; with only one of --f and --p given,
    /// the other equals it).
    #[arg(long)]
    pub f: Option<usize>,
    /// Past horizon p.
    #[arg(long)]
    pub p: Option<usize>,
}

impl Horizons {
    /// `(f, p)` when at least one is given.
    pub fn given(&self) -> Option<(usize, usize)> {
        match (self.f, self.p) {
            (Some(f), Some(p)) => Some((f, p)),
            (Some(h), None) | (None, Some(h)) => Some((h, h)),
            (None, None) => None,
        }
    }

    /// `(f, p)`, the paper's 10 when neither is given.
    pub fn or_paper(&self) -> (usize, usize) {
        self.given().unwrap_or((10, 10))
    }
}

/// Where a model file goes.
#[derive(Args, Clone, Debug)]
pub struct ModelOut {
    /// Write the model here, as a model file (format hsid-model/1, see docs/model-format.md).
    #[arg(long)]
    pub json: Option<PathBuf>,
}

/// Border basis of the regressor.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum BasisArg {
    /// Linear B-splines (hat functions): sparse, better conditioned.
    Hat,
    /// The paper's ramp functions P_i.
    Ramp,
}

impl From<BasisArg> for Basis {
    fn from(b: BasisArg) -> Self {
        match b {
            BasisArg::Hat => Basis::Hat,
            BasisArg::Ramp => Basis::Ramp,
        }
    }
}

/// The sample time and the units of the signals.
#[derive(Args, Clone, Debug)]
pub struct UnitArgs {
    /// Sample time in seconds (> 0). Without it, the step of the record's time column when it
    /// has one, or its header comment `# ts = 0.01 s` (as `hsid simulate` writes it); every
    /// one stated must agree within 0.1 %. With none, times are in samples and frequencies in
    /// rad/sample.
    #[arg(long, allow_hyphen_values = true, value_parser = finite_f64)]
    pub ts: Option<f64>,
    /// Unit of the input u (free text, e.g. `V`), for the reports and the model file. Without
    /// it, the record's header comments `# input unit = V` and `# output unit = deg` (as
    /// `hsid simulate` writes them); every one stated must agree.
    #[arg(long, requires = "output_unit")]
    pub input_unit: Option<String>,
    /// Unit of the output y (free text, e.g. `deg`).
    #[arg(long, requires = "input_unit")]
    pub output_unit: Option<String>,
    /// Time column: when the record has it, it must increase with a uniform step (within
    /// 0.1 %), which is the sample time [default: `t`, used only when present].
    #[arg(long)]
    pub time_column: Option<String>,
}

impl UnitArgs {
    /// `--ts`, checked positive.
    pub fn ts(&self) -> Result<Option<f64>, String> {
        self.ts
            .map(|v| checked_ts(v, Origin::Flag))
            .transpose()
            .map_err(|e| e.to_string())
    }

    /// `--input-unit` and `--output-unit`, checked non-empty and free of the characters a unit
    /// may not hold (double quotes, control characters: [`check_unit_text`]).
    pub fn units(&self) -> Result<Option<Units>, String> {
        let (Some(input), Some(output)) = (&self.input_unit, &self.output_unit) else {
            return Ok(None);
        };
        for (flag, v) in [("--input-unit", input), ("--output-unit", output)] {
            if v.trim().is_empty() {
                return Err(format!(
                    "{flag} is empty: give the unit's name, e.g. V or deg"
                ));
            }
            check_unit_text(v).map_err(|e| format!("{flag} {v:?}: {e}"))?;
        }
        Ok(Some(Units {
            input: input.trim().to_string(),
            output: output.trim().to_string(),
        }))
    }

    /// The time column's name and whether it was named explicitly (then it must be there).
    pub fn time_column(&self) -> (&str, bool) {
        self.time_column
            .as_deref()
            .map_or(("t", false), |name| (name, true))
    }

    /// The units every source states — the flags first, then `others` (a model file's, the
    /// records' header comments) — checked to agree; `None` when none states them.
    pub fn resolve_units(
        &self,
        others: impl IntoIterator<Item = (UnitsOrigin, Units)>,
    ) -> Result<Option<Units>, String> {
        let stated: Vec<(UnitsOrigin, Units)> = self
            .units()?
            .map(|u| (UnitsOrigin::Flags, u))
            .into_iter()
            .chain(others)
            .collect();
        resolve_units(&stated).map_err(|e| e.to_string())
    }
}

/// The units records' header comments state (with the record's name), as sources for
/// [`UnitArgs::resolve_units`].
pub fn comment_units(
    records: impl IntoIterator<Item = (PathBuf, Units)>,
) -> impl Iterator<Item = (UnitsOrigin, Units)> {
    records
        .into_iter()
        .map(|(p, u)| (UnitsOrigin::Comment(p), u))
}

/// What reading a record from CSV gives: the requested columns, the sample times the file
/// states and the units its header comments state.
pub struct CsvRead {
    /// The requested columns and the line of each row.
    pub table: Table,
    /// The sample times the record states, with where each came from: its header comment
    /// `# ts = … s` and its time column (none, one or both; `resolve_ts` checks agreement).
    pub ts: Vec<(Origin, f64)>,
    /// The units its header comments state (`# input unit = …`, `# output unit = …`), with
    /// the record's name.
    pub units: Option<(PathBuf, Units)>,
}

/// Reads the columns `names` from `data` (a file, or `-` for standard input) and the time
/// column of `units` when the file has it (or it was named), checked uniform.
pub fn read_record(
    data: &Path,
    names: &[&str],
    csv: &CsvArgs,
    units: &UnitArgs,
) -> Result<CsvRead, String> {
    let options = CsvOptions {
        delimiter: csv.delimiter(),
    };
    let (source, text) = read_source(data).map_err(|e| e.to_string())?;
    let mut ts: Vec<(Origin, f64)> = ts_from_comments(&source, &text)
        .map_err(|e| e.to_string())?
        .map(|v| (Origin::Comment(source.clone()), v))
        .into_iter()
        .collect();
    let stated_units = units_from_comments(&source, &text)
        .map_err(|e| e.to_string())?
        .map(|u| (source.clone(), u));
    let (time, named) = units.time_column();
    let mut all = names.to_vec();
    all.push(time);
    let mut table = match parse_table(&source, &text, &all, &options) {
        Err(IoError::MissingColumn { column, .. }) if !named && column == time.trim() => {
            return parse_table(&source, &text, names, &options)
                .map(|table| CsvRead {
                    table,
                    ts,
                    units: stated_units,
                })
                .map_err(|e| e.to_string());
        }
        r => r.map_err(|e| e.to_string())?,
    };
    let t = table.columns.pop().unwrap_or_default();
    let column = ts_from_column(source.clone(), &t, &table.lines).map_err(|e| e.to_string())?;
    ts.push((Origin::TimeColumn(source), column));
    Ok(CsvRead {
        table,
        ts,
        units: stated_units,
    })
}

/// Reads the columns `u, y` named by `columns` from `data` (a file, or `-` for standard input),
/// with the sample time of its time column (see [`read_record`]).
pub fn read_uy(
    data: &Path,
    columns: &Columns,
    csv: &CsvArgs,
    units: &UnitArgs,
) -> Result<CsvRead, String> {
    let names = [
        columns.input_column.as_str(),
        columns.output_column.as_str(),
    ];
    read_record(data, &names, csv, units)
}
