//! Argument groups shared by several subcommands (`#[command(flatten)]`) and the value enums.

use std::path::{Path, PathBuf};

use clap::{Args, ValueEnum};
use hsid::Basis;
use hsid_host::diagnose::Nonlinearity;
use hsid_host::io::{CsvOptions, Delimiter, Table, read_table};
use hsid_host::model_file::NonlinearityKind;

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
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    pub knots_asc: Option<Vec<f64>>,
    /// Descending knots, comma separated, u_min first and u_max last.
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
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
    /// Future horizon f (default: from the data for `identify`, 10 for `diagnose`; with only
    /// one of --f and --p given, the other equals it).
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

/// The input element.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum NonlinearityArg {
    /// Backlash (play operator): two paths, Table I data.
    Backlash,
    /// Switch (hysteresis relay with borders): two paths.
    Switch,
    /// Static, memoryless: one border for both directions, any input.
    Static,
}

impl From<NonlinearityArg> for NonlinearityKind {
    fn from(n: NonlinearityArg) -> Self {
        match n {
            NonlinearityArg::Backlash => NonlinearityKind::Backlash,
            NonlinearityArg::Switch => NonlinearityKind::Switch,
            NonlinearityArg::Static => NonlinearityKind::Static,
        }
    }
}

impl From<NonlinearityArg> for Nonlinearity {
    fn from(n: NonlinearityArg) -> Self {
        match n {
            NonlinearityArg::Backlash => Nonlinearity::Backlash,
            NonlinearityArg::Switch => Nonlinearity::Switch,
            NonlinearityArg::Static => Nonlinearity::Static,
        }
    }
}

/// Reads the columns `u, y` named by `columns` from `data` (a file, or `-` for standard input).
pub fn read_uy(data: &Path, columns: &Columns, csv: &CsvArgs) -> Result<Table, String> {
    let names = [
        columns.input_column.as_str(),
        columns.output_column.as_str(),
    ];
    let options = CsvOptions {
        delimiter: csv.delimiter(),
    };
    read_table(data, &names, &options).map_err(|e| e.to_string())
}
