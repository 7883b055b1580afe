//! The mean gap's standard deviation a refined model reports (`std.mean_gap` of the model
//! file, from the refinement's whole covariance of the borders) against the spread of the
//! mean gap over independent noise realisations of the same servo.

#![allow(clippy::panic)]

use hsid_host::choose::{Choices, Horizons, KnotPlacement, Segments, best_model, model_std};
use hsid_host::identify::{IdentifyOptions, interpolate};
use hsid_host::refine::NoiseOrder;
use hsid_host::sim::{Backlash, Lti, simulate, table1_excitation, with_hold};
use rand::SeedableRng;
use rand_pcg::Pcg64;

const U_MIN: f64 = -2.0;
const U_MAX: f64 = 2.0;
const HOLD: usize = 200;

/// The knots of the model and of the simulated borders.
const KNOTS: [f64; 5] = [-2.0, -1.0, 0.0, 1.0, 2.0];
/// The simulated borders at the knots: a play of 0.6 inside, meeting at both ends as the
/// model's borders do, piecewise linear on the model's knots (the model class holds them).
const ASC: [f64; 5] = [-2.0, -1.3, -0.3, 0.7, 2.0];
const DESC: [f64; 5] = [-2.0, -0.7, 0.3, 1.3, 2.0];

/// A servo with the borders [`ASC`], [`DESC`] and a first-order plant (pole 0.8),
/// driven by one Table I excitation; white output noise at 20 dB, from `seed`. The input is
/// the same for every seed: the covariance is that of the noise, given the input.
fn record(seed: u64) -> (Vec<f64>, Vec<f64>) {
    let Ok(ex) = table1_excitation(2_000, U_MIN, U_MAX, &mut Pcg64::seed_from_u64(7)) else {
        panic!("a valid interval");
    };
    let u = with_hold(HOLD, U_MIN, &ex);
    let (Ok(plant), Ok(white)) = (
        Lti::new(vec![0.0, 0.2], vec![1.0, -0.8]),
        Lti::new(vec![1.0], vec![1.0]),
    ) else {
        panic!("valid filters");
    };
    let mut rng = Pcg64::seed_from_u64(seed);
    let mut element = Backlash::from_fns(
        |u| interpolate(&KNOTS, &ASC, u),
        |u| interpolate(&KNOTS, &DESC, u),
    );
    let Ok(sim) = simulate(
        &u,
        &mut element,
        &plant,
        &white,
        Some(20.0),
        HOLD..u.len(),
        &mut rng,
    ) else {
        panic!("the servo simulates");
    };
    (u, sim.y)
}

#[test]
fn the_reported_gap_std_is_the_spread_of_the_gap_over_noise_realisations() {
    let mut base = IdentifyOptions::uniform(U_MIN, U_MAX, KNOTS.len() - 1, HOLD);
    base.order = Some(1);
    let choices = Choices {
        segments: Segments::Given,
        knots: KnotPlacement::Given,
        horizons: Horizons::Given,
        noise: NoiseOrder::Fixed(0),
        window: None,
        ..Choices::default()
    };
    let runs = 200;
    let (mut gaps, mut stds) = (Vec::new(), Vec::new());
    let mut fit_model = None;
    for seed in 0..runs {
        let (u, y) = record(100 + seed);
        let Ok(best) = best_model(&u, &y, &base, &choices) else {
            panic!("seed {seed}: no model");
        };
        let Some(fit) = &best.fit else {
            panic!("seed {seed}: not refined");
        };
        let (Some(gap), (std, _)) = (fit.model.mean_gap(), model_std(fit)) else {
            panic!("seed {seed}: no mean gap");
        };
        let Some(s) = std.mean_gap else {
            panic!("seed {seed}: a backlash model without the gap's std");
        };
        fit_model = Some(fit.model.clone());
        gaps.push(gap);
        stds.push(s);
    }
    let n = runs as f64;
    let mean = gaps.iter().sum::<f64>() / n;
    let spread = (gaps.iter().map(|g| (g - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
    let reported = stds.iter().sum::<f64>() / n;
    let Some(fit_model) = fit_model else {
        panic!("no run");
    };
    // The true mean gap of these borders, and the estimate unbiased within its spread.
    let truth = {
        let mut m = fit_model.clone();
        m.border_asc = ASC.to_vec();
        m.border_desc = DESC.to_vec();
        m.mean_gap().unwrap_or(f64::NAN)
    };
    eprintln!("mean gap {mean:.4} (true {truth:.4}), spread {spread:.5}, reported {reported:.5}");
    assert!(
        (mean - truth).abs() < 4.0 * spread / n.sqrt(),
        "mean gap {mean}, true {truth}"
    );
    // 200 runs: the sample standard deviation is within ±15 % of the truth at 3σ (its
    // relative standard error is 1/√(2·199) = 5 %). Seen: 0.01163 reported, 0.01202 spread.
    let ratio = reported / spread;
    assert!(
        (0.85..=1.18).contains(&ratio),
        "reported {reported:.5}, spread {spread:.5}, ratio {ratio:.3}"
    );
}
