//! A figure inlined in the page: the SVG text made safe to sit beside others in one document
//! (its ids prefixed, its XML prolog and namespace URL dropped, which HTML does not need), with
//! a title and a caption that says what to look at.

use std::fmt::Write as _;

use super::escape::escape;

/// One inline figure.
#[derive(Clone, Debug, PartialEq)]
pub struct InlineFigure {
    /// Short title, plain text.
    pub title: String,
    /// What to look at, plain text.
    pub caption: String,
    /// The `<svg>` element, already made unique in the page by [`inline_svg`].
    pub svg: String,
}

impl InlineFigure {
    /// The figure as a `<figure>` element.
    pub fn html(&self) -> String {
        let mut s = String::from("<figure>\n");
        s.push_str(&self.svg);
        let _ = write!(
            s,
            "\n<figcaption><b>{}.</b> {}</figcaption>\n</figure>\n",
            escape(&self.title),
            escape(&self.caption)
        );
        s
    }
}

/// The SVG document `svg` as an element of an HTML page: everything before `<svg` dropped,
/// the SVG namespace attribute dropped (HTML parsers place `<svg>` in it by themselves), and
/// every `id` renamed `{prefix}-{id}` together with its `url(#id)` and `href="#id"` references,
/// so that figures drawn with the same clip-path ids do not clip each other. `None` when the
/// text holds no `<svg` element.
pub fn inline_svg(svg: &str, prefix: &str) -> Option<String> {
    let start = svg.find("<svg")?;
    let mut s = svg[start..]
        .trim_end()
        .replacen(" xmlns=\"http://www.w3.org/2000/svg\"", "", 1);
    for id in ids(&s) {
        let new = format!("{prefix}-{id}");
        s = s
            .replace(&format!("id=\"{id}\""), &format!("id=\"{new}\""))
            .replace(&format!("url(#{id})"), &format!("url(#{new})"))
            .replace(&format!("href=\"#{id}\""), &format!("href=\"#{new}\""));
    }
    Some(s)
}

/// The distinct values of the `id` attributes in `s`, in order of first appearance.
fn ids(s: &str) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    let mut rest = s;
    while let Some(i) = rest.find(" id=\"") {
        rest = &rest[i + 5..];
        let Some(end) = rest.find('"') else { break };
        let id = rest[..end].to_string();
        if !out.contains(&id) {
            out.push(id);
        }
        rest = &rest[end..];
    }
    out
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;

    #[test]
    fn ids_are_prefixed_with_their_references() {
        let svg = "<?xml version=\"1.0\"?>\n<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"10\">\
                   <clipPath id=\"plot-area\"><rect/></clipPath>\
                   <g clip-path=\"url(#plot-area)\"><use href=\"#plot-area\"/></g></svg>\n";
        let s = inline_svg(svg, "fig2").unwrap();
        assert_eq!(
            s,
            "<svg width=\"10\"><clipPath id=\"fig2-plot-area\"><rect/></clipPath>\
             <g clip-path=\"url(#fig2-plot-area)\"><use href=\"#fig2-plot-area\"/></g></svg>"
        );
        assert_eq!(inline_svg("not a figure", "x"), None);
    }
}
