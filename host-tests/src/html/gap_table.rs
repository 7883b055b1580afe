//! The gap table of the headline: the gap at the report's inputs across the interval, after
//! a descent and after an ascent, with the standard deviations where known, the loop height,
//! and the mean gap; with the true plant, its gap beside the identified one. The cells are
//! [`GapAt::cells`](crate::units::GapAt::cells), the text `identify` prints.

use hsid::Direction;

use super::headline::TextTable;
use super::model_words::input_unit;
use crate::figures::TrueBorders;
use crate::units::{UnitReport, gap_text};

/// The label of the table's last row, the mean over both directions.
pub const MEAN_ROW: &str = "mean of both directions";

/// The table of `r`'s gaps, with the true gap of `truth` (a column `true gap`, and the true
/// mean in the last row); `None` when `r` has no gap (a static element).
pub fn gap_table(r: &UnitReport, truth: Option<&TrueBorders>) -> Option<TextTable> {
    if r.gap.is_empty() {
        return None;
    }
    let u_unit = input_unit(r);
    let y_unit = r
        .units
        .as_ref()
        .map_or("output units", |u| u.output.as_str());
    let mut header = vec![
        format!("u [{u_unit}]"),
        format!("gap after a descent [{u_unit}]"),
        format!("gap after an ascent [{u_unit}]"),
    ];
    if truth.is_some() {
        header.push(format!("true gap [{u_unit}]"));
    }
    header.push(format!("loop height [{y_unit}]"));
    let mut rows: Vec<Vec<String>> = r
        .gap
        .iter()
        .map(|g| {
            let [u, descent, ascent, height] = g.cells();
            let mut row = vec![u, descent, ascent];
            if let Some(t) = truth {
                row.push(true_gap(
                    t.gap_at(Direction::Descending, g.u),
                    t.gap_at(Direction::Ascending, g.u),
                ));
            }
            row.push(height);
            row
        })
        .collect();
    let mut mean = vec![
        MEAN_ROW.to_string(),
        r.mean_gap_text().unwrap_or_else(|| "none".to_string()),
        String::new(),
    ];
    if let Some(t) = truth {
        mean.push(gap_text(t.mean_gap(), None));
    }
    mean.push(String::new());
    rows.push(mean);
    let known = r
        .gap
        .iter()
        .any(|g| g.after_descent_std.is_some() || g.after_ascent_std.is_some());
    let mut caption = format!(
        "The gap: how far the input must travel back after a reversal at u before the \
         output moves again, after arriving at u falling and rising ({} inputs across the \
         interval; the borders figure marks the one after a descent at the middle). The \
         loop height is the output's difference between the two borders there, times the \
         static gain. The last row is the mean over both directions.",
        r.gap.len()
    );
    if known || r.mean_gap_std.is_some() {
        caption.push_str(" ±: one standard deviation, to first order.");
    }
    if truth.is_some() {
        caption.push_str(
            " True gap: the plant of --true-plant, read the same way on its true loop (one \
             value where both directions agree to five decimals, else after a descent / \
             after an ascent).",
        );
    }
    Some(TextTable {
        caption,
        header,
        rows,
    })
}

/// The true gap's cell: one value when both directions agree to five decimals.
fn true_gap(descent: Option<f64>, ascent: Option<f64>) -> String {
    let (d, a) = (gap_text(descent, None), gap_text(ascent, None));
    if d == a { d } else { format!("{d} / {a}") }
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;
    use crate::model_file::Units;
    use crate::units::gain::tests::first_order;

    #[test]
    fn the_table_holds_the_reports_cells_and_the_truth() {
        // P_a = 2u − 0.5, P_d = 2u + 0.5 on knots −1, 0, 1: the gap is 0.5 wherever defined.
        let k = [-1.0, 0.0, 1.0];
        let m = first_order(
            0.9,
            0.1,
            k.iter().map(|u| 2.0 * u - 0.5).collect(),
            k.iter().map(|u| 2.0 * u + 0.5).collect(),
        );
        let units = Units {
            input: "V".into(),
            output: "deg".into(),
        };
        let r = m
            .unit_report(Some(0.01), Some(units), None, true)
            .with_gap_std(Some(0.0123))
            .with_gap_stds(|dir, _| (dir == Direction::Descending).then_some(0.0234));
        // The true loop: a play of 0.4 and slope 1.
        let u: Vec<f64> = (0..=20).map(|i| -1.0 + 0.1 * f64::from(i)).collect();
        let truth = TrueBorders {
            asc: u.iter().map(|u| u - 0.2).collect(),
            desc: u.iter().map(|u| u + 0.2).collect(),
            u,
        };
        let t = gap_table(&r, Some(&truth)).unwrap();
        assert_eq!(t.header[3], "true gap [V]");
        assert_eq!(t.rows.len(), r.gap.len() + 1);
        let middle = &t.rows[2];
        assert_eq!(middle[..3], ["0.00000", "0.500 ± 0.023", "0.50000"]);
        assert_eq!(middle[3], "0.40000");
        let last = t.rows.last().unwrap();
        assert_eq!(last[0], MEAN_ROW);
        assert_eq!(last[1], "0.500 ± 0.012");
        assert_eq!(last[3], "0.40000");
        // Without the truth, no such column; a static report has no table.
        assert!(
            gap_table(&r, None)
                .unwrap()
                .header
                .iter()
                .all(|h| !h.contains("true"))
        );
        let none = m.unit_report(None, None, None, false);
        assert!(gap_table(&none, None).is_none());
    }
}
