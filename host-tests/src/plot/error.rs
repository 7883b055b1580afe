//! What can go wrong building or saving a figure.

use std::path::PathBuf;

/// Errors from building or saving a figure.
#[derive(Debug)]
pub enum PlotError {
    /// The coordinate vectors of a series have different lengths.
    LengthMismatch {
        /// 0-based position of the series in the figure.
        series: usize,
        /// Its legend label, if any.
        label: Option<String>,
        /// Description of the mismatch, e.g. `x has 10 values, y has 9`.
        detail: String,
    },
    /// An explicit axis range is not finite, empty or reversed, or not positive on a log axis.
    InvalidRange {
        /// `"x"` or `"y"`.
        axis: &'static str,
        /// Lower end.
        min: f64,
        /// Upper end.
        max: f64,
    },
    /// The figure is too small to hold its axes (minimum 200×150 px).
    InvalidSize {
        /// Requested width in px.
        width: u32,
        /// Requested height in px.
        height: u32,
    },
    /// The SVG file could not be written.
    Io {
        /// Target file.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
}

impl std::fmt::Display for PlotError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            PlotError::LengthMismatch {
                series,
                label,
                detail,
            } => match label {
                Some(l) => write!(f, "series {series} (\"{l}\"): {detail}"),
                None => write!(f, "series {series}: {detail}"),
            },
            PlotError::InvalidRange { axis, min, max } => {
                write!(f, "invalid {axis} axis range [{min}, {max}]")
            }
            PlotError::InvalidSize { width, height } => {
                write!(f, "figure size {width}×{height} px is below 200×150 px")
            }
            PlotError::Io { path, source } => {
                write!(f, "{}: cannot write figure: {source}", path.display())
            }
        }
    }
}

impl std::error::Error for PlotError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            PlotError::Io { source, .. } => Some(source),
            _ => None,
        }
    }
}
