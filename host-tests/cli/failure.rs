//! How a subcommand ends when it does not succeed: with a message for the user, or quietly
//! because the reader of its standard output went away (`hsid validate … | head -1`).

use std::fmt;
use std::io::{self, ErrorKind};

use hsid_host::io::{FileAction, FileError, IoError};
use hsid_host::plot::PlotError;
use hsid_host::refine::stochastic::NoiseFileError;
use hsid_host::report::UndefinedFit;

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

/// Errors of the library that the user reads as they are.
macro_rules! message_from {
    ($($t:ty),* $(,)?) => {$(
        impl From<$t> for Failure {
            fn from(e: $t) -> Self {
                Failure::Message(e.to_string())
            }
        }
    )*};
}
message_from!(UndefinedFit, NoiseFileError, PlotError);

/// `println!` that returns the write's result instead of panicking when the pipe is closed.
macro_rules! outln {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        writeln!(std::io::stdout().lock(), $($arg)*)
    }};
}
pub(crate) use outln;
