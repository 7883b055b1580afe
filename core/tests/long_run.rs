//! Long runs: 10^6 samples of a Table I experiment on the paper's backlash system (Section
//! IV-B: `H_a(u) = atan(u − 1)`, `H_d(u) = atan(u + 1)`, the paper's `G(q)` and its coloured
//! noise at 10 dB SNR), accumulated by the streaming core in `f32` with compensated output
//! sums (`Identifier<f32, _, _, Compensated>`) and in `f64` with plain sums from the same data
//! (rounded to `f32` once, so both precisions see the same numbers). Plain `f32` sums drift
//! out of this tolerance by 10^6 samples (noise-floor singular values 14× the tolerance; see
//! `docs/reliability.md`, *Long runs*).
//!
//! **Tolerance.** Single precision must not add an error comparable to the estimator's own:
//! every compared quantity of the `f32` model must lie within a quarter of that quantity's
//! standard deviation over noise realisations at the same record length. The standard
//! deviations are measured here (40 runs of j = 4000 in `f64`) and scaled by `√(4000 / N)`
//! (not the whitened singular values, whose spread does not shrink with `N`).
//! Compared: the poles, the Markov parameters `h_0 … h_39`, the borders at the knots, μ0, the
//! singular values `σ_i / σ₁` and the whitened singular values of the order selection.
//!
//! `HSID_LONG_RUN_SAMPLES=N` changes the record length; the `#[ignore]`d test runs 3·10^7
//! samples. The inline simulator keeps the core's tests free of host code.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::sync::OnceLock;

use hsid::{
    AUTO_ORDER_MARGIN, Compensated, Direction, Excitation, Identifier, Knots, Model, MuZero, Order,
    Settings,
};
use rand_core::{Rng, SeedableRng};
use rand_pcg::Pcg32;

const HOLD: usize = 300;
/// Record length of the Monte Carlo that calibrates the tolerances.
const J0: usize = 4000;
/// Runs of that Monte Carlo.
const RUNS: u64 = 40;
/// Fraction of the statistical standard deviation single precision may add.
const FRACTION: f64 = 0.25;

/// A standard normal sample (Box–Muller).
fn gauss(rng: &mut Pcg32) -> f64 {
    let u1 = (f64::from(rng.next_u32()) + 0.5) / 4_294_967_296.0;
    let u2 = f64::from(rng.next_u32()) / 4_294_967_296.0;
    (-2.0 * u1.ln()).sqrt() * (core::f64::consts::TAU * u2).cos()
}

/// `HOLD + n` samples `(u, y)` of the paper's backlash experiment at 10 dB SNR, rounded to
/// `f32`; `seed` selects the excitation and the noise.
fn record(n: usize, seed: u64) -> Vec<(f32, f32)> {
    let u: Vec<f32> =
        Excitation::<f32, _>::new(-3.0, 3.0, HOLD, Pcg32::seed_from_u64(1 + 2 * seed))
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
    // v = (1 + 0.5 q⁻¹)/(1 − 0.85 q⁻¹) e with var(y_clean) / var(v) = 10 over the
    // excitation: var(v) = σ_e² (1 + 1.35² / (1 − 0.85²)).
    let tail = &clean[HOLD..];
    let mean = tail.iter().sum::<f64>() / tail.len() as f64;
    let var = tail.iter().map(|y| (y - mean) * (y - mean)).sum::<f64>() / tail.len() as f64;
    let energy = 1.0 + 1.35f64.powi(2) / (1.0 - 0.85f64.powi(2));
    let sigma = (var / (10.0 * energy)).sqrt();
    let mut rng = Pcg32::seed_from_u64(2 + 2 * seed);
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
/// 2 so that models are compared like for like (the automatic order is compared separately,
/// from the whitened singular values).
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

/// The compared quantities of a model, in `f64`, by group.
#[derive(Clone, Debug)]
struct Summary {
    /// Upper pole (re, im).
    poles: Vec<f64>,
    /// h_0 … h_39.
    markov: Vec<f64>,
    /// P_a then P_d at the knots.
    borders: Vec<f64>,
    mu0: Vec<f64>,
    /// σ_i / σ₁.
    sv: Vec<f64>,
    /// Whitened singular values.
    white: Vec<f64>,
}

/// Index of the whitened singular values in [`GROUPS`].
const WHITE: usize = 5;

const GROUPS: [&str; 6] = [
    "poles",
    "Markov parameters",
    "borders",
    "mu0",
    "singular values / σ₁",
    "whitened singular values",
];

impl Summary {
    fn of<T: hsid::Real>(m: &Model<T, 14>) -> Self {
        assert_eq!(m.order(), 2);
        let a = |i, j| m.a(i, j).to_f64();
        let tr = a(0, 0) + a(1, 1);
        let det = a(0, 0) * a(1, 1) - a(0, 1) * a(1, 0);
        let mut borders = Vec::new();
        for d in [Direction::Ascending, Direction::Descending] {
            borders.extend(m.border_values(d).iter().map(|v| v.to_f64()));
        }
        let s1 = m.singular_values()[0].to_f64();
        Self {
            poles: vec![tr / 2.0, (det - tr * tr / 4.0).max(0.0).sqrt()],
            markov: (0..40).map(|k| m.markov(k).to_f64()).collect(),
            borders,
            mu0: vec![m.mu0().to_f64()],
            sv: m
                .singular_values()
                .iter()
                .map(|v| v.to_f64() / s1)
                .collect(),
            white: m
                .whitened_singular_values()
                .iter()
                .map(|v| v.to_f64())
                .collect(),
        }
    }

    fn groups(&self) -> [&[f64]; 6] {
        [
            &self.poles,
            &self.markov,
            &self.borders,
            &self.mu0,
            &self.sv,
            &self.white,
        ]
    }

    /// The order [`Order::Auto`] would pick from the whitened singular values.
    fn auto_order(&self) -> usize {
        let (f, pm) = (10.0, 10.0 * 14.0);
        let thr = AUTO_ORDER_MARGIN * (1.0 + f64::sqrt(f / pm));
        self.white.iter().take_while(|&&w| w > thr).count()
    }
}

/// Standard deviation of every compared quantity over `RUNS` noise realisations of `J0`
/// samples (f64). All but the whitened singular values shrink like `1/√N` (checked against
/// 40 runs of 40,000 samples: the standard deviations of `σ_i/σ₁` fall by 3.1–3.5, those of
/// the whitened noise-floor values stay at 0.05–0.07); μ0 comes from the hold alone, its
/// spread (of a 150-sample mean) does not shrink, which only makes its tolerance stricter.
fn spread() -> &'static Summary {
    static S: OnceLock<Summary> = OnceLock::new();
    S.get_or_init(|| {
        let runs: Vec<Summary> = (100..100 + RUNS)
            .map(|seed| {
                let mut id = Identifier::<f64, 14, 20>::new(settings()).unwrap();
                for &(u, y) in &record(J0, seed) {
                    id.push(f64::from(u), f64::from(y));
                }
                let mut ws = vec![0.0; id.workspace_len()];
                Summary::of(&id.solve(&mut ws).unwrap())
            })
            .collect();
        let std = |pick: &dyn Fn(&Summary) -> &[f64]| -> Vec<f64> {
            let len = pick(&runs[0]).len();
            (0..len)
                .map(|i| {
                    let v: Vec<f64> = runs.iter().map(|r| pick(r)[i]).collect();
                    let mean = v.iter().sum::<f64>() / v.len() as f64;
                    let ss = v.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>();
                    (ss / (v.len() - 1) as f64).sqrt()
                })
                .collect()
        };
        Summary {
            poles: std(&|s| &s.poles),
            markov: std(&|s| &s.markov),
            borders: std(&|s| &s.borders),
            mu0: std(&|s| &s.mu0),
            sv: std(&|s| &s.sv),
            white: std(&|s| &s.white),
        }
    })
}

/// The two models at one record length.
struct Stop {
    samples: usize,
    single: Summary,
    double: Summary,
}

/// Runs `n` excitation samples through both precisions, solving at 4019, 10^4, 10^5, … and
/// `n` samples after the hold.
fn run(n: usize) -> Vec<Stop> {
    let data = record(n, 0);
    let mut single = Identifier::<f32, 14, 20, Compensated>::new(settings()).unwrap();
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
    let mut stops = stops.into_iter().peekable();
    let mut out = Vec::new();
    for (i, &(u, y)) in data.iter().enumerate() {
        single.push(u, y);
        double.push(f64::from(u), f64::from(y));
        let after_hold = (i + 1).saturating_sub(HOLD);
        if i + 1 > HOLD && stops.peek() == Some(&after_hold) {
            stops.next();
            out.push(Stop {
                samples: after_hold,
                single: Summary::of(&single.solve(&mut ws32).unwrap()),
                double: Summary::of(&double.solve(&mut ws64).unwrap()),
            });
        }
    }
    assert_eq!(single.fault(), None);
    assert_eq!(double.fault(), None);
    out
}

/// The 10^6-sample run, shared by the tests below.
fn million() -> &'static [Stop] {
    static R: OnceLock<Vec<Stop>> = OnceLock::new();
    R.get_or_init(|| {
        let n = std::env::var("HSID_LONG_RUN_SAMPLES")
            .ok()
            .and_then(|v| v.parse().ok())
            .unwrap_or(1_000_000);
        run(n)
    })
}

/// Checks the groups `which` of every stop; prints the largest difference and the largest
/// ratio difference / tolerance per group, and returns the violations.
fn check(stops: &[Stop], which: &[usize]) -> Vec<String> {
    let sd = spread();
    let mut bad = Vec::new();
    for st in stops {
        let shrink = (J0 as f64 / st.samples as f64).sqrt();
        let (a, b, s) = (st.single.groups(), st.double.groups(), sd.groups());
        for &g in which {
            // The whitened singular values are normalised by √j: their spread does not shrink.
            let scale = FRACTION * if g == WHITE { 1.0 } else { shrink };
            let (mut worst_diff, mut worst_ratio, mut tol_at_worst, mut worst_at) =
                (0.0f64, 0.0f64, 0.0, 0);
            for (i, ((&x, &y), &sigma)) in a[g].iter().zip(b[g]).zip(s[g]).enumerate() {
                let tol = scale * sigma;
                let d = (x - y).abs();
                worst_diff = worst_diff.max(d);
                if d / tol > worst_ratio {
                    worst_ratio = d / tol;
                    tol_at_worst = tol;
                    worst_at = i;
                }
                if d > tol {
                    bad.push(format!(
                        "N = {}: {} [{i}]: f32 {x:.6e}, f64 {y:.6e}, |diff| {d:.2e} > tolerance {tol:.2e}",
                        st.samples, GROUPS[g]
                    ));
                }
            }
            println!(
                "N = {:>9}: {:<26} max |f32 − f64| = {worst_diff:.2e}; worst diff/tolerance = {worst_ratio:.3} at [{worst_at}] (tolerance there {tol_at_worst:.2e})",
                st.samples, GROUPS[g]
            );
        }
    }
    bad
}

/// Poles, Markov parameters, borders and μ0 of the `f32` model after 10^6 samples.
#[test]
fn million_samples_f32_model_tracks_f64() {
    let bad = check(million(), &[0, 1, 2, 3]);
    assert!(bad.is_empty(), "f32 drifts from f64:\n{}", bad.join("\n"));
}

/// Singular values (and the automatic order) of the `f32` model after 10^6 samples.
#[test]
fn million_samples_f32_singular_values_track_f64() {
    let stops = million();
    for st in stops {
        assert_eq!(
            st.single.auto_order(),
            st.double.auto_order(),
            "automatic order at N = {}",
            st.samples
        );
    }
    let bad = check(stops, &[4, 5]);
    assert!(bad.is_empty(), "f32 drifts from f64:\n{}", bad.join("\n"));
}

/// 3·10^7 samples: where plain `f32` sums lose their increments (the ulp of a sum of ~10^7
/// is 1 in `f32`).
#[test]
#[ignore = "3·10^7 samples, ~20 s; fails: the compensated output sums hold to 10^6 samples, not 10^7 (docs/reliability.md, Long runs)"]
fn thirty_million_samples_f32_tracks_f64() {
    let stops = run(30_000_000);
    let bad = check(&stops, &[0, 1, 2, 3, 4, 5]);
    assert!(bad.is_empty(), "f32 drifts from f64:\n{}", bad.join("\n"));
}
