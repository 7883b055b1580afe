//! The data checks and residual tests as one table: statistic, threshold, p-value and whether
//! it fired, and for each finding what it found, what that means and what to do.

use std::fmt::Write as _;

use super::advice::{check_advice, test_advice};
use super::escape::escape;
use crate::diagnose::{Check, TestSet, Warning};

/// One row of the table.
#[derive(Clone, Debug, PartialEq)]
pub struct CheckRow {
    /// Check or test name, with what it ran on (e.g. `whiteness (validation, after)`).
    pub name: String,
    /// Test statistic (none for a data check).
    pub statistic: Option<f64>,
    /// Critical value (none for a data check).
    pub threshold: Option<f64>,
    /// p-value (none for a data check).
    pub p_value: Option<f64>,
    /// Whether it fired (a data check: whether it warned).
    pub fired: bool,
    /// What it found, in words.
    pub finding: String,
    /// What a firing means and what to do (empty when it did not fire).
    pub advice: String,
}

/// One row per data check of `run` (the checks that ran, [`BEFORE_FIT`](super::advice::BEFORE_FIT)
/// or [`CHECKS`](super::advice::CHECKS)): the warnings of `warnings`, the others passed. A
/// check that did not run has no row, rather than a "passed" it did not earn.
pub(crate) fn data_rows(warnings: &[Warning], run: &[Check]) -> Vec<CheckRow> {
    run.iter()
        .map(|&c| {
            let found: Vec<&str> = warnings
                .iter()
                .filter(|w| w.check == c)
                .map(|w| w.message.as_str())
                .collect();
            let fired = !found.is_empty();
            let (meaning, action) = check_advice(c);
            CheckRow {
                name: format!("data: {c}"),
                statistic: None,
                threshold: None,
                p_value: None,
                fired,
                finding: if fired {
                    found.join(" ")
                } else {
                    "passed".to_string()
                },
                advice: if fired {
                    format!("{meaning} What to do: {action}")
                } else {
                    String::new()
                },
            }
        })
        .collect()
}

/// One row per test of `set`, named `{test} ({on})`.
pub(crate) fn test_rows(set: &TestSet, on: &str) -> Vec<CheckRow> {
    set.tests
        .iter()
        .map(|t| {
            let (meaning, action) = test_advice(t.name);
            CheckRow {
                name: format!("{} ({on})", t.name),
                statistic: Some(t.statistic),
                threshold: Some(t.threshold),
                p_value: Some(t.p_value),
                fired: t.fired,
                finding: t.detail.clone(),
                advice: if t.fired {
                    format!("{meaning} What to do: {action}")
                } else {
                    String::new()
                },
            }
        })
        .collect()
}

fn cell(v: Option<f64>, p: bool) -> String {
    match v {
        Some(v) if p => format!("<td class=\"num\">{}</td>", p_value(v)),
        Some(v) => format!("<td class=\"num\">{v:.4}</td>"),
        None => "<td class=\"num\">—</td>".to_string(),
    }
}

/// A p-value as a reader reads it: `< 1e-6` below one in a million, three
/// significant digits in plain decimals otherwise (`0.0123`, `0.500`, `1.00`).
fn p_value(v: f64) -> String {
    if !v.is_finite() {
        return format!("{v}");
    }
    if v < 1e-6 {
        return "&lt; 1e-6".to_string();
    }
    let digits = (2 - v.log10().floor() as i32).max(2) as usize;
    format!("{v:.digits$}")
}

/// The table as HTML, after the sentence `note` (plain text, may be empty).
pub fn table(rows: &[CheckRow], note: &str) -> String {
    let mut s = String::new();
    if !note.is_empty() {
        let _ = writeln!(s, "<p>{}</p>", escape(note));
    }
    s.push_str(
        "<table class=\"checks\">\n<tr><th>check or test</th><th>statistic</th>\
         <th>threshold</th><th>p-value</th><th>fired</th><th>finding</th>\
         <th>what it means, what to do</th></tr>\n",
    );
    for r in rows {
        let class = if r.fired { " class=\"fired\"" } else { "" };
        let _ = writeln!(
            s,
            "<tr{class}><td>{}</td>{}{}{}<td{class}>{}</td><td>{}</td><td>{}</td></tr>",
            escape(&r.name),
            cell(r.statistic, false),
            cell(r.threshold, false),
            cell(r.p_value, true),
            if r.fired { "yes" } else { "no" },
            escape(&r.finding),
            escape(&r.advice)
        );
    }
    s.push_str("</table>\n");
    s
}

#[cfg(test)]
mod tests {
    use super::p_value;

    #[test]
    fn p_values_print_as_plain_decimals() {
        assert_eq!(p_value(1.0), "1.00");
        assert_eq!(p_value(0.5), "0.500");
        assert_eq!(p_value(0.0123), "0.0123");
        assert_eq!(p_value(0.000_456_7), "0.000457");
        assert_eq!(p_value(3e-7), "&lt; 1e-6");
        assert_eq!(p_value(0.0), "&lt; 1e-6");
    }
}
