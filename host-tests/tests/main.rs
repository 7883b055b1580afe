//! The host's integration tests, one module per file: `cargo test -p hsid-host --test host
//! MODULE::` runs one file's tests (e.g. `closed_loop::`). `abandon.rs` is a binary of its own:
//! what it tests keeps a lock until the process ends.

mod common;

mod agreement;
mod allocator;
mod atomic_outputs;
mod bad_input;
mod bounded_inputs;
mod cli;
mod cli_diagnose_reference;
mod cli_edges;
mod cli_hysteresis;
mod cli_pipe;
mod cli_simulate;
mod cli_sizes;
mod cli_stream;
mod cli_units;
mod closed_loop;
mod compensation;
mod csv_layouts;
mod diagnose;
mod diagnose_hysteresis;
mod diagnose_measured;
mod diagnose_reference;
mod distributions;
mod error_messages;
mod figures;
mod firmware;
mod fleet;
mod gap_uncertainty;
mod html_gap;
mod html_report;
mod hysteresis;
mod integrating;
mod interrupt;
mod io;
mod knots_from_data;
mod linear_baseline;
mod long_records;
mod long_run;
mod matlab_recipe;
mod model_file;
mod model_format;
mod one_verdict;
mod outside_interval;
mod paper;
mod plot;
mod quick_start;
mod reference;
mod refine;
mod refine_cli;
mod refine_mc;
mod refused_inputs;
mod sim;
mod stable_start;
