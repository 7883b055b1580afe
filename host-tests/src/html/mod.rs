//! One self-contained HTML report per run of `identify`, `validate`, `diagnose` or `paper`
//! (`--html FILE`): a single file with the figures inline as SVG and the style sheet inline, no script
//! and no reference to anything outside the file, readable offline and printable.
//!
//! The page, in order:
//! 1. [`headline`]: the result in words (the model in units, the fit; for `diagnose` the
//!    verdict and the errors before and after);
//! 2. [`figure`]s with captions that say what to look at ([`captions`]);
//! 3. [`checks`]: the data checks and residual tests as a table, each finding with what it
//!    means and what to do ([`advice`]); left out when there are none (`paper`, whose records
//!    are simulated);
//! 4. [`reproduce`]: the command line as run, the hsid version, the input files and sizes.
//!
//! [`paper_page`] fills the sections for `paper` ([`printed`] turns its printed tables into
//! page tables, [`paper_captions`] captions its figures).
//!
//! Every string from outside goes through [`escape::escape`].

pub mod advice;
pub mod captions;
pub mod checks;
pub mod diagnosis_page;
pub mod error;
pub mod escape;
pub mod figure;
pub mod figures;
pub mod gap_table;
pub mod headline;
pub mod identified;
pub mod model_page;
pub mod model_words;
pub mod paper_captions;
pub mod paper_page;
pub mod printed;
pub mod reproduce;
pub mod skeleton;

use std::path::Path;

pub use checks::CheckRow;
pub use error::HtmlError;
pub use figure::InlineFigure;
pub use headline::{Fact, Headline, TextTable};
pub use reproduce::Reproduction;

/// Everything the page shows.
#[derive(Clone, Debug, PartialEq)]
pub struct Page {
    /// The page title (e.g. `hsid identify: servo.csv`), plain text.
    pub title: String,
    /// The result first.
    pub headline: Headline,
    /// The figures, in order.
    pub figures: Vec<InlineFigure>,
    /// The sentence above the checks table (what the tests ran on), plain text.
    pub checks_note: String,
    /// The data checks and residual tests; with an empty `checks_note` too, the section is
    /// left out.
    pub checks: Vec<CheckRow>,
    /// The command, version and inputs.
    pub reproduction: Reproduction,
}

impl Page {
    /// The page as one HTML document.
    pub fn render(&self) -> String {
        let figures = if self.figures.is_empty() {
            "<p>This run drew no figures.</p>\n".to_string()
        } else {
            self.figures.iter().map(InlineFigure::html).collect()
        };
        let checks = if self.checks.is_empty() && self.checks_note.is_empty() {
            String::new()
        } else {
            skeleton::section(2, &checks::table(&self.checks, &self.checks_note))
        };
        let body = [
            skeleton::section(0, &self.headline.html()),
            skeleton::section(1, &figures),
            checks,
            skeleton::section(3, &self.reproduction.html()),
        ]
        .concat();
        skeleton::document(&self.title, &body)
    }

    /// Writes the page to `path`.
    pub fn write(&self, path: &Path) -> Result<(), HtmlError> {
        crate::io::write_atomic(path, self.render()).map_err(|source| HtmlError::Write {
            path: path.to_path_buf(),
            source,
        })
    }
}
