//! Scoring a model on the validation record against the noise floor, and the table.

use std::fmt::Write as _;

use super::case::{Case, HOLD, SimulatedRecord};
use hsid_host::identify::HostModel;
use hsid_host::report::fit;

/// What an estimator returned for a case.
#[derive(Clone, Debug)]
pub struct Estimate {
    /// The model.
    pub model: HostModel,
    /// What the estimator says it chose (horizons, order), for the table.
    pub note: String,
}

/// One estimator's score on one case.
#[derive(Clone, Debug)]
pub enum Score {
    /// The model's order and its validation NRMSE over the noise floor's.
    Scored {
        /// Order of the model.
        order: usize,
        /// Validation NRMSE / noise floor NRMSE.
        ratio: f64,
        /// The estimator's note.
        note: String,
    },
    /// The estimator failed.
    Failed(String),
}

impl Score {
    /// The ratio, infinite for a failure.
    pub fn ratio(&self) -> f64 {
        match self {
            Score::Scored { ratio, .. } => *ratio,
            Score::Failed(_) => f64::INFINITY,
        }
    }
}

/// Scores `estimate` (a model from the estimation record, or an error) on the validation record.
pub fn score(validation: &SimulatedRecord, estimate: Result<Estimate, String>) -> Score {
    let floor = fit(&validation.y[HOLD..], &validation.y_clean[HOLD..]).nrmse;
    match estimate {
        Ok(e) => {
            let sim = e.model.simulate(&validation.u);
            let ratio = fit(&validation.y[HOLD..], &sim[HOLD..]).nrmse / floor;
            if ratio.is_finite() {
                Score::Scored {
                    order: e.model.order,
                    ratio,
                    note: e.note,
                }
            } else {
                Score::Failed("the model's simulation is not finite".into())
            }
        }
        Err(e) => Score::Failed(e),
    }
}

/// One row of the table: a case and its scores, one per estimator.
#[derive(Clone, Debug)]
pub struct Row {
    /// The case.
    pub case: Case,
    /// The scores, in the order of the estimators.
    pub scores: Vec<Score>,
}

/// The table in Markdown, with a summary line per estimator: how many cases land within
/// 1.15× and 1.5× the floor, the worst ratio, and the order confusion.
pub fn table(rows: &[Row], names: &[&str]) -> String {
    let mut s = String::new();
    let _ = write!(
        s,
        "| plant | element | order | slowest pole | SNR | noise |"
    );
    for n in names {
        let _ = write!(s, " {n}: order | {n}: ratio |");
    }
    s.push('\n');
    s.push_str("|---|---|---|---|---|---|");
    for _ in names {
        s.push_str("---|---|");
    }
    s.push('\n');
    for r in rows {
        let c = &r.case;
        let _ = write!(
            s,
            "| {} | {} | {} | {:.3} | {} dB | {} |",
            c.index,
            c.element.kind.element(),
            c.plant.order(),
            c.plant.slowest(),
            c.snr_db,
            c.colour
        );
        for sc in &r.scores {
            match sc {
                Score::Scored { order, ratio, .. } => {
                    let _ = write!(s, " {order} | {ratio:.3} |");
                }
                Score::Failed(e) => {
                    let _ = write!(s, " – | failed: {e} |");
                }
            }
        }
        s.push('\n');
    }
    s.push('\n');
    for (k, n) in names.iter().enumerate() {
        let ratios: Vec<f64> = rows.iter().map(|r| r.scores[k].ratio()).collect();
        let within = |t: f64| ratios.iter().filter(|&&x| x <= t).count();
        let worst = ratios.iter().copied().fold(0.0, f64::max);
        let right = rows
            .iter()
            .filter(|r| matches!(r.scores[k], Score::Scored { order, .. } if order == r.case.plant.order()))
            .count();
        let _ = writeln!(
            s,
            "- {n}: within 1.15× the noise floor {}/{}, within 1.5× {}/{}, worst {worst:.2}×, true order {}/{}",
            within(1.15),
            rows.len(),
            within(1.5),
            rows.len(),
            right,
            rows.len()
        );
    }
    s
}

/// The order confusion of estimator `k`: rows the true order 1–4, columns the chosen order
/// 1–6 (a failure counts in no column), in Markdown.
pub fn confusion(rows: &[Row], k: usize, name: &str) -> String {
    let mut counts = [[0usize; 6]; 4];
    for r in rows {
        let truth = r.case.plant.order();
        if let Score::Scored { order, .. } = &r.scores[k]
            && (1..=4).contains(&truth)
            && (1..=6).contains(order)
        {
            counts[truth - 1][order - 1] += 1;
        }
    }
    let mut s = format!(
        "| {name}: true order ↓ chosen → | 1 | 2 | 3 | 4 | 5 | 6 |\n|---|---|---|---|---|---|---|\n"
    );
    for (t, row) in counts.iter().enumerate() {
        let _ = write!(s, "| {} |", t + 1);
        for c in row {
            let _ = write!(s, " {c} |");
        }
        s.push('\n');
    }
    s
}
