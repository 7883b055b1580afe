//! The first section: the result in sentences, then label–value facts (the model in units,
//! the fit) and tables (for `diagnose`, the errors before and after).

use std::fmt::Write as _;

use super::escape::escape;

/// One labelled value of the headline, plain text.
#[derive(Clone, Debug, PartialEq)]
pub struct Fact {
    /// What the value is (e.g. `mean gap`).
    pub label: String,
    /// The value with its unit.
    pub value: String,
}

impl Fact {
    /// A fact from anything printable.
    pub fn new(label: impl Into<String>, value: impl Into<String>) -> Self {
        Fact {
            label: label.into(),
            value: value.into(),
        }
    }
}

/// A table of plain-text cells; cells that parse as numbers are aligned right.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct TextTable {
    /// The sentence above the table.
    pub caption: String,
    /// Column headings.
    pub header: Vec<String>,
    /// Rows of cells.
    pub rows: Vec<Vec<String>>,
}

impl TextTable {
    /// The table as HTML; a table without header and rows is its caption alone.
    pub fn html(&self) -> String {
        let mut s = String::new();
        if !self.caption.is_empty() {
            let _ = writeln!(s, "<p>{}</p>", escape(&self.caption));
        }
        if self.header.is_empty() && self.rows.is_empty() {
            return s;
        }
        s.push_str("<table>\n<tr>");
        for h in &self.header {
            let _ = write!(s, "<th>{}</th>", escape(h));
        }
        s.push_str("</tr>\n");
        for row in &self.rows {
            s.push_str("<tr>");
            for c in row {
                let class = if numeric(c) { " class=\"num\"" } else { "" };
                let _ = write!(s, "<td{class}>{}</td>", escape(c));
            }
            s.push_str("</tr>\n");
        }
        s.push_str("</table>\n");
        s
    }
}

/// Whether a cell reads as a number (possibly with a sign, a percent sign or `±`).
fn numeric(c: &str) -> bool {
    let t = c.trim_end_matches(" %");
    !t.is_empty()
        && t.split(" ± ")
            .all(|p| p.trim_start_matches(['+', '−']).parse::<f64>().is_ok())
}

/// The headline: sentences, facts, tables.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Headline {
    /// The result in sentences, plain text.
    pub lead: Vec<String>,
    /// The model and the fit, one value each.
    pub facts: Vec<Fact>,
    /// Further tables (before/after).
    pub tables: Vec<TextTable>,
}

impl Headline {
    /// The section's content as HTML.
    pub fn html(&self) -> String {
        let mut s = String::new();
        for p in &self.lead {
            let _ = writeln!(s, "<p class=\"lead\">{}</p>", escape(p));
        }
        if !self.facts.is_empty() {
            s.push_str("<table class=\"facts\">\n");
            for f in &self.facts {
                let _ = writeln!(
                    s,
                    "<tr><th>{}</th><td>{}</td></tr>",
                    escape(&f.label),
                    escape(&f.value)
                );
            }
            s.push_str("</table>\n");
        }
        for t in &self.tables {
            s.push_str(&t.html());
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cells_are_escaped_and_numbers_aligned() {
        let t = TextTable {
            caption: "a <b> & c".into(),
            header: vec!["x".into(), "y".into()],
            rows: vec![vec!["1.5 ± 0.2".into(), "<i>".into()]],
        };
        let h = t.html();
        assert!(h.contains("<p>a &lt;b&gt; &amp; c</p>"), "{h}");
        assert!(
            h.contains("<td class=\"num\">1.5 ± 0.2</td><td>&lt;i&gt;</td>"),
            "{h}"
        );
        assert!(numeric("83.00 %") && numeric("-0.5") && !numeric("none"));
    }
}
