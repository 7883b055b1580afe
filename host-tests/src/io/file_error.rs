//! A file that could not be opened, read, created or written: the part of every file error
//! that is about the file system rather than the file's content.

use std::path::{Path, PathBuf};

/// What was being done with the file when the file system refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FileAction {
    /// Opening or reading the file.
    Read,
    /// Creating or writing the file.
    Write,
}

/// The file system refused to open, read, create or write a file.
///
/// `Display` gives one line that starts with the file name, e.g.
/// `data.csv: cannot read file: No such file or directory (os error 2)`.
#[derive(Debug, thiserror::Error)]
#[error("{path}: cannot {} file: {source}", verb(*.action))]
pub struct FileError {
    /// The file.
    pub path: PathBuf,
    /// Reading or writing.
    pub action: FileAction,
    /// The underlying error.
    pub source: std::io::Error,
}

impl FileError {
    /// `path` could not be opened or read.
    pub fn read(path: &Path, source: std::io::Error) -> Self {
        Self {
            path: path.to_path_buf(),
            action: FileAction::Read,
            source,
        }
    }

    /// `path` could not be created or written.
    pub fn write(path: &Path, source: std::io::Error) -> Self {
        Self {
            path: path.to_path_buf(),
            action: FileAction::Write,
            source,
        }
    }
}

/// The verb of the message.
fn verb(action: FileAction) -> &'static str {
    match action {
        FileAction::Read => "read",
        FileAction::Write => "write",
    }
}
