//! Long runs: 10^6 samples of a Table I experiment on the paper's backlash system (Section
//! IV-B: `H_a(u) = atan(u − 1)`, `H_d(u) = atan(u + 1)`, the paper's `G(q)` and coloured noise
//! at 10 dB SNR), accumulated by the streaming core in `f32` and in `f64` from the same data.
//! The `f32` model must stay within stated tolerances of the `f64` one: no precision collapse
//! of the lagged sums.
//!
//! The tolerances are a quarter of the estimator's own spread at that record length (the
//! paper's Monte Carlo spread at j = 4000 scaled by `√(4000 / N)`), so single precision never
//! dominates the statistical error. The simulator is written inline (no host dependency).
//!
//! `HSID_LONG_RUN_SAMPLES=N` changes the record length; the `#[ignore]`d test runs 3·10^7
//! samples, where naive `f32` accumulation does collapse (see `docs/reliability.md`).
#![allow(clippy::unwrap_used, clippy::expect_used)]

use hsid::{Direction, Excitation, Identifier, Knots, Model, MuZero, Order, Settings};
use rand_core::{RngCore, SeedableRng};
use rand_pcg::Pcg32;

const HOLD: usize = 300;

/// A standard normal sample (Box–Muller).
fn gauss(rng: &mut Pcg32) -> f64 {
    let u1 = (f64::from(rng.next_u32()) + 0.5) / 4_294_967_296.0;
    let u2 = f64::from(rng.next_u32()) / 4_294_967_296.0;
    (-2.0 * u1.ln()).sqrt() * (core::f64::consts::TAU * u2).cos()
}

/// `HOLD + n` samples `(u, y)` of the paper's backlash experiment at 10 dB SNR, rounded to
/// `f32` so that both precisions see exactly the same numbers.
fn record(n: usize) -> Vec<(f32, f32)> {
    record_seed(n, 0)
}
fn record_seed(n: usize, seed: u64) -> Vec<(f32, f32)> {
    let u: Vec<f32> =
        Excitation::<f32, _>::new(-3.0, 3.0, HOLD, Pcg32::seed_from_u64(1 + 100 * seed))
            .unwrap()
            .take(HOLD + n)
            .collect();
    // Backlash (play operator) from rest at u_min, then G(q) from zero initial conditions.
    let mut w = (-3.0f64 + 1.0).atan();
    let (mut w1, mut w2, mut y1, mut y2) = (0.0, 0.0, 0.0, 0.0);
    let clean: Vec<f64> = u
        .iter()
        .map(|&u| {
            let u = f64::from(u);
            w = w.max((u - 1.0).atan()).min((u + 1.0).atan());
            let y = 1.8858 * y1 - 0.9048 * y2 + 0.1994 * w1 - 0.1804 * w2;
            (w2, w1, y2, y1) = (w1, w, y1, y);
            y
        })
        .collect();
    // Noise v = (1 + 0.5 q⁻¹)/(1 − 0.85 q⁻¹) e, scaled so that var(y) / var(v) = 10 over the
    // excitation: var(v) = σ_e² · (1 + 1.35² / (1 − 0.85²)).
    let tail = &clean[HOLD..];
    let mean = tail.iter().sum::<f64>() / tail.len() as f64;
    let var = tail.iter().map(|y| (y - mean) * (y - mean)).sum::<f64>() / tail.len() as f64;
    let energy = 1.0 + 1.35f64.powi(2) / (1.0 - 0.85f64.powi(2));
    let sigma = (var / (10.0 * energy)).sqrt();
    let mut rng = Pcg32::seed_from_u64(2 + 100 * seed);
    let (mut e1, mut v1) = (0.0, 0.0);
    u.iter()
        .zip(&clean)
        .map(|(&u, &y)| {
            let e = sigma * gauss(&mut rng);
            let v = 0.85 * v1 + e + 0.5 * e1;
            (e1, v1) = (e, v);
            (u, (y + v) as f32)
        })
        .collect()
}

/// The paper's settings (7 uniform segments per path on [-3, 3], f = p = 10), order fixed at
/// 2 so that models are compared like for like (with 10^7 samples the automatic order sees
/// the approximation error of the piecewise-linear borders as a third state).
fn settings<T: hsid::Real>() -> Settings<T, 14> {
    let knots = Knots::<T, 14>::uniform(T::of(-3.0), T::of(3.0), 7, 7).unwrap();
    let mut s = Settings::new(
        knots,
        10,
        10,
        MuZero::Hold {
            len: HOLD,
            settle: 150,
        },
    );
    s.order = Order::Fixed(2);
    s
}

/// What is compared, in `f64`.
struct Summary {
    sv: Vec<f64>,
    poles: (f64, f64),
    markov: Vec<f64>,
    borders: Vec<f64>,
    mu0: f64,
}

fn summary<T: hsid::Real>(m: &Model<T, 14>) -> Summary {
    assert_eq!(m.order(), 2);
    let a = |i, j| m.a(i, j).to_f64();
    let tr = a(0, 0) + a(1, 1);
    let det = a(0, 0) * a(1, 1) - a(0, 1) * a(1, 0);
    let mut borders = Vec::new();
    for d in [Direction::Ascending, Direction::Descending] {
        borders.extend(m.border_values(d).iter().map(|v| v.to_f64()));
    }
    Summary {
        sv: m.singular_values().iter().map(|v| v.to_f64()).collect(),
        poles: (tr / 2.0, (det - tr * tr / 4.0).max(0.0).sqrt()),
        markov: (0..40).map(|k| m.markov(k).to_f64()).collect(),
        borders,
        mu0: m.mu0().to_f64(),
    }
}

fn max_abs_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// Differences of the `f32` model from the `f64` model.
#[derive(Debug, Clone, Copy)]
struct Diff {
    samples: usize,
    /// Largest singular-value difference relative to σ₁.
    sv: f64,
    /// Distance between the upper poles.
    poles: f64,
    /// Largest Markov-parameter difference (h_0 … h_39).
    markov: f64,
    /// Largest border difference at the knots.
    borders: f64,
    mu0: f64,
}

fn diff(a: &Summary, b: &Summary, samples: usize) -> Diff {
    Diff {
        samples,
        sv: max_abs_diff(&a.sv, &b.sv) / b.sv[0],
        poles: (a.poles.0 - b.poles.0).hypot(a.poles.1 - b.poles.1),
        markov: max_abs_diff(&a.markov, &b.markov),
        borders: max_abs_diff(&a.borders, &b.borders),
        mu0: (a.mu0 - b.mu0).abs(),
    }
}

/// Runs `n` excitation samples through both precisions, solving at a few record lengths on
/// the way; returns the differences at each.
fn run(n: usize) -> Vec<Diff> {
    let data = record(n);
    let mut single = Identifier::<f32, 14, 20>::new(settings()).unwrap();
    let mut double = Identifier::<f64, 14, 20>::new(settings()).unwrap();
    let mut ws32 = vec![0.0f32; single.workspace_len()];
    let mut ws64 = vec![0.0f64; double.workspace_len()];
    let mut stops = vec![4019];
    let mut s = 10_000;
    while s < n {
        stops.push(s);
        s *= 10;
    }
    stops.push(n);
    let mut out = Vec::new();
    let mut stops = stops.into_iter().peekable();
    for (i, &(u, y)) in data.iter().enumerate() {
        single.push(u, y);
        double.push(f64::from(u), f64::from(y));
        let after_hold = (i + 1).saturating_sub(HOLD);
        if i + 1 > HOLD && stops.peek() == Some(&after_hold) {
            stops.next();
            let b = summary(&double.solve(&mut ws64).unwrap());
            let a = summary(&single.solve(&mut ws32).unwrap());
            let d = diff(&a, &b, after_hold);
            println!(
                "sv per index {:?}",
                a.sv.iter()
                    .zip(&b.sv)
                    .map(|(x, y)| format!("{:.1e}/{:.1e}", (x - y).abs() / b.sv[0], y / b.sv[0]))
                    .collect::<Vec<_>>()
            );
            println!(
                "markov per k {:?}",
                a.markov
                    .iter()
                    .zip(&b.markov)
                    .take(12)
                    .map(|(x, y)| format!("{:.1e}", (x - y).abs()))
                    .collect::<Vec<_>>()
            );
            println!(
                "borders {:?}",
                a.borders
                    .iter()
                    .zip(&b.borders)
                    .map(|(x, y)| format!("{:.1e}", (x - y).abs()))
                    .collect::<Vec<_>>()
            );
            println!(
                "N = {:>9}: f32 − f64: sv {:.2e} (rel. σ₁), poles {:.2e}, Markov {:.2e}, borders {:.2e}, μ0 {:.2e}; f64 pole {:.5} ± {:.5}j",
                d.samples, d.sv, d.poles, d.markov, d.borders, d.mu0, b.poles.0, b.poles.1
            );
            out.push(d);
        }
    }
    assert_eq!(double.fault(), None);
    out
}

/// Tolerances at `n` samples: a quarter of the estimator's spread, from the paper's Monte Carlo
/// at j = 4000 (pole std 0.006, single-run border RMS 0.14, h₁ spread ≈ 0.01) scaled by
/// `√(4000 / n)`; singular values relative to σ₁ like the poles.
fn tolerances(n: usize) -> Diff {
    let scale = 0.25 * (4000.0 / n as f64).sqrt();
    Diff {
        samples: n,
        sv: 0.006 * scale,
        poles: 0.006 * scale,
        markov: 0.01 * scale,
        borders: 0.14 * scale,
        mu0: 1e-6,
    }
}

fn check(d: &Diff) {
    let t = tolerances(d.samples);
    println!(
        "tolerances at N = {}: sv {:.1e}, poles {:.1e}, Markov {:.1e}, borders {:.1e}, μ0 {:.0e}",
        t.samples, t.sv, t.poles, t.markov, t.borders, t.mu0
    );
    assert!(d.sv <= t.sv, "singular values: {d:?} vs {t:?}");
    assert!(d.poles <= t.poles, "poles: {d:?} vs {t:?}");
    assert!(d.markov <= t.markov, "Markov parameters: {d:?} vs {t:?}");
    assert!(d.borders <= t.borders, "borders: {d:?} vs {t:?}");
    assert!(d.mu0 <= t.mu0, "mu0: {d:?} vs {t:?}");
}

#[test]
fn million_samples_single_precision_tracks_double() {
    let n = std::env::var("HSID_LONG_RUN_SAMPLES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(1_000_000);
    let diffs = run(n);
    for d in &diffs {
        check(d);
    }
}

/// Beyond 10^7 samples the `f32` lagged sums lose the small increments (a sum of ~10^7
/// has an ulp of 1 in `f32`): this documents the collapse until the accumulation is compensated.
#[test]
#[ignore = "3·10^7 samples (~15 s); f32 collapses there with plain summation"]
fn thirty_million_samples_single_precision() {
    let diffs = run(30_000_000);
    for d in &diffs {
        check(d);
    }
}

#[test]
#[ignore]
fn scratch_spread() {
    for n in [4000usize, 100_000] {
        let mut svs = vec![];
        let mut poles = vec![];
        let mut h1 = vec![];
        for seed in 0..40u64 {
            // reuse record with different seeds: hack via global? simple re-implementation
            let data = record_seed(n, seed);
            let mut id = Identifier::<f64, 14, 20>::new(settings()).unwrap();
            for &(u, y) in &data {
                id.push(f64::from(u), f64::from(y));
            }
            let mut ws = vec![0.0; id.workspace_len()];
            let s = summary(&id.solve(&mut ws).unwrap());
            svs.push(s.sv.iter().map(|v| v / s.sv[0]).collect::<Vec<_>>());
            poles.push(s.poles);
            h1.push(s.markov.clone());
        }
        let std = |v: &[f64]| {
            let m = v.iter().sum::<f64>() / v.len() as f64;
            (v.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / (v.len() - 1) as f64).sqrt()
        };
        for i in 0..10 {
            print!(
                "{:.2e} ",
                std(&svs.iter().map(|s| s[i]).collect::<Vec<_>>())
            );
        }
        println!();
        println!(
            "pole std {:.2e} {:.2e}",
            std(&poles.iter().map(|p| p.0).collect::<Vec<_>>()),
            std(&poles.iter().map(|p| p.1).collect::<Vec<_>>())
        );
        let mut hm: f64 = 0.0;
        for k in 0..40 {
            hm = hm.max(std(&h1.iter().map(|h| h[k]).collect::<Vec<_>>()));
        }
        println!("markov max std {hm:.2e}");
    }
}
