//! A record's header comments: the `# key = value` lines among the comment lines that open
//! it, as `hsid simulate` writes them (`# ts = 0.01 s`, `# input unit = V`).

/// One `# key = value` line of a record's header.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct HeaderComment<'a> {
    /// Its 1-based line.
    pub line: usize,
    /// The key, trimmed (`ts`, `input unit`).
    pub key: &'a str,
    /// The value after the first `=`, trimmed (may be empty).
    pub value: &'a str,
    /// The whole line, trimmed, for messages.
    pub text: &'a str,
}

/// The `# key = value` lines of `text`'s header: the lines starting with `#` before the first
/// other non-blank line (blank lines are skipped). Comment lines without `=` are not
/// key–value lines and are passed over.
pub fn header_comments(text: &str) -> impl Iterator<Item = HeaderComment<'_>> {
    text.lines()
        .enumerate()
        .map(|(i, line)| (i + 1, line.trim()))
        .filter(|(_, line)| !line.is_empty())
        .map_while(|(line, text)| text.strip_prefix('#').map(|c| (line, text, c)))
        .filter_map(|(line, text, comment)| {
            let (key, value) = comment.split_once('=')?;
            Some(HeaderComment {
                line,
                key: key.trim(),
                value: value.trim(),
                text,
            })
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_key_value_comments_until_the_first_other_line() {
        let text =
            "# made by hsid\n\n#ts = 0.01 s\n# input unit =  V \n# empty =\nu,y\n# ts = 9 s\n";
        let found: Vec<(usize, &str, &str)> = header_comments(text)
            .map(|c| (c.line, c.key, c.value))
            .collect();
        assert_eq!(
            found,
            [
                (3, "ts", "0.01 s"),
                (4, "input unit", "V"),
                (5, "empty", "")
            ]
        );
    }
}
