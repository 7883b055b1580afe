//! What can go wrong building or saving a figure.

use std::path::PathBuf;

/// Errors from building or saving a figure.
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    /// The coordinate vectors of a series have different lengths.
    #[error("series {series}{}: {detail}", labelled(.label.as_deref()))]
    LengthMismatch {
        /// 0-based position of the series in the figure.
        series: usize,
        /// Its legend label, if any.
        label: Option<String>,
        /// Description of the mismatch, e.g. `x has 10 values, y has 9`.
        detail: String,
    },
    /// An explicit axis range is not finite, empty or reversed, or not positive on a log axis.
    #[error("invalid {axis} axis range [{min}, {max}]")]
    InvalidRange {
        /// `"x"` or `"y"`.
        axis: &'static str,
        /// Lower end.
        min: f64,
        /// Upper end.
        max: f64,
    },
    /// The figure is too small to hold its axes (minimum 200×150 px).
    #[error("figure size {width}×{height} px is below 200×150 px")]
    InvalidSize {
        /// Requested width in px.
        width: u32,
        /// Requested height in px.
        height: u32,
    },
    /// The SVG file could not be written.
    #[error("{path}: cannot write figure: {source}")]
    Io {
        /// Target file.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
}

/// ` ("label")` after a series' number, or nothing without a label.
fn labelled(label: Option<&str>) -> String {
    label.map_or_else(String::new, |l| format!(" (\"{l}\")"))
}
