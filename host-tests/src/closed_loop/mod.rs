//! Closed-loop records: a simulated backlash servo whose input is computed from its measured
//! output ([`simulate`]), for the feedback check
//! ([`crate::diagnose::checks::feedback`]) and its tests.

pub mod simulate;

pub use simulate::{Servo, ServoError, ServoSpec, simulate_servo};
