//! Escaping text for HTML: every string that reaches the page from outside (file names, column
//! names, units, command-line arguments, findings) goes through [`escape`].

/// `s` with `& < > " '` replaced by their character references, safe in element content and in
/// quoted attribute values.
pub fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            c => out.push(c),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::escape;

    #[test]
    fn markup_and_ampersands_are_escaped() {
        assert_eq!(
            escape("<script>alert('a&b')</script> \"x\""),
            "&lt;script&gt;alert(&#39;a&amp;b&#39;)&lt;/script&gt; &quot;x&quot;"
        );
        assert_eq!(escape("plain 1.5 V"), "plain 1.5 V");
    }
}
