//! A second scenario family for the diagnosis's confusion table, written apart from
//! [`crate::scenario`]: its own plants (continuous cascades of orders 1–4 with real
//! and complex poles, sampled at 0.05, 0.1 or 0.2 s), elements (static curve, play operator,
//! switch on piecewise-linear borders), inputs (Table I, smoothed random, multisine), noise
//! (white, AR(1), MA(2) at 10–40 dB) and classes: clean, the catalog's effects, and a
//! backlash or switch behind a static model, a closed loop, an integrating plant and a
//! saturating output.
//!
//! A scenario is `(class, seed)` ([`Scenario`]); [`generate()`] gives its estimation and
//! validation records, the diagnosis's options and the truth; [`Class::named_right`] says in
//! one place what the diagnosis must do on each class; [`run::run_all`] and
//! [`table::confusion_table`] make the table (example `confusion_b`).

pub mod additions;
pub mod class;
pub mod clean;
pub mod closed_loop;
pub mod element;
pub mod generate;
pub mod input;
pub mod noise;
pub mod plant;
pub mod rng;
pub mod run;
pub mod scenario;
pub mod table;

pub use class::{Class, Expect};
pub use generate::{Data, Truth, generate};
pub use run::{Harm, Outcome, run_adjusted, run_all, run_one};
pub use scenario::{Design, Scenario};
