//! No step that hurts: on a bounded subset of the confusion table's runs (one seed of each
//! effect whose extension competes with an input delay, on the first-order plant with the
//! backlash, and one clean run), every step the diagnosis adds lowers the validation error
//! (`Outcome::harmful` is empty), and the effect of the run is still named first. The whole
//! table's count is `cargo run --release -p hsid-host --example confusion -- 3 10`.

#![allow(clippy::panic)]

use hsid_host::diagnose::bench::{Outcome, run_all};
use hsid_host::diagnose::scenario::{Plant, Scenario};
use hsid_host::diagnose::{Effect, Nonlinearity};

#[test]
fn no_added_step_raises_the_validation_error() {
    let kind = Nonlinearity::Backlash;
    let scenarios: Vec<Scenario> = [
        None,
        Some(Effect::InputDelay),
        Some(Effect::OutputNonlinearity),
    ]
    .into_iter()
    .map(|e| Scenario::new(e, Plant::FirstOrder, kind, 1))
    .collect();
    let threads = std::thread::available_parallelism().map_or(2, |n| n.get());
    let outcomes: Vec<Outcome> = run_all(&scenarios, threads, &|o| eprintln!("{}", o.line()))
        .into_iter()
        .map(|r| match r {
            Ok(o) => o,
            Err(e) => panic!("{e}"),
        })
        .collect();
    for o in &outcomes {
        assert!(o.harmful.is_empty(), "{}: {:?}", o.line(), o.harmful);
        assert!(o.passes(), "{}", o.line());
    }
}
