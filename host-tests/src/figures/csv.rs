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

/// Legend text of a ±2σ band: the range of its half width, since a narrow band hides under
/// its curve (`sd` are the standard deviations; half widths below a millionth of the largest,
/// e.g. at a point fixed by the normalisation, are left out of the range).
pub(super) fn band_label(name: &str, sd: &[f64], unit: &str) -> String {
    let hi = sd.iter().map(|s| 2.0 * s).fold(0.0, f64::max);
    let lo = sd
        .iter()
        .map(|s| 2.0 * s)
        .filter(|h| *h > 1e-6 * hi)
        .fold(f64::INFINITY, f64::min);
    let head = if name.is_empty() {
        "±2σ".to_string()
    } else {
        format!("{name} ±2σ")
    };
    if lo.is_finite() {
        format!("{head}: {} to {}{unit}", two_digits(lo), two_digits(hi))
    } else {
        head
    }
}

/// A positive number with two significant digits (`0.0031`, `0.42`, `8.1`, `120`).
fn two_digits(v: f64) -> String {
    let decimals = (1.0 - v.log10().floor()).max(0.0) as usize;
    format!("{v:.decimals$}")
}

/// Writes `DIR/STEM.svg`.
pub(super) fn save_svg(fig: &Figure, dir: &Path, stem: &str) -> Result<PathBuf, FigureError> {
    let path = dir.join(format!("{stem}.svg"));
    fig.save(&path)?;
    Ok(path)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn band_labels_give_the_half_width_range() {
        assert_eq!(two_digits(0.003_14), "0.0031");
        assert_eq!(two_digits(8.14), "8.1");
        assert_eq!(two_digits(123.0), "123");
        assert_eq!(
            band_label("P_a", &[0.0, 0.01, 0.2], ""),
            "P_a ±2σ: 0.020 to 0.40"
        );
        assert_eq!(band_label("", &[0.5], " dB"), "±2σ: 1.0 to 1.0 dB");
        assert_eq!(band_label("P_d", &[0.0], ""), "P_d ±2σ");
        assert_eq!(band_label("", &[1e-14, 0.5], "°"), "±2σ: 1.0 to 1.0°");
    }
}
