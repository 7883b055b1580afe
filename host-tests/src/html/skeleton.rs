//! The page around the sections: the document head with the inline style sheet (screen and
//! print), the title and the table of contents. Nothing is loaded from outside.

use super::escape::escape;

/// The style sheet. Figures scale to the text width and are never split across printed
/// pages; tables of numbers align right.
const STYLE: &str = "
body{font-family:'DejaVu Sans','Liberation Sans',Arial,Helvetica,sans-serif;color:#111;
 max-width:62rem;margin:1.5rem auto;padding:0 1rem;line-height:1.45;font-size:15px}
h1{font-size:1.6rem;margin-bottom:.2rem}
h2{font-size:1.25rem;border-bottom:1px solid #bbb;margin-top:2rem;padding-bottom:.2rem}
p.lead{font-size:1.08rem}
nav{font-size:.9rem;color:#444}
nav a{margin-right:1rem}
table{border-collapse:collapse;margin:.6rem 0 1rem}
th,td{border:1px solid #ccc;padding:.25rem .5rem;text-align:left;vertical-align:top}
th{background:#f1f1f1}
table.facts th{width:15rem}
td.num{text-align:right;font-variant-numeric:tabular-nums;white-space:nowrap}
tr.fired td{background:#fde9e7}
td.fired{font-weight:bold;color:#a40000}
figure{margin:1.2rem 0;break-inside:avoid;page-break-inside:avoid}
figure svg{display:block;width:100%;max-width:800px;height:auto}
figcaption{font-size:.93rem;color:#333;max-width:800px}
figcaption b{color:#111}
pre{background:#f4f4f4;padding:.6rem;white-space:pre-wrap;overflow-wrap:anywhere;font-size:.88rem}
@media print{
 body{max-width:none;margin:0;padding:0;font-size:11pt}
 nav{display:none}
 figure svg{max-width:100%;max-height:22cm}
 h2{break-after:avoid;page-break-after:avoid}
 table,tr{break-inside:avoid;page-break-inside:avoid}
}
";

/// The sections of the page, in order: (anchor, heading).
pub(crate) const SECTIONS: [(&str, &str); 4] = [
    ("headline", "Result"),
    ("figures", "Figures"),
    ("checks", "Data checks and residual tests"),
    ("reproduce", "Reproduce this report"),
];

/// A complete HTML document titled `title` around `body` (already HTML); the table of
/// contents lists the sections `body` holds.
pub fn document(title: &str, body: &str) -> String {
    let title = escape(title);
    let nav: String = SECTIONS
        .iter()
        .filter(|(id, _)| body.contains(&format!("<section id=\"{id}\">")))
        .map(|(id, h)| format!("<a href=\"#{id}\">{h}</a>"))
        .collect();
    format!(
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n\
         <title>{title}</title>\n<style>{STYLE}</style>\n</head>\n<body>\n\
         <h1>{title}</h1>\n<nav>{nav}</nav>\n{body}</body>\n</html>\n"
    )
}

/// A section with its anchor and heading around `inner` (already HTML).
pub fn section(index: usize, inner: &str) -> String {
    let (id, h) = SECTIONS[index.min(SECTIONS.len() - 1)];
    format!("<section id=\"{id}\">\n<h2>{h}</h2>\n{inner}</section>\n")
}
