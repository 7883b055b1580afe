//! What can go wrong making the page.

use std::fmt;
use std::path::PathBuf;

/// An error making or writing the HTML report.
#[derive(Debug)]
pub enum HtmlError {
    /// A scratch folder for the figures could not be made or read.
    Scratch {
        /// The folder.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// A figure file could not be read.
    ReadFigure {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// A figure file holds no `<svg>` element.
    NotSvg {
        /// The file.
        path: PathBuf,
    },
    /// Drawing the figures failed.
    Figures(String),
    /// The page could not be written.
    Write {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
}

impl fmt::Display for HtmlError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            HtmlError::Scratch { path, source } => write!(
                f,
                "{}: cannot use this scratch folder for the report's figures: {source} \
                 (set TMPDIR to a writable folder)",
                path.display()
            ),
            HtmlError::ReadFigure { path, source } => {
                write!(f, "{}: cannot read the figure: {source}", path.display())
            }
            HtmlError::NotSvg { path } => write!(
                f,
                "{}: holds no <svg> element, so it cannot be inlined in the report",
                path.display()
            ),
            HtmlError::Figures(e) => write!(f, "the report's figures: {e}"),
            HtmlError::Write { path, source } => write!(
                f,
                "{}: cannot write the HTML report: {source} (check that the folder exists and \
                 is writable)",
                path.display()
            ),
        }
    }
}

impl std::error::Error for HtmlError {}
