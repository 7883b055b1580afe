//! `hsid diagnose` on simulated two-tank plants ([`hsid_lab::scenario::TwoTanks`]):
//! square-root outflows with an overflowing upper tank (the level-dependent stores should be
//! named first) and linear outflows (they should not be added), over seeds and noise levels.
//!
//! ```text
//! cargo run --release -p hsid-lab --example stores_scenarios [SEEDS]
//! ```

use hsid_lab::scenario::{Outflow, TwoTanks};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let seeds: u64 = std::env::args().nth(1).map_or(Ok(4), |s| s.parse())?;
    let options = TwoTanks::options();
    println!(
        "| outflow | noise (V) | seed | named first | before (V) | after (V) | after / before | after / floor |"
    );
    println!("|---|---|---|---|---|---|---|---|");
    for outflow in [Outflow::SquareRoot, Outflow::Linear] {
        for noise in [0.02, 0.1, 0.3] {
            for seed in 1..=seeds {
                let plant = TwoTanks {
                    outflow,
                    noise,
                    seed,
                };
                let (d, floor) = plant.diagnose(&options)?;
                let first = d.steps.first();
                let name = first.map_or("—", |s| s.effect.name());
                let after = first.map_or(d.before.rmse, |s| s.error_after);
                println!(
                    "| {outflow:?} | {noise} | {seed} | {name} | {:.4} | {after:.4} | {:.2} | {:.2} |",
                    d.before.rmse,
                    after / d.before.rmse,
                    after / floor
                );
            }
        }
    }
    Ok(())
}
