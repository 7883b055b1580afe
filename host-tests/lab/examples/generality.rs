//! The generality benchmark: `cargo run --release -p hsid-lab --example generality -- [PLANTS]
//! [SEED]` (default 40 plants, seed 1) prints, per plant, the true order, the chosen order and
//! the validation NRMSE over the noise floor for the paper's estimator (PI-MOESP, 7 segments
//! per path, f = p = 10, the subspace order) and the desktop default (`hsid identify` without
//! options: segments and horizons from the data, refined, the order by BIC), then a summary.
//! `-- PLANTS SEED diagnose` adds the base model of `hsid diagnose` at its defaults.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use hsid_lab::generality::{
    Estimator, Row, confusion, default_estimate, diagnose_estimate, paper_estimate, run_case, table,
};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let plants: usize = args
        .get(1)
        .map_or(40, |a| a.parse().expect("PLANTS: a number"));
    let seed: u64 = args
        .get(2)
        .map_or(1, |a| a.parse().expect("SEED: a number"));
    let mut estimators: Vec<Estimator> = vec![paper_estimate, default_estimate];
    let mut names = vec!["paper", "default"];
    match args.get(3).map(String::as_str) {
        None => {}
        Some("diagnose") => {
            estimators.push(diagnose_estimate);
            names.push("diagnose");
        }
        Some(other) => {
            eprintln!("generality: unknown third argument {other:?}; the only one is `diagnose`");
            std::process::exit(2);
        }
    }
    let rows: Vec<Row> = (0..plants)
        .map(|i| {
            let row = run_case(seed, i, &estimators).expect("case");
            eprintln!(
                "plant {i}: {:?}",
                row.scores.iter().map(|s| s.ratio()).collect::<Vec<_>>()
            );
            row
        })
        .collect();
    println!("{}", table(&rows, &names));
    println!("{}", confusion(&rows, 0, "paper"));
    println!("{}", confusion(&rows, 1, "default"));
}
