//! Shared pieces of the property tests (`core/tests/proptest_*.rs`): the deterministic runner
//! configuration, a small Hammerstein plant, the Table I record, and the checks every outcome
//! of `solve` must pass.
#![allow(dead_code, clippy::panic)]

use hsid::{
    Basis, Direction, Error, Excitation, Identifier, Knots, Method, Model, MuZero, Real, Settings,
};
use proptest::prelude::*;
use proptest::test_runner::{Config, RngAlgorithm, RngSeed};
use rand_core::SeedableRng;
use rand_pcg::Pcg32;

/// Regressor-channel capacity of the identifiers under test.
pub const M: usize = 6;
/// Block-row capacity (`f + p`).
pub const K: usize = 8;

/// The identifier type of the property tests.
pub type Id<T> = Identifier<T, M, K>;

/// A deterministic runner configuration: `cases` cases from the fixed ChaCha seed `seed`
/// (`HSID_PROPTEST_SEED=<u64>` overrides it to explore other cases locally), no failure
/// persistence (nothing read or written between runs), so CI runs the same cases every time.
pub fn config(cases: u32, seed: u64) -> Config {
    let seed = std::env::var("HSID_PROPTEST_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(seed);
    Config {
        cases,
        rng_algorithm: RngAlgorithm::ChaCha,
        rng_seed: RngSeed::Fixed(seed),
        failure_persistence: None,
        max_shrink_iters: 2048,
        ..Config::default()
    }
}

/// Outcome counters of a property, printed after the run so that a property that passes
/// vacuously (e.g. every case refused before the interesting part) shows.
#[derive(Default)]
pub struct Tally(std::sync::Mutex<std::collections::BTreeMap<String, usize>>);

impl Tally {
    /// Counts one case under `label`.
    pub fn count(&self, label: impl Into<String>) {
        if let Ok(mut m) = self.0.lock() {
            *m.entry(label.into()).or_default() += 1;
        }
    }
    /// The count under `label`.
    pub fn get(&self, label: &str) -> usize {
        self.0
            .lock()
            .map(|m| m.get(label).copied().unwrap_or(0))
            .unwrap_or(0)
    }
    /// Prints every label and count.
    pub fn print(&self, name: &str) {
        if let Ok(m) = self.0.lock() {
            let total: usize = m.values().sum();
            println!("{name}: {total} cases");
            for (k, v) in m.iter() {
                println!("  {k:<40} {v}");
            }
        }
    }
}

/// Runs `cases` cases of `test` on values of `strategy` with the fixed `seed` (see
/// [`config`]) and panics with proptest's (shrunk) counterexample on failure.
pub fn run_cases<S: Strategy>(
    cases: u32,
    seed: u64,
    strategy: S,
    test: impl Fn(S::Value) -> Result<(), TestCaseError>,
) where
    S::Value: std::fmt::Debug,
{
    let mut runner = proptest::test_runner::TestRunner::new(config(cases, seed));
    if let Err(e) = runner.run(&strategy, test) {
        panic!("{e}");
    }
}

/// A stable LTI plant of order 1 or 2 with unit static gain, in direct form.
#[derive(Clone, Debug)]
pub struct Lti {
    /// Numerator `b_0 + b_1 q⁻¹ + b_2 q⁻²`.
    pub b: [f64; 3],
    /// Denominator `1 + a_1 q⁻¹ + a_2 q⁻²`.
    pub a: [f64; 2],
    x: [f64; 2],
    y: [f64; 2],
}

impl Lti {
    /// `G(q)` with the given poles (a real pair or a complex pair `re ± im j`), a zero `z`
    /// (numerator `(q⁻¹ − z q⁻²)` for order 2, `q⁻¹` for order 1), a feed-through fraction
    /// `d`, and `G(1) = 1`.
    pub fn new(order: usize, p1: f64, p2: f64, complex: bool, zero: f64, d: f64) -> Self {
        let (a, mut b) = if order == 1 {
            ([-p1, 0.0], [d, 1.0, 0.0])
        } else if complex {
            // p1 ± p2 j
            ([-2.0 * p1, p1 * p1 + p2 * p2], [d, 1.0, -zero])
        } else {
            ([-(p1 + p2), p1 * p2], [d, 1.0, -zero])
        };
        let gain = (b[0] + b[1] + b[2]) / (1.0 + a[0] + a[1]);
        for v in &mut b {
            *v /= gain;
        }
        Self {
            b,
            a,
            x: [0.0; 2],
            y: [0.0; 2],
        }
    }

    /// The true order (the numerator's zero never cancels a pole, see the strategies).
    pub fn order(&self) -> usize {
        if self.a[1] == 0.0 { 1 } else { 2 }
    }

    /// One step: input `w(t)`, output `y(t)`.
    pub fn step(&mut self, w: f64) -> f64 {
        let y = self.b[0] * w + self.b[1] * self.x[0] + self.b[2] * self.x[1]
            - self.a[0] * self.y[0]
            - self.a[1] * self.y[1];
        self.x = [w, self.x[0]];
        self.y = [y, self.y[0]];
        y
    }

    /// Markov parameters `h_0 … h_{n−1}` (impulse response from rest).
    pub fn markov(&self, n: usize) -> Vec<f64> {
        let mut g = Self {
            x: [0.0; 2],
            y: [0.0; 2],
            ..self.clone()
        };
        (0..n)
            .map(|k| g.step(if k == 0 { 1.0 } else { 0.0 }))
            .collect()
    }
}

/// Strategy for a stable plant with unit static gain: order 1 or 2, poles of modulus
/// 0.1–0.85, real or complex, a zero at least 0.3 away from the poles, optional feed-through.
pub fn plant() -> impl Strategy<Value = Lti> {
    (
        1usize..=2,
        0.1f64..0.85,
        0.1f64..0.85,
        any::<bool>(),
        -0.6f64..0.6,
        prop_oneof![Just(0.0), -0.5f64..0.5],
        any::<bool>(),
        any::<bool>(),
    )
        .prop_map(|(order, r1, r2, complex, zero, d, s1, s2)| {
            if order == 2 && complex {
                // re ± im j with modulus r1, angle 20°–80°.
                let ang = (20.0 + 60.0 * r2) * core::f64::consts::PI / 180.0;
                let (re, im) = (r1 * ang.cos(), r1 * ang.sin());
                let z = if (zero - re).abs() < 0.3 { -0.5 } else { zero };
                Lti::new(2, re, im, true, z, d)
            } else {
                let p1 = if s1 { r1 } else { -r1 * 0.5 };
                let mut p2 = if s2 { r2 } else { -r2 * 0.5 };
                if (p1 - p2).abs() < 0.15 {
                    p2 = p1 - 0.3 * p1.signum().max(0.5);
                }
                // Poles lie in [-0.425, 0.85): -0.95 is always at least 0.3 away.
                let far = |z: f64| (z - p1).abs() >= 0.3 && (z - p2).abs() >= 0.3;
                let z = if far(zero) { zero } else { -0.95 };
                Lti::new(order, p1, p2, false, z, d)
            }
        })
}

/// Piecewise-linear interpolation of `values` on increasing `knots` (clamped).
pub fn pwl(knots: &[f64], values: &[f64], u: f64) -> f64 {
    if u <= knots[0] {
        return values[0];
    }
    for i in 0..knots.len() - 1 {
        if u <= knots[i + 1] {
            let t = (u - knots[i]) / (knots[i + 1] - knots[i]);
            return values[i] + (values[i + 1] - values[i]) * t;
        }
    }
    values[values.len() - 1]
}

/// A switch whose borders are piecewise linear on the identification knots, so the model
/// class is exact: `P_a(u_min) = P_d(u_min) = μ0`.
#[derive(Clone, Debug)]
pub struct PwlSwitch {
    pub asc_knots: Vec<f64>,
    pub asc: Vec<f64>,
    pub desc_knots: Vec<f64>,
    pub desc: Vec<f64>,
    up: bool,
    prev: f64,
}

impl PwlSwitch {
    pub fn new(asc_knots: Vec<f64>, asc: Vec<f64>, desc_knots: Vec<f64>, desc: Vec<f64>) -> Self {
        let prev = asc_knots[0];
        Self {
            asc_knots,
            asc,
            desc_knots,
            desc,
            up: false,
            prev,
        }
    }

    /// δ(t) as the paper defines it (initially descending), then the border.
    pub fn step(&mut self, u: f64) -> f64 {
        if u > self.prev {
            self.up = true;
        } else if u < self.prev {
            self.up = false;
        }
        self.prev = u;
        if self.up {
            pwl(&self.asc_knots, &self.asc, u)
        } else {
            pwl(&self.desc_knots, &self.desc, u)
        }
    }
}

/// `n` samples of the Table I excitation on the knots' interval (a hold of `hold` samples at
/// `u_min` first), through `switch` and `plant`, in the scalar type `T`.
pub fn table1<T: Real>(
    knots: &Knots<T, M>,
    hold: usize,
    n: usize,
    seed: u64,
    switch: &mut PwlSwitch,
    plant: &mut Lti,
) -> Vec<(T, T)> {
    Excitation::<T, _>::new(
        knots.u_min(),
        knots.u_max(),
        hold,
        Pcg32::seed_from_u64(seed),
    )
    .map(|e| {
        e.take(n)
            .map(|u| {
                let y = plant.step(switch.step(u.to_f64()));
                (u, T::of(y))
            })
            .collect()
    })
    .unwrap_or_default()
}

/// Border values at the knots: μ0 at u_min, then μ0 + the random values, kept apart from μ0
/// on the first segment so that every channel carries signal.
pub fn borders(mu0: f64, v: &[f64]) -> Vec<f64> {
    let mut out = vec![mu0];
    out.extend(v.iter().map(|x| {
        mu0 + if x.abs() < 0.2 {
            0.2f64.copysign(*x)
        } else {
            *x
        }
    }));
    out
}

/// [`table1`] with white noise of standard deviation `noise` added to `y` (a uniform deviate
/// from an LCG seeded with `seed`, so no extra dependency), the result rounded to `T` and
/// held as `f64` so that an `f64` identifier can see exactly the same numbers.
pub fn noisy_record<T: Real>(
    knots: &Knots<T, M>,
    hold: usize,
    n: usize,
    seed: u64,
    noise: f64,
    switch: &mut PwlSwitch,
    plant: &mut Lti,
) -> Vec<(f64, f64)> {
    let mut rng = seed ^ 0x9E37_79B9_7F4A_7C15;
    table1(knots, hold, n, seed, switch, plant)
        .into_iter()
        .map(|(u, y)| {
            rng = rng
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            let e = ((rng >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * noise * 12f64.sqrt();
            (u.to_f64(), T::of(y.to_f64() + e).to_f64())
        })
        .collect()
}

/// Strategy: strictly increasing knots from `lo` to `hi` with `segments` segments, each at
/// least `min_frac` of the interval (so every segment is visited by a Table I record).
pub fn knot_vector(
    lo: f64,
    hi: f64,
    segments: usize,
    min_frac: f64,
) -> impl Strategy<Value = Vec<f64>> {
    proptest::collection::vec(0.0f64..1.0, segments).prop_map(move |w| {
        let total: f64 = w.iter().sum::<f64>() + 1e-9;
        let free = 1.0 - min_frac * segments as f64;
        let mut k = vec![lo];
        let mut acc = 0.0;
        for (i, wi) in w.iter().enumerate() {
            acc += min_frac + free * wi / total;
            k.push(if i + 1 == segments {
                hi
            } else {
                lo + (hi - lo) * acc
            });
        }
        k
    })
}

/// `true` if every number of the model is finite.
pub fn all_finite<T: Real, const MM: usize>(m: &Model<T, MM>) -> bool {
    let n = m.order();
    let mut ok = m.d().finite() && m.mu0().finite() && m.static_gain().finite();
    for i in 0..n {
        for j in 0..n {
            ok &= m.a(i, j).finite();
        }
    }
    ok &= m.b().iter().chain(m.c()).all(|v| v.finite());
    for d in [Direction::Ascending, Direction::Descending] {
        ok &= m.border_values(d).iter().all(|v| v.finite());
    }
    ok &= m.singular_values().iter().all(|v| v.finite());
    ok &= m.whitened_singular_values().iter().all(|v| v.finite());
    ok
}

/// Checks a successful model: finite, order in `1..f`, G(1) = 1 to rounding, singular values
/// non-negative and sorted, border values at `u_min` equal to μ0 and one per knot.
pub fn check_model<T: Real, const MM: usize>(
    m: &Model<T, MM>,
    f: usize,
) -> Result<(), TestCaseError> {
    prop_assert!(all_finite(m), "non-finite model: {m:?}");
    prop_assert!(
        m.order() >= 1 && m.order() < f,
        "order {} with f = {f}",
        m.order()
    );
    let g = m.static_gain().to_f64();
    // dc = (C x_B + u_D) / g0 with |g0| > √ε · (|C x_B| + |u_D|): G(1) − 1 is a few ε / √ε.
    let tol = 64.0 * T::EPS.to_f64().sqrt();
    prop_assert!((g - 1.0).abs() <= tol, "G(1) = {g} (tolerance {tol:e})");
    let sv = m.singular_values();
    prop_assert_eq!(sv.len(), f);
    prop_assert!(
        sv.windows(2).all(|w| w[0] >= w[1]) && sv.iter().all(|&s| s >= T::zero()),
        "singular values {sv:?}"
    );
    for d in [Direction::Ascending, Direction::Descending] {
        let b = m.border_values(d);
        prop_assert_eq!(b.len(), m.knots().path(d).len());
        prop_assert!(
            b[0] == m.mu0(),
            "{d} border at u_min {:?} vs mu0 {:?}",
            b[0],
            m.mu0()
        );
    }
    Ok(())
}

/// Errors `solve` may return for data that passed `push` (no fault): the claim of each is
/// checked where it can be. `count` is the number of samples after the hold.
pub fn check_solve_error<T: Real>(
    e: &Error,
    id: &Id<T>,
    samples: &[(T, T)],
) -> Result<(), TestCaseError> {
    match *e {
        Error::TooFewSamples { have, need } => {
            prop_assert_eq!(have, id.accumulator().count());
            prop_assert_eq!(need, id.min_samples());
            prop_assert!(have < need);
        }
        Error::NoExcitation { path, knot } => {
            prop_assert!(id.accumulator().count() >= id.min_samples());
            let s = id.settings();
            prop_assert!(knot >= 1 && knot <= s.knots.segments(path));
            // No sample on that path may have excited the channel clearly.
            let peak = excitation_of(samples, s.mu0.hold_len(), &s.knots, s.basis, path, knot);
            prop_assert!(peak < 1e-3, "{e}: but the channel reached {peak}");
        }
        Error::Overflow { .. } => {
            // Only sums of squares beyond the scalar's range overflow: some |y − μ0| (or the
            // interval, in the ramp basis) must be at least √(MAX / (64·j)).
            let s = id.settings();
            let mu0 = id.mu0().map_or(0.0, |v| v.to_f64());
            let big = samples
                .iter()
                .skip(s.mu0.hold_len())
                .map(|&(_, y)| (y.to_f64() - mu0).abs().max(y.to_f64().abs()))
                .fold((s.knots.u_max() - s.knots.u_min()).to_f64(), f64::max);
            let j = id.accumulator().count().max(1) as f64;
            let max = if T::BYTES == 4 {
                f64::from(f32::MAX)
            } else {
                f64::MAX
            };
            let floor = (max / (64.0 * j)).sqrt();
            prop_assert!(big >= floor, "{e}: but the largest value is {big:e}");
        }
        Error::UnstableModel { spectral_radius } => {
            prop_assert!(id.accumulator().count() >= id.min_samples());
            prop_assert!(spectral_radius >= 1.0, "{e}");
        }
        Error::RankDeficient { .. }
        | Error::NoConvergence { .. }
        | Error::NoDynamics
        | Error::ZeroStaticGain
        | Error::IntegratingModel => {
            prop_assert!(id.accumulator().count() >= id.min_samples());
        }
        ref other => prop_assert!(false, "unexpected error from solve: {other:?} ({other})"),
    }
    let msg = e.to_string();
    prop_assert!(!msg.is_empty());
    Ok(())
}

/// The largest value basis function `knot` of `path` took over the samples after the hold,
/// computed independently of the core (δ(t) and the hat or ramp function from their
/// definitions).
pub fn excitation_of<T: Real>(
    samples: &[(T, T)],
    hold: usize,
    knots: &Knots<T, M>,
    basis: Basis,
    path: Direction,
    knot: usize,
) -> f64 {
    let k: Vec<f64> = knots.path(path).iter().map(|v| v.to_f64()).collect();
    let mut prev = knots.u_min().to_f64();
    let mut dir = Direction::Descending;
    let mut peak = 0.0f64;
    for (t, &(u, _)) in samples.iter().enumerate() {
        let u = u.to_f64();
        if t >= hold {
            if u > prev {
                dir = Direction::Ascending;
            } else if u < prev {
                dir = Direction::Descending;
            }
            if dir == path {
                let v = match basis {
                    // Hat peaking at knot `knot`.
                    Basis::Hat => {
                        let (l, c) = (k[knot - 1], k[knot]);
                        let r = k.get(knot + 1).copied().unwrap_or(c);
                        if u > l && u <= c {
                            (u - l) / (c - l)
                        } else if u > c && u < r {
                            (r - u) / (r - c)
                        } else {
                            0.0
                        }
                    }
                    // Ramp of segment `knot`: 0 below k[knot − 1].
                    Basis::Ramp => (u.min(k[knot]) - k[knot - 1]).max(0.0),
                };
                peak = peak.max(v);
            }
        }
        prev = u;
    }
    peak
}

/// Strategy for the µ0 mode with a hold of at most `max_hold` samples.
pub fn mu0_mode<T: Real>(max_hold: usize) -> impl Strategy<Value = MuZero<T>> {
    prop_oneof![
        (1..=max_hold)
            .prop_flat_map(|len| (Just(len), 0..len))
            .prop_map(|(len, settle)| MuZero::Hold { len, settle }),
        (-2.0f64..2.0).prop_map(|v| MuZero::Known(T::of(v))),
        Just(MuZero::Estimate),
    ]
}

/// Bit patterns of everything a model reports (for bit-identity checks).
pub fn model_bits<T: Real, const MM: usize>(m: &Model<T, MM>) -> Vec<u64> {
    let mut v: Vec<u64> = (0..12).map(|k| m.markov(k).to_f64().to_bits()).collect();
    v.push(m.order() as u64);
    v.extend(m.singular_values().iter().map(|x| x.to_f64().to_bits()));
    v.extend(
        m.whitened_singular_values()
            .iter()
            .map(|x| x.to_f64().to_bits()),
    );
    for d in [Direction::Ascending, Direction::Descending] {
        v.extend(m.border_values(d).iter().map(|x| x.to_f64().to_bits()));
    }
    v.push(m.mu0().to_f64().to_bits());
    v
}

/// Outcome of a solve as comparable bits.
pub fn outcome_bits<T: Real, const MM: usize>(
    r: &Result<Model<T, MM>, Error>,
) -> Result<Vec<u64>, Error> {
    r.as_ref().map(model_bits).map_err(|e| *e)
}

/// Offset just past the settings section of a checkpoint (magic 4, version 2, scalar size 1,
/// fingerprint 4, then the settings), or `None` if the bytes do not hold one.
pub fn settings_end(bytes: &[u8], scalar: usize) -> Option<usize> {
    let mut pos = 11 + 1 + 2 + 2;
    for _ in 0..2 {
        let len = u16::from_le_bytes([*bytes.get(pos)?, *bytes.get(pos + 1)?]) as usize;
        pos += 2 + len * scalar;
    }
    pos += 1 + 4 + 4 + scalar + 2 + 1 + scalar;
    (pos <= bytes.len()).then_some(pos)
}

/// Recomputes the settings fingerprint and the final CRC, as a writer would.
pub fn fix_checksums(bytes: &mut [u8], scalar: usize) {
    if let Some(end) = settings_end(bytes, scalar) {
        let fp = hsid::crc32(&bytes[11..end]);
        bytes[7..11].copy_from_slice(&fp.to_le_bytes());
    }
    if bytes.len() >= 4 {
        let n = bytes.len() - 4;
        let crc = hsid::crc32(&bytes[..n]);
        bytes[n..].copy_from_slice(&crc.to_le_bytes());
    }
}

/// The documented rule of `Error::TooFewInstruments`: the instruments have `p·m` rows, plus `p`
/// rows of past outputs for every weighting but PI-MOESP, and need at least `f`.
pub fn enough_instruments<T: Real, const MM: usize>(s: &Settings<T, MM>) -> bool {
    let m = s.knots.channels();
    let rows = s.p * m + if s.method == Method::PiMoesp { 0 } else { s.p };
    rows >= s.f
}
