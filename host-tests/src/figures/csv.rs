//! Writing one figure's files: the SVG and the CSV of every curve it plots.

use std::path::{Path, PathBuf};

use super::error::FigureError;
use crate::io::write_columns;
use crate::plot::Figure;

/// One table of a figure: column names (series and unit) and equally long columns.
#[derive(Debug, Default)]
pub(super) struct Table {
    names: Vec<String>,
    columns: Vec<Vec<f64>>,
}

impl Table {
    /// Adds a column.
    pub(super) fn col(&mut self, name: impl Into<String>, values: Vec<f64>) -> &mut Self {
        self.names.push(name.into());
        self.columns.push(values);
        self
    }

    /// Writes `DIR/STEM.csv`.
    pub(super) fn save(&self, dir: &Path, stem: &str) -> Result<PathBuf, FigureError> {
        let path = dir.join(format!("{stem}.csv"));
        let names: Vec<&str> = self.names.iter().map(String::as_str).collect();
        write_columns(&path, &names, &self.columns)?;
        Ok(path)
    }
}

/// Writes `DIR/STEM.svg`.
pub(super) fn save_svg(fig: &Figure, dir: &Path, stem: &str) -> Result<PathBuf, FigureError> {
    let path = dir.join(format!("{stem}.svg"));
    fig.save(&path)?;
    Ok(path)
}
