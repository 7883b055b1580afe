//! Knots from the data: a record whose input thins out at the ends of its range (random
//! levels, normally distributed, the interval their own extremes) gets a model by default,
//! with a note of the merged segments; knots the user gives stay as given.
//!
//! The plant is written here, apart from the project's simulators: a play operator of width
//! 0.2 before `G(q) = (0.06 q⁻¹ + 0.04 q⁻²) / (1 − 1.5 q⁻¹ + 0.6 q⁻²)` (`G(1) = 1`).

#![allow(clippy::unwrap_used, clippy::panic)]

use crate::common;

use common::nrmse;
use hsid_host::model::{FileModel, Record, Simulate};
use hsid_host::workflow::{IdentifyRequest, Syntax, WorkflowError, identify_record};
use rand_core::SeedableRng;
use rand_distr::{Distribution, StandardNormal};
use rand_pcg::Pcg32;

const HALF_WIDTH: f64 = 0.1;
const NOISE_SD: f64 = 0.01;

/// Random levels held 30 samples each, standard deviation 0.4.
fn levels(n: usize, seed: u64) -> Vec<f64> {
    let mut rng = Pcg32::seed_from_u64(seed);
    let mut u = Vec::with_capacity(n);
    while u.len() < n {
        let level: f64 = StandardNormal.sample(&mut rng);
        u.extend(std::iter::repeat_n(0.4 * level, 30));
    }
    u.truncate(n);
    u
}

/// The plant's noise-free output.
fn plant(u: &[f64]) -> Vec<f64> {
    let mut w = 0.0f64;
    let (mut y1, mut y2, mut w1, mut w2) = (0.0, 0.0, 0.0, 0.0);
    u.iter()
        .map(|&v| {
            w = w.clamp(v - HALF_WIDTH, v + HALF_WIDTH);
            let y = 1.5 * y1 - 0.6 * y2 + 0.06 * w1 + 0.04 * w2;
            (y2, y1, w2, w1) = (y1, y, w1, w);
            y
        })
        .collect()
}

fn noisy(y: &[f64], seed: u64) -> Vec<f64> {
    let mut rng = Pcg32::seed_from_u64(seed);
    y.iter()
        .map(|v| {
            let e: f64 = StandardNormal.sample(&mut rng);
            v + NOISE_SD * e
        })
        .collect()
}

fn range(u: &[f64]) -> (f64, f64) {
    let lo = u.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = u.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    (lo, hi)
}

#[test]
fn sparse_ends_get_a_model_with_merged_knots_near_the_noise_floor() {
    let u = levels(4000, 1);
    let y = noisy(&plant(&u), 2);
    let (lo, hi) = range(&u);
    let record = Record::new(u, y).unwrap();
    let request = IdentifyRequest::new(lo, hi, Syntax::Cli);
    let id = identify_record(&record, &request).unwrap();
    let lines = id.lines().unwrap();
    assert!(
        lines.iter().any(|l| l.starts_with("knots from the data")),
        "{lines:#?}"
    );
    let knots = id.best.knots.as_ref().unwrap();
    // The ends the levels seldom visit lose their segments on a path at least (which paths
    // depends on the segment count the criterion keeps).
    assert!(knots.merged_asc + knots.merged_desc > 0, "{knots:?}");
    // Validation on another realisation, its input inside the identified interval.
    let uv: Vec<f64> = levels(4000, 3).iter().map(|v| v.clamp(lo, hi)).collect();
    let clean = plant(&uv);
    let yv = noisy(&clean, 4);
    let model = FileModel::from_file(&id.model_file());
    let fit = nrmse(&yv, &model.simulate(&uv));
    let floor = nrmse(&yv, &clean);
    assert!(
        fit < 1.1 * floor,
        "validation NRMSE {fit:.4}, noise floor {floor:.4}"
    );
}

#[test]
fn knots_the_user_gives_stay_strict() {
    let u = levels(4000, 1);
    let y = noisy(&plant(&u), 2);
    let (lo, hi) = range(&u);
    let record = Record::new(u, y).unwrap();
    let mut request = IdentifyRequest::new(lo, hi, Syntax::Cli);
    let knots: Vec<f64> = (0..=14).map(|i| lo + (hi - lo) * i as f64 / 14.0).collect();
    request.knots_asc = Some(knots.clone());
    request.knots_desc = Some(knots.clone());
    match identify_record(&record, &request) {
        Err(WorkflowError::Sample { error, .. }) => {
            let text = error.to_string();
            assert!(text.contains("never excited"), "{text}");
        }
        Ok(id) => {
            assert!(id.best.knots.is_none());
            assert_eq!(id.best.options.knots_asc, knots);
        }
        Err(e) => panic!("{e}"),
    }
}
