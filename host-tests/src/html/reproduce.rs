//! The last section: the command line exactly as run (each argument quoted for a POSIX
//! shell), the hsid version, and every input file's name and size in bytes.

use std::fmt::Write as _;
use std::path::Path;

use super::escape::escape;

/// One input file of the run.
#[derive(Clone, Debug, PartialEq)]
pub struct InputFile {
    /// Its name as given on the command line.
    pub name: String,
    /// Its size in bytes; `None` for standard input or a file that could not be read.
    pub bytes: Option<u64>,
}

/// What a reader needs to run the same command again.
#[derive(Clone, Debug, PartialEq)]
pub struct Reproduction {
    /// The arguments, the program first.
    pub argv: Vec<String>,
    /// The hsid version.
    pub version: String,
    /// The input files.
    pub inputs: Vec<InputFile>,
}

impl Reproduction {
    /// This process's command line and version, with the sizes of `inputs` now.
    pub fn of_this_run<P: AsRef<Path>>(inputs: &[P]) -> Self {
        Reproduction {
            argv: std::env::args_os()
                .map(|a| a.to_string_lossy().into_owned())
                .collect(),
            version: env!("CARGO_PKG_VERSION").to_string(),
            inputs: inputs
                .iter()
                .map(|p| {
                    let p = p.as_ref();
                    InputFile {
                        name: p.display().to_string(),
                        bytes: (p != Path::new("-"))
                            .then(|| std::fs::metadata(p).ok().map(|m| m.len()))
                            .flatten(),
                    }
                })
                .collect(),
        }
    }

    /// The command line as one line a POSIX shell reads back into the same arguments.
    pub fn command(&self) -> String {
        self.argv
            .iter()
            .map(|a| quote(a))
            .collect::<Vec<_>>()
            .join(" ")
    }

    /// The section's content as HTML.
    pub fn html(&self) -> String {
        let mut s = String::from("<p>The command as run:</p>\n");
        let _ = writeln!(
            s,
            "<pre class=\"command\">{}</pre>",
            escape(&self.command())
        );
        let _ = writeln!(s, "<p>hsid version {}.</p>", escape(&self.version));
        s.push_str("<table class=\"inputs\">\n<tr><th>input file</th><th>size (bytes)</th></tr>\n");
        for f in &self.inputs {
            let size = f.bytes.map_or_else(
                || "— (standard input or unreadable)".to_string(),
                |b| b.to_string(),
            );
            let _ = writeln!(
                s,
                "<tr><td>{}</td><td class=\"num\">{}</td></tr>",
                escape(&f.name),
                size
            );
        }
        s.push_str("</table>\n");
        s
    }
}

/// `a` as one POSIX shell word: unchanged when it holds only safe characters, otherwise in
/// single quotes with each `'` written `'\''`.
pub fn quote(a: &str) -> String {
    let safe = !a.is_empty()
        && a.chars()
            .all(|c| c.is_ascii_alphanumeric() || "-_./=:,+@%".contains(c));
    if safe {
        a.to_string()
    } else {
        format!("'{}'", a.replace('\'', "'\\''"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn arguments_are_quoted_for_the_shell() {
        assert_eq!(quote("--data"), "--data");
        assert_eq!(quote("a b.csv"), "'a b.csv'");
        assert_eq!(quote("it's"), "'it'\\''s'");
        assert_eq!(quote(""), "''");
        assert_eq!(quote("<x>&"), "'<x>&'");
    }
}
