//! The page of `paper`: what was run against the paper's Section IV, the Monte Carlo table
//! exactly as `hsid paper` prints it (the true pole of the paper's system beside the measured
//! ones), the method comparison when `--method` ran, the figures `paper` wrote, and the
//! command with its settings and output files. The records are simulated, so the page has no
//! data checks.

use super::headline::{Fact, Headline, TextTable};
use super::printed::tables;
use super::{InlineFigure, Page, Reproduction};
use crate::paper::{CaseResult, PaperConfig, paper_table};

/// A finished run of `paper`.
pub struct PaperRun<'a> {
    /// The settings it ran with.
    pub cfg: &'a PaperConfig,
    /// The cases, in the order run.
    pub results: &'a [CaseResult],
    /// The table `--method` printed, when it ran.
    pub methods: Option<&'a str>,
}

impl PaperRun<'_> {
    /// The cases' names, `switch and backlash`.
    fn cases(&self) -> String {
        let names: Vec<&str> = self.results.iter().map(|r| r.case.name()).collect();
        names.join(" and ")
    }

    /// `case` or `cases`.
    fn case_word(&self) -> &'static str {
        if self.results.len() == 1 {
            "case"
        } else {
            "cases"
        }
    }

    /// The page title, plain text.
    pub fn title(&self) -> String {
        format!(
            "hsid paper: Section IV, the {} {}, {} runs each",
            self.cases(),
            self.case_word(),
            self.cfg.runs
        )
    }

    /// The settings sentence `paper` prints above its table, for the reproduction section.
    pub fn settings(&self) -> String {
        paper_table(self.cfg, self.results)
            .lines()
            .next()
            .unwrap_or_default()
            .to_string()
    }

    /// The page with `figures` (those `paper` wrote) and `reproduction`.
    pub fn page(&self, figures: Vec<InlineFigure>, reproduction: Reproduction) -> Page {
        let mut printed = tables(&paper_table(self.cfg, self.results));
        for t in printed.iter_mut().filter(|t| !t.header.is_empty()) {
            t.caption = format!(
                "{}. The true pole is the paper's G(q); every other column is measured on this \
                 run's records (std: sample standard deviation over the runs of order 2).",
                t.caption
            );
        }
        let mut all = vec![paper_beside_run(self.cfg, &self.cases())];
        all.extend(printed);
        if let Some(m) = self.methods {
            all.extend(tables(m));
        }
        Page {
            title: self.title(),
            headline: Headline {
                lead: self.lead(),
                facts: self.facts(),
                tables: all,
            },
            figures,
            checks_note: String::new(),
            checks: Vec::new(),
            reproduction,
        }
    }

    fn lead(&self) -> Vec<String> {
        let c = self.cfg;
        let mut lead = vec![
            format!(
                "Section IV of the paper reproduced by simulation: {} Monte Carlo runs of the \
                 {} {}, each record identified by PI-MOESP ({} uniform segments per path, \
                 {} basis) and compared with the true system.",
                c.runs,
                self.cases(),
                self.case_word(),
                c.segments,
                format!("{:?}", c.basis).to_lowercase()
            ),
            "The paper publishes no numbers for these runs: its results are Figs. 6–11 and \
             the statement that the method gives no bias and a low standard deviation. Its \
             published values are the system it simulates (the true pole in the table, the \
             true paths in the figures) and its settings, which stand beside this run's."
                .to_string(),
        ];
        let departs = departures(c);
        if !departs.is_empty() {
            lead.push(format!(
                "This run departs from the paper's settings in: {}.",
                departs.join(", ")
            ));
        }
        lead
    }

    /// What `summary.json` holds beyond the printed table: the pole's bias and μ0.
    fn facts(&self) -> Vec<Fact> {
        let mut facts = Vec::new();
        for r in self.results {
            let s = &r.summary;
            facts.push(Fact::new(
                format!("{}: |mean pole − true pole|", s.case),
                format!("{:.5}", s.pole_bias),
            ));
            facts.push(Fact::new(
                format!("{}: mean μ0 (true μ0)", s.case),
                format!("{:.5} ({:.5})", s.mu0_mean, s.mu0_true),
            ));
        }
        facts
    }
}

/// The settings that differ from the paper's.
fn departures(c: &PaperConfig) -> Vec<&'static str> {
    let p = PaperConfig::default();
    [
        (c.runs != p.runs, "runs per case"),
        (c.j != p.j, "Hankel columns j"),
        (c.snr_db != p.snr_db, "SNR"),
        (c.segments != p.segments, "segments per path"),
        ((c.u_min, c.u_max) != (p.u_min, p.u_max), "input interval"),
    ]
    .into_iter()
    .filter_map(|(differs, name)| differs.then_some(name))
    .collect()
}

/// The paper's settings (Section IV) beside this run's.
fn paper_beside_run(c: &PaperConfig, cases: &str) -> TextTable {
    let row = |s: &str, paper: &str, run: String| vec![s.to_string(), paper.to_string(), run];
    let order = c
        .order
        .map_or("selected from the singular values".to_string(), |n| {
            format!("fixed at {n}")
        });
    let hold = if c.hold == 0 {
        "no hold: μ0 estimated with the model".to_string()
    } else {
        format!(
            "hold of {} samples at u_min, the first {} skipped",
            c.hold, c.settle
        )
    };
    TextTable {
        caption: "The paper's settings beside this run's:".to_string(),
        header: ["setting", "the paper (Section IV)", "this run"]
            .map(String::from)
            .to_vec(),
        rows: vec![
            row("cases", "switch and backlash", cases.to_string()),
            row("runs per case", "100", c.runs.to_string()),
            row("Hankel columns j", "4000", c.j.to_string()),
            row(
                "noise",
                "SNR 10 dB, v = G_v(q) e, G_v = (1 + 0.5 q⁻¹) / (1 − 0.85 q⁻¹)",
                format!("SNR {} dB, the paper's G_v", c.snr_db),
            ),
            row(
                "knots",
                "n_p = 7 per path, uniform on [−3, 3]",
                format!(
                    "{} segments per path, uniform on [{}, {}]",
                    c.segments, c.u_min, c.u_max
                ),
            ),
            row(
                "horizons f, p",
                "not stated",
                format!("f = {}, p = {}", c.f, c.p),
            ),
            row("order", "not stated (the true order is 2)", order),
            row("μ0", "from a hold at u_min, length not stated", hold),
            row(
                "border basis",
                "ramp functions P_i",
                format!("{:?}", c.basis).to_lowercase(),
            ),
            row("seed", "—", c.seed.to_string()),
        ],
    }
}
