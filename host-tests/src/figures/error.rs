//! What can go wrong writing the figures of a model.

use std::path::PathBuf;

use crate::io::IoError;
use crate::plot::PlotError;

/// Errors from [`write_figures`](super::write_figures).
#[derive(Debug)]
pub enum FigureError {
    /// The output directory could not be created.
    CreateDir {
        /// The directory.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
    /// A sample time that is not a positive finite number of seconds.
    InvalidSampleTime(f64),
    /// The record's `u` and `y` differ in length, or the skipped start leaves nothing.
    InvalidRecord {
        /// Samples of `u`.
        u: usize,
        /// Samples of `y`.
        y: usize,
        /// Samples left out at the start.
        skip: usize,
    },
    /// A figure could not be drawn or saved.
    Plot(PlotError),
    /// A CSV file could not be written.
    Csv(IoError),
}

impl std::fmt::Display for FigureError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::CreateDir { path, source } => write!(
                f,
                "{}: cannot create the figure directory: {source} (give a writable --out DIR)",
                path.display()
            ),
            Self::InvalidSampleTime(ts) => write!(
                f,
                "sample time {ts} s: it must be a positive finite number of seconds"
            ),
            Self::InvalidRecord { u, y, skip } => write!(
                f,
                "record of {u} inputs and {y} outputs with {skip} skipped at the start: the \
                 figures need equal lengths and at least 2 samples after the skipped ones"
            ),
            Self::Plot(e) => write!(f, "{e}"),
            Self::Csv(e) => write!(f, "{e}"),
        }
    }
}

impl std::error::Error for FigureError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::CreateDir { source, .. } => Some(source),
            Self::Plot(e) => Some(e),
            Self::Csv(e) => Some(e),
            Self::InvalidSampleTime(_) | Self::InvalidRecord { .. } => None,
        }
    }
}

impl From<PlotError> for FigureError {
    fn from(e: PlotError) -> Self {
        Self::Plot(e)
    }
}

impl From<IoError> for FigureError {
    fn from(e: IoError) -> Self {
        Self::Csv(e)
    }
}
