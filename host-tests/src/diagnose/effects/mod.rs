//! The catalog of missing effects, the evidence each one needs, and the proposal of each
//! effect's model extension with its setting chosen on the estimation data.
//!
//! Every setting is chosen by an inner hold-out inside the estimation record: the extended
//! model is fitted on its first 70 % (after the hold) and scored by simulation on the last
//! 30 % (simulated from the start, so the initial state is consistent). The same score decides
//! whether the effect is added: the extension must lower the inner hold-out mean squared error
//! by at least the minimum gain and significantly (one-sided Diebold–Mariano test on the
//! squared errors at 1 %, Newey–West variance).

pub mod candidate;
pub mod catalog;
pub mod delay;
pub mod drift;
pub mod friction;
pub mod holdout;
pub mod hysteresis;
pub mod noise;
pub mod order;
pub mod outliers;
pub mod output_map;
pub mod periodic;
pub mod play_between;
pub mod proposal;
pub mod stores;

pub use candidate::{Candidate, Significance, choose, compare};
pub use catalog::{Effect, has_evidence, setting};
pub use holdout::{Fold, Holdout, too_slow};
pub use periodic::refine_frequency;
pub use proposal::Proposal;
