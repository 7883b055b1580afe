//! Closed-loop records: a simulated backlash servo whose input is computed from its measured
//! output ([`simulate`]), for the feedback check
//! ([`crate::validation::checks::feedback`]) and its tests; and a closed-loop consistent
//! estimate from a logged reference ([`reference_iv`], on a whole record: [`record`]).

pub mod error;
pub mod estimator;
pub mod instruments;
mod linalg;
pub mod record;
pub mod reference_iv;
pub mod simulate;

pub use error::ReferenceError;
pub use estimator::Estimator;
pub use record::identify_closed_loop;
pub use reference_iv::identify_with_reference;
pub use simulate::{LoopRecord, ServoError, ServoSpec, simulate_servo};
