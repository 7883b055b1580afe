//! `hsid diagnose` on a simulated two-tank plant: state-dependent dynamics (square-root
//! outflows, an overflowing upper tank) must be named first and fixed by the level-dependent
//! stores.
//!
//! The plant is simulated here, independently of the model class: the tank equations
//! integrated with 50 Euler steps per sample (the model uses 4), a pump curve the identifier
//! does not know (a quadratic pump curve), white sensor noise of 0.02 V.

use hsid_host::diagnose::model::Record;
use hsid_host::diagnose::{DiagnoseOptions, Effect, Nonlinearity, Validation, diagnose};
use hsid_host::identify::IdentifyOptions;
use rand::{Rng, SeedableRng};
use rand_distr::{Distribution, StandardNormal};
use rand_pcg::Pcg32;

type Outcome = Result<(), Box<dyn std::error::Error>>;

/// Two tanks: `x1' = q_in(u) − a1 √x1` (overflowing above `top`, a fraction `spill` of the
/// excess reaching the lower tank), `x2' = a1 √x1 − a2 √x2`, output `y = 2 x2` (volts).
struct Tanks;

impl Tanks {
    fn simulate(&self, u: &[f64]) -> Vec<f64> {
        let (a1, a2, top, spill) = (0.05, 0.04, 3.2, 0.4);
        let (mut x1, mut x2) = (1.0f64, 1.0f64);
        let steps = 50;
        let dt = 1.0 / steps as f64;
        u.iter()
            .map(|&v| {
                let y = 2.0 * x2;
                // A pump whose flow grows faster than its voltage.
                let q_in = 0.01 * v + 0.0012 * v * v;
                for _ in 0..steps {
                    let (q1, q2) = (a1 * x1.max(0.0).sqrt(), a2 * x2.max(0.0).sqrt());
                    x1 += dt * (q_in - q1);
                    let over = (x1 - top).max(0.0);
                    x1 -= over;
                    x2 += dt * (q1 - q2) + spill * over;
                }
                y
            })
            .collect()
    }
}

/// Pump voltages: random levels in [0, 10] V held for 15 to 60 samples.
fn staircase(n: usize, rng: &mut Pcg32) -> Vec<f64> {
    let mut u = Vec::with_capacity(n);
    while u.len() < n {
        let level = rng.random_range(0.0..10.0);
        let hold = rng.random_range(15..60);
        u.extend(std::iter::repeat_n(level, hold));
    }
    u.truncate(n);
    u
}

/// An estimation and a validation record of the plant with white sensor noise of 0.02 V
/// RMS, and the validation record's noise RMS (the floor).
fn records(plant: &Tanks, seed: u64) -> (Record, Record, f64) {
    let mut rng = Pcg32::seed_from_u64(seed);
    let run = |rng: &mut Pcg32| {
        let u = staircase(1500, rng);
        let clean = plant.simulate(&u);
        let sigma = 0.02;
        let noise: Vec<f64> = (0..u.len())
            .map(|_| {
                let z: f64 = StandardNormal.sample(rng);
                sigma * z
            })
            .collect();
        let y: Vec<f64> = clean.iter().zip(&noise).map(|(y, e)| y + e).collect();
        let floor = (noise.iter().map(|e| e * e).sum::<f64>() / noise.len() as f64).sqrt();
        (Record::new(u, y), floor)
    };
    let (est, _) = run(&mut rng);
    let (val, floor) = run(&mut rng);
    (est, val, floor)
}

fn options() -> DiagnoseOptions {
    let mut id = IdentifyOptions::uniform(0.0, 10.0, 5, 0);
    id.order = Some(2);
    DiagnoseOptions::new(id, Nonlinearity::Static)
}

#[test]
fn square_root_tanks_get_level_dependent_stores() -> Outcome {
    let (est, val, floor) = records(&Tanks, 5);
    let d = diagnose(
        &est,
        &Validation::Separate {
            record: val,
            skip: 0,
        },
        &options(),
    )?;
    println!("{}", hsid_host::diagnose::report::text(&d));
    let first = d.steps.first().ok_or("no effect added")?;
    assert_eq!(first.effect, Effect::StateDependentDynamics);
    let after = first.error_after;
    assert!(
        after <= 0.7 * d.before.rmse,
        "before {}, after {after}",
        d.before.rmse
    );
    // Not down to the noise floor: the model's 4 Euler sub-steps per sample and its
    // 5-segment border of the quadratic pump curve leave about 2.4 × the floor.
    assert!(
        after <= 0.1 * d.before.rmse,
        "before {}, after {after}",
        d.before.rmse
    );
    assert!(after <= 3.0 * floor, "after {after}, noise floor {floor}");
    Ok(())
}
