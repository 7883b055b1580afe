//! What can go wrong making the page.

use std::path::PathBuf;

/// An error making or writing the HTML report.
#[derive(Debug, thiserror::Error)]
pub enum HtmlError {
    /// A scratch folder for the figures could not be made or read.
    #[error(
        "{path}: cannot use this scratch folder for the report's figures: {source} \
         (set TMPDIR to a writable folder)"
    )]
    Scratch {
        /// The folder.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// A figure file could not be read.
    #[error("{path}: cannot read the figure: {source}")]
    ReadFigure {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// A figure file holds no `<svg>` element.
    #[error("{path}: holds no <svg> element, so it cannot be inlined in the report")]
    NotSvg {
        /// The file.
        path: PathBuf,
    },
    /// Drawing the figures failed.
    #[error("the report's figures: {0}")]
    Figures(String),
    /// The page could not be written.
    #[error(
        "{path}: cannot write the HTML report: {source} (check that the folder exists and \
         is writable)"
    )]
    Write {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
}
