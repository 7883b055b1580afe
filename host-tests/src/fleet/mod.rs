//! A fleet of devices: many checkpoints solved across cores, one result or one typed error per
//! device ([`solve`]); a simulated fleet whose checkpoints come from the core's `Identifier`
//! as the firmware runs it, with gaps that drift as devices wear ([`simulate`]); and the wear
//! report, per device the gap per week, its trend and a flag ([`wear`]).

pub mod device;
pub mod device_wear;
pub mod score;
pub mod simulate;
pub mod solve;
pub mod trend;
pub mod wear;
pub mod write;

/// The largest fleet table read whole, in bytes (1 GiB): the truth CSV of `fleet simulate`
/// (`--truth`) and the JSON lines of `fleet` (`--models`), a few hundred bytes a checkpoint,
/// so millions of checkpoints; a larger file (or a device such as `/dev/zero`, refused as not
/// a regular file) is refused before it is read.
pub const MAX_TABLE_BYTES: u64 = 1 << 30;

pub use device::{DeviceError, DeviceResult};
pub use solve::{FleetCount, FleetSettings, Listing, solve_dir, solve_dir_each, solve_many};
