//! What can go wrong writing the figures of a model.

use std::path::PathBuf;

use crate::io::IoError;
use crate::plot::PlotError;

/// Errors from [`write_figures`](super::write_figures).
#[derive(Debug, thiserror::Error)]
pub enum FigureError {
    /// The output directory could not be created.
    #[error("{path}: cannot create the figure directory: {source} (give a writable --out DIR)")]
    CreateDir {
        /// The directory.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
    /// A sample time that is not a positive finite number of seconds.
    #[error("sample time {0} s: it must be a positive finite number of seconds")]
    InvalidSampleTime(f64),
    /// The record's `u` and `y` differ in length, or the skipped start leaves nothing.
    #[error(
        "record of {u} inputs and {y} outputs with {skip} skipped at the start: the \
         figures need equal lengths and at least 2 samples after the skipped ones"
    )]
    InvalidRecord {
        /// Samples of `u`.
        u: usize,
        /// Samples of `y`.
        y: usize,
        /// Samples left out at the start.
        skip: usize,
    },
    /// A figure could not be drawn or saved.
    #[error("{0}")]
    Plot(#[from] PlotError),
    /// A CSV file could not be written.
    #[error("{0}")]
    Csv(#[from] IoError),
}
