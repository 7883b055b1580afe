//! The closed loop: after the hold, a PI controller computes the input from the measured
//! output to follow a reference (the design's ordinary input on the element's output range
//! widened by 5 % each side, so that the input reaches both ends),
//! so the noise is fed back into the input.

use nalgebra::DVector;

use super::clean::Clean;
use super::element::Element;
use super::noise::{Noise, noise, sigma_for, variance};
use super::plant::{Discrete, Section};
use super::scenario::{Design, Scenario};

/// The PI gains `(k_p, k_i)` for a plant of unit static gain: `k_i = 1/(2 (T + 1))` with `T`
/// the plant's summed time constants in samples.
pub fn gains(d: &Design) -> (f64, f64) {
    let t: f64 = d
        .plant
        .sections
        .iter()
        .map(|s| match *s {
            Section::Real { tau } => tau / d.ts,
            Section::Complex { omega, zeta } => 2.0 * zeta / omega / d.ts,
            Section::Integrator { .. } => 0.0,
        })
        .sum();
    (0.3, 0.5 / (t + 1.0))
}

/// Both records (`(hold, len)` each): the input and the noise-free output, the noise, and its
/// standard deviation (set by the ratio of the estimation record's output without noise).
pub fn records(
    s: &Scenario,
    d: &Design,
    lens: [(usize, usize); 2],
) -> (Vec<Clean>, Vec<Noise>, f64) {
    let plant = d.plant.sampled(d.ts);
    let references: Vec<Vec<f64>> = lens
        .iter()
        .enumerate()
        .map(|(k, &(hold, len))| {
            let lo = d.borders.asc_at(d.range.0);
            let hi = d.borders.asc_at(d.range.1);
            let span = (lo - 0.05 * (hi - lo), hi + 0.05 * (hi - lo));
            d.input.generate(&mut s.rng(2 + k as u64), span, hold, len)
        })
        .collect();
    let quiet = vec![0.0; references[0].len()];
    let (_, y0) = run(d, &plant, &references[0], &quiet, lens[0].0);
    let sigma = sigma_for(variance(&y0[lens[0].0..]), d.snr_db);
    let mut clean = Vec::new();
    let mut noises = Vec::new();
    for (k, r) in references.iter().enumerate() {
        let n = noise(&mut s.rng(4 + k as u64), d.colour, sigma, r.len());
        let (u, y) = run(d, &plant, r, &n.v, lens[k].0);
        clean.push(Clean { u, y });
        noises.push(n);
    }
    (clean, noises, sigma)
}

/// One record of the loop: `u_min` during the hold, then `u(t) = u(t−1) + k_p (e(t) −
/// e(t−1)) + k_i e(t)`, `e = r − (y + v)`, clamped to the range. Returns the input and the
/// noise-free output.
fn run(d: &Design, plant: &Discrete, r: &[f64], v: &[f64], hold: usize) -> (Vec<f64>, Vec<f64>) {
    let (kp, ki) = gains(d);
    let (lo, hi) = d.range;
    let mut el = Element::new(d.kind, d.borders.clone(), lo);
    let mut x: DVector<f64> = plant.rest(el.next(lo));
    let (mut u_prev, mut e_prev) = (lo, 0.0);
    let (mut us, mut ys) = (Vec::with_capacity(r.len()), Vec::with_capacity(r.len()));
    for t in 0..r.len() {
        let y = plant.c.dot(&x);
        let e = r[t] - (y + v[t]);
        let u = if t < hold {
            lo
        } else {
            (u_prev + kp * (e - e_prev) + ki * e).clamp(lo, hi)
        };
        (u_prev, e_prev) = (u, e);
        let w = el.next(u);
        x = &plant.phi * &x + &plant.gamma * w;
        us.push(u);
        ys.push(y);
    }
    (us, ys)
}
