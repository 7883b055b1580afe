//! The lab's tests, one module per file: `cargo test -p hsid-lab --test lab MODULE::` runs one
//! file's tests (e.g. `generality::`).

mod diagnose;
mod diagnose_steps;
mod diagnose_stores;
mod family_b;
mod generality;
mod unit_root;
