//! The table of `hsid diagnose` on the third scenario family ([`hsid_lab::family_c`]):
//! servos with the effects real drives have — clean, friction, play between motor and load,
//! play at the input, an end stop — in open and closed loop.
//!
//! ```text
//! cargo run --release -p hsid-lab --example confusion_c -- [SEEDS] [THREADS] [CLASS [SEED]]
//! ```
//!
//! Prints one line per run (stderr), then the table (per class and loop: runs, resolvable
//! runs, named right among them and overall, false alarms, harmful steps, the effects named
//! first, the mean wall time) and its summary, and the wall time.
//!
//! With `CLASS` (a class name as in the table, e.g. `play_between`) and optionally `SEED`,
//! only the matching scenarios run (both loops), and each one's whole diagnosis report
//! (`hsid_host::diagnose::report::text`) is printed before its line.

use hsid_host::diagnose::{Diagnosis, report};
use hsid_lab::family_c::Class;
use hsid_lab::family_c::run::{family, run_all};
use hsid_lab::family_c::table::{summary, table};

fn main() {
    let mut args = std::env::args().skip(1);
    let seeds: u64 = args.next().and_then(|s| s.parse().ok()).unwrap_or(4);
    let threads: usize = args
        .next()
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(2, |n| n.get()));
    let class = args.next();
    let seed: Option<u64> = args.next().and_then(|s| s.parse().ok());
    if let Some(c) = &class
        && Class::from_name(c).is_none()
    {
        let names: Vec<&str> = Class::ALL.iter().map(|c| c.name()).collect();
        eprintln!("no class {c}: one of {}", names.join(", "));
        std::process::exit(2);
    }
    let filtered = class.is_some();
    let mut scenarios = family(seeds);
    scenarios.retain(|s| {
        class.as_deref().is_none_or(|c| s.class.name() == c) && seed.is_none_or(|n| s.seed == n)
    });
    if scenarios.is_empty() {
        eprintln!("no scenario matches class {class:?} seed {seed:?}");
        std::process::exit(2);
    }
    eprintln!("{} runs on {threads} threads", scenarios.len());
    let clock = std::time::Instant::now();
    let print_report = |d: &Diagnosis| {
        if filtered {
            eprintln!("{}", report::text(d));
        }
    };
    let outcomes = run_all(
        &scenarios,
        threads,
        &|o| eprintln!("{}", o.line()),
        &print_report,
    );
    println!("{}", table(&outcomes));
    print!("{}", summary(&outcomes));
    println!(
        "{} runs, {seeds} seeds per class and loop, {threads} threads: wall time {:.1} min",
        outcomes.len(),
        clock.elapsed().as_secs_f64() / 60.0
    );
}
