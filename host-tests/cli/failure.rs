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

/// `message` as one line for the terminal: control characters (a line break, ESC, BEL, NUL
/// from a field, a header or a unit quoted in the message) are written as escapes (`\n`,
/// `\u{1b}`), so an input cannot add a line or drive the terminal.
pub fn one_line(message: &str) -> String {
    let mut line = String::with_capacity(message.len());
    for c in message.chars() {
        match c.is_control() {
            true => line.extend(c.escape_default()),
            false => line.push(c),
        }
    }
    line
}

/// Set once standard output's reader went away: later lines are not written, and the command
/// ends quietly (exit code 0) once its files are written.
static STDOUT_CLOSED: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// Whether standard output's reader went away during the run.
pub fn stdout_closed() -> bool {
    STDOUT_CLOSED.load(std::sync::atomic::Ordering::Relaxed)
}

/// A line for standard output: written unless its reader went away. A closed pipe (`hsid
/// identify … --json m.json | head -1`) does not stop the command: the files it was asked for
/// are still written, whole ([`hsid_host::io::write_atomic`]); any other write error is the
/// command's failure.
pub fn out_line(line: std::fmt::Arguments<'_>) -> Result<(), Failure> {
    use std::io::Write as _;
    if stdout_closed() {
        return Ok(());
    }
    match writeln!(io::stdout().lock(), "{line}") {
        Err(e) if e.kind() == ErrorKind::BrokenPipe => {
            STDOUT_CLOSED.store(true, std::sync::atomic::Ordering::Relaxed);
            Ok(())
        }
        r => r.map_err(Failure::from),
    }
}

/// A note on standard error, `hsid: note: …` on one line (not silenced by `--quiet`, which
/// silences the progress lines): what the run did with its input that the user did not ask
/// for in so many words. A closed standard error is ignored.
pub fn note(message: &str) {
    use std::io::Write as _;
    let _ = writeln!(io::stderr().lock(), "hsid: note: {}", one_line(message));
}

/// `println!` that does not panic when the pipe is closed ([`out_line`]).
macro_rules! outln {
    ($($arg:tt)*) => {
        $crate::failure::out_line(format_args!($($arg)*))
    };
}
pub(crate) use outln;

#[cfg(test)]
mod tests {
    use super::one_line;

    #[test]
    fn control_characters_are_escaped_and_the_rest_kept() {
        assert_eq!(
            one_line("bad \"V\nhsid: injected\" at ä\u{1b}[31m\u{7}\0"),
            "bad \"V\\nhsid: injected\" at ä\\u{1b}[31m\\u{7}\\u{0}"
        );
    }
}
