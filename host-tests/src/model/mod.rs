//! The host's domain: the measured record every estimator and check takes, and the input
//! element a model assumes.

mod element;
mod interval;
mod record;
mod simulate;

pub use element::{Element, MemoryElement, UnknownElement};
pub use interval::{Extended, Interval, OutsideInterval, Syntax, first_outside, for_input};
pub use record::{Record, RecordError};
pub use simulate::{FileModel, Simulate};
