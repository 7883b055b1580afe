//! Section IV of the paper, reproduced: Monte Carlo identification of the switch and the
//! backlash cases, statistics against the true system, `summary.json` and Figs. 6–11, and the
//! evaluation beyond it on the same experiments.
//!
//! * [`case`]: the two examples, one simulated experiment, the seeds and options of a run;
//! * [`mod@monte_carlo`]: the runs of a case and their statistics;
//! * [`table`]: the Monte Carlo table;
//! * [`figures`]: the paper's figures (pole map, Bode magnitude, borders);
//! * [`methods`]: every method on the same experiments, the table of the README;
//! * [`crb`]: the Cramér–Rao bound of the paper's example;
//! * [`method_figures`]: the method comparison's figures with uncertainty bands.

pub mod case;
pub mod crb;
pub mod figures;
pub mod method_figures;
pub mod methods;
pub mod monte_carlo;
pub mod table;

pub use case::{
    Case, Experiment, ExperimentError, PaperConfig, case_system, derive_seed, experiment, options,
};
pub use figures::write_figures;
pub use monte_carlo::{
    CaseResult, CaseSummary, RunError, best_pwl, border_at, monte_carlo, run_case, summarize,
};
pub use table::paper_table;
