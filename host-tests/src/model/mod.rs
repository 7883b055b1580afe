//! The host's domain: the measured record every estimator and check takes, and the input
//! element a model assumes.

mod element;
mod record;
mod simulate;

pub use element::{Element, MemoryElement, UnknownElement};
pub use record::{Record, RecordError};
pub use simulate::{FileModel, Simulate};
