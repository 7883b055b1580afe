//! Escaping text for HTML: every string that reaches the page from outside (file names, column
//! names, units, command-line arguments, findings) goes through [`escape`].

pub use crate::plot::escape;

#[cfg(test)]
mod tests {
    use super::escape;

    #[test]
    fn markup_and_ampersands_are_escaped() {
        assert_eq!(
            escape("<script>alert('a&b')</script> \"x\""),
            "&lt;script&gt;alert(&apos;a&amp;b&apos;)&lt;/script&gt; &quot;x&quot;"
        );
        assert_eq!(escape("plain 1.5 V"), "plain 1.5 V");
        // Control characters are not allowed in XML (the page embeds SVG): dropped.
        assert_eq!(escape("a\u{1}b\tc"), "ab\tc");
    }
}
