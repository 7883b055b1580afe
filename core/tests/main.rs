//! The core's integration tests, one module per file: `cargo test -p hsid --test core
//! MODULE::` runs one file's tests (e.g. `store_`, `structured::`).

mod proptest_common;
mod store_common;

mod checkpoint;
mod forgetting;
mod hat_update;
mod horizon_capacity;
mod long_run;
mod noise_free;
mod proptest_checkpoint;
mod proptest_config;
mod proptest_data;
mod proptest_reconstruction;
mod proptest_regressions;
mod store_bit_flips;
mod store_power_loss;
mod store_sequence;
mod structured;
