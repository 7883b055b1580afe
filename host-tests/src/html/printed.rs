//! The tables a command prints (Markdown pipe tables between sentences) as page tables, cell
//! for cell: the page shows the very strings the terminal showed, so the two cannot disagree.

use super::headline::TextTable;

/// The blocks of `text` (separated by blank lines) as tables: a block of `|` lines is a table
/// (its first line the header, a `|---|` line skipped), the sentences before it its caption;
/// sentences after the last table become a caption-only table (a paragraph).
pub fn tables(text: &str) -> Vec<TextTable> {
    let mut out = Vec::new();
    let mut caption: Vec<&str> = Vec::new();
    for block in text.split("\n\n") {
        let lines: Vec<&str> = block
            .lines()
            .map(str::trim)
            .filter(|l| !l.is_empty())
            .collect();
        if lines.is_empty() {
            continue;
        }
        if !lines.iter().all(|l| l.starts_with('|')) {
            caption.extend(lines);
            continue;
        }
        let mut rows: Vec<Vec<String>> = lines
            .iter()
            .map(|l| cells(l))
            .filter(|r| !r.iter().all(|c| c.starts_with("---")))
            .collect();
        let header = if rows.is_empty() {
            Vec::new()
        } else {
            rows.remove(0)
        };
        out.push(TextTable {
            caption: std::mem::take(&mut caption).join(" "),
            header,
            rows,
        });
    }
    if !caption.is_empty() {
        out.push(TextTable {
            caption: caption.join(" "),
            ..TextTable::default()
        });
    }
    out
}

/// The cells of one `| a | b |` line, trimmed.
fn cells(line: &str) -> Vec<String> {
    let inner = line.trim().trim_start_matches('|').trim_end_matches('|');
    inner.split('|').map(|c| c.trim().to_string()).collect()
}

#[cfg(test)]
mod tests {
    use super::tables;

    #[test]
    fn printed_tables_keep_their_cells_and_captions() {
        let text = "Monte Carlo: 3 runs\n\n| case | pole |\n|---|---|\n| switch | 0.94 ± 0.12j |\n\
                    | backlash | (0.0051, 0.0041) |\n\nnote one\nnote two\n";
        let t = tables(text);
        assert_eq!(t.len(), 2);
        assert_eq!(t[0].caption, "Monte Carlo: 3 runs");
        assert_eq!(t[0].header, ["case", "pole"]);
        assert_eq!(
            t[0].rows,
            [
                vec!["switch".to_string(), "0.94 ± 0.12j".to_string()],
                vec!["backlash".to_string(), "(0.0051, 0.0041)".to_string()],
            ]
        );
        assert_eq!(t[1].caption, "note one note two");
        assert!(t[1].header.is_empty() && t[1].rows.is_empty());
    }
}
