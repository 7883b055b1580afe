//! The confusion table of `hsid diagnose` on the second scenario family
//! ([`hsid_host::family_b`]): clean runs, the catalog's effects, and a backlash or switch
//! behind a static model, a closed loop, an integrating plant and a saturating output, over
//! plants of orders 1–4, three sample times, 10–40 dB, Table I and ordinary inputs.
//!
//! ```text
//! cargo run --release -p hsid-host --example confusion_b -- [SEEDS] [CLEAN_SEEDS] [THREADS]
//! ```
//!
//! Prints one line per run (stderr), then the table (true class × named first, with the
//! data checks that fired), named right per class and overall, false alarms on clean runs,
//! the steps that raised the validation error, and the wall time.

use hsid_host::family_b::run::{family, run_all};
use hsid_host::family_b::table::{confusion_table, summary};

fn main() {
    let mut args = std::env::args().skip(1);
    let seeds: u64 = args.next().and_then(|s| s.parse().ok()).unwrap_or(4);
    let clean: u64 = args.next().and_then(|s| s.parse().ok()).unwrap_or(8);
    let threads: usize = args
        .next()
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(2, |n| n.get()));
    let scenarios = family(seeds, clean);
    eprintln!("{} runs on {threads} threads", scenarios.len());
    let clock = std::time::Instant::now();
    let outcomes = run_all(&scenarios, threads, &|o| eprintln!("{}", o.line()));
    println!("{}", confusion_table(&outcomes));
    print!("{}", summary(&outcomes));
    println!(
        "{} runs, {seeds} seeds per class, {clean} clean seeds, {threads} threads: wall time {:.1} min",
        outcomes.len(),
        clock.elapsed().as_secs_f64() / 60.0
    );
}
