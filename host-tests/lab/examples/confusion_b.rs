//! The confusion table of `hsid diagnose` on the second scenario family
//! ([`hsid_lab::family_b`]): clean runs, the catalog's effects, and a backlash or switch
//! behind a static model, a closed loop, an integrating plant and a saturating output, over
//! plants of orders 1–4, three sample times, 10–40 dB, Table I and ordinary inputs.
//!
//! ```text
//! cargo run --release -p hsid-lab --example confusion_b -- [--min-gain G] [--propose-every] [SEEDS] [CLEAN_SEEDS] [THREADS] [CLASS [SEED]]
//! ```
//!
//! Prints one line per run (stderr), then the table (true class × named first, with the
//! data checks that fired), named right per class and overall, false alarms on clean runs,
//! the steps that raised the validation error, and the wall time.
//!
//! With `CLASS` (a class name as in the table, e.g. `static_hysteresis`) and optionally
//! `SEED`, only the matching scenarios of the family run, and each one's whole diagnosis
//! report (`hsid_host::diagnose::report::text`) is printed after its line; the table then
//! covers only those runs.
//!
//! `--min-gain G` runs the diagnosis with another minimum gain (`hsid diagnose --min-gain`,
//! default 0.2), and `--propose-every` has every step fit and score every deterministic
//! effect, with or without a residual test's evidence (`Proposing::Every`): the measurements
//! of what the estimation data can show in docs/closing-the-loop.md.

use hsid_host::diagnose::{DiagnoseOptions, diagnose, report};
use hsid_lab::bench::take_bench_flags;
use hsid_lab::family_b::generate::generate;
use hsid_lab::family_b::run::{family, run_all};
use hsid_lab::family_b::scenario::Scenario;
use hsid_lab::family_b::table::{confusion_table, summary};

/// Prints the whole diagnosis report of one scenario (diagnosed again, for the filter).
fn print_report(s: &Scenario, adjust: &dyn Fn(&mut DiagnoseOptions)) {
    let mut data = generate(s);
    adjust(&mut data.options);
    match diagnose(&data.record, &data.validation, &data.options) {
        Ok(d) => eprintln!("{}", report::text(&d)),
        Err(e) => eprintln!("diagnosis failed: {e}"),
    }
}

fn main() {
    let (bench, rest) = take_bench_flags(std::env::args().skip(1).collect()).unwrap_or_else(|e| {
        eprintln!("{e}");
        std::process::exit(2)
    });
    let mut args = rest.into_iter();
    let seeds: u64 = args.next().and_then(|s| s.parse().ok()).unwrap_or(4);
    let clean: u64 = args.next().and_then(|s| s.parse().ok()).unwrap_or(8);
    let threads: usize = args
        .next()
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(2, |n| n.get()));
    let class = args.next();
    let seed: Option<u64> = args.next().and_then(|s| s.parse().ok());
    let filtered = class.is_some();
    let mut scenarios = family(seeds, clean);
    scenarios.retain(|s| {
        class.as_deref().is_none_or(|c| s.class.name() == c) && seed.is_none_or(|n| s.seed == n)
    });
    if filtered && scenarios.is_empty() {
        eprintln!("no scenario matches class {class:?} seed {seed:?}: names are as in the table");
        std::process::exit(2);
    }
    eprintln!("{} runs on {threads} threads", scenarios.len());
    let clock = std::time::Instant::now();
    let adjust = |o: &mut DiagnoseOptions| bench.apply(o);
    let outcomes = run_all(&scenarios, threads, &adjust, &|o| {
        eprintln!("{}", o.line());
        if filtered {
            print_report(&o.scenario, &adjust);
        }
    });
    println!("{}", confusion_table(&outcomes));
    print!("{}", summary(&outcomes));
    println!(
        "{} runs, {seeds} seeds per class, {clean} clean seeds, minimum gain {}, {threads} threads: wall time {:.1} min",
        outcomes.len(),
        outcomes.first().map_or(f64::NAN, |o| o.min_gain),
        clock.elapsed().as_secs_f64() / 60.0
    );
}
