//! How a subcommand ends when it does not succeed: with a message for the user, or quietly
//! because the reader of its standard output went away (`hsid validate … | head -1`).

use std::fmt;
use std::io::{self, ErrorKind};

use hsid_host::io::{FileAction, FileError, IoError};

/// A subcommand's failure.
#[derive(Debug)]
pub enum Failure {
    /// Something the user must read (printed as `hsid: …`, exit code 1).
    Message(String),
    /// Standard output was closed by its reader: the command stops quietly, with exit code 0,
    /// as `head`, `grep -q` and the shell expect.
    OutputClosed,
}

impl fmt::Display for Failure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Failure::Message(m) => f.write_str(m),
            Failure::OutputClosed => f.write_str("standard output closed"),
        }
    }
}

impl From<String> for Failure {
    fn from(m: String) -> Self {
        Failure::Message(m)
    }
}

impl From<io::Error> for Failure {
    fn from(e: io::Error) -> Self {
        if e.kind() == ErrorKind::BrokenPipe {
            Failure::OutputClosed
        } else {
            Failure::Message(format!("standard output: {e}"))
        }
    }
}

impl From<IoError> for Failure {
    fn from(e: IoError) -> Self {
        match e {
            IoError::File(FileError {
                action: FileAction::Write,
                source,
                ..
            }) if source.kind() == ErrorKind::BrokenPipe => Failure::OutputClosed,
            e => Failure::Message(e.to_string()),
        }
    }
}

/// `println!` that returns the write's result instead of panicking when the pipe is closed.
macro_rules! outln {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        writeln!(std::io::stdout().lock(), $($arg)*)
    }};
}
pub(crate) use outln;
