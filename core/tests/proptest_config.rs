//! Property tests over random configurations: knot vectors (valid and invalid: unsorted,
//! duplicated, outside the interval, non-finite, mismatched ends, too few, too many), the three
//! constructors (`Knots::new`, `Knots::shared`, `Knots::uniform`), horizons, orders, hold
//! settings, μ0 modes and bases, in `f32` and `f64`.
//!
//! Properties: configuration never panics; it succeeds exactly when the configuration is valid
//! (an oracle written here from the documented rules), and every error is the right variant
//! with a claim that is true of the input (right path, index, counts) and a message. A valid
//! configuration then takes a short Table I record: `push` never panics and `solve` returns a
//! finite model with `G(1) = 1` or a typed error whose claim is checked; a workspace smaller
//! than [`Identifier::min_workspace_len`] is refused and any larger one gives the same model
//! bit for bit.
//!
//! Cases: 2 × 5,000 (seeded, see `proptest_common::config`).
#![allow(clippy::unwrap_used, clippy::expect_used)]

use crate::proptest_common;

use hsid::{
    Basis, Direction, Error, Forgetting, KnotEnd, Knots, Method, MuZero, Order, Real, Settings,
};
use proptest::prelude::*;
use proptest_common::{
    Id, K, Lti, M, Tally, check_model, check_solve_error, enough_instruments, outcome_bits, plant,
    run_cases,
};

/// Cases per scalar type.
const CASES: u32 = 5_000;

/// How the knots are built.
#[derive(Clone, Debug)]
enum KnotSpec {
    New(Vec<f64>, Vec<f64>),
    Shared(Vec<f64>),
    Uniform(f64, f64, usize, usize),
}

/// Strategy for an interval `[lo, hi]`: mostly ordinary, sometimes extreme (tiny, huge,
/// far from zero), sometimes empty, reversed or non-finite.
fn interval() -> impl Strategy<Value = (f64, f64)> {
    let lo = prop_oneof![
        Just(-3.0),
        Just(0.0),
        Just(1e-3),
        -1e3f64..1e3,
        Just(-1e30),
        Just(-1e38),
    ];
    let width = prop_oneof![
        12 => Just(6.0),
        12 => 1e-2f64..1e2,
        1 => Just(1e-6),
        1 => Just(1e-30),
        1 => Just(2e30),
        1 => Just(0.0),
        1 => Just(-1.0),
        1 => Just(f64::NAN),
        1 => Just(f64::INFINITY),
    ];
    (lo, width).prop_map(|(lo, w)| (lo, lo + w))
}

/// A knot vector on `[lo, hi]` with `segments` segments (`lo` first, `hi` last), then, one
/// time in five, one of the mutations that make it invalid.
fn mutated(lo: f64, hi: f64, segments: usize) -> impl Strategy<Value = Vec<f64>> {
    (
        proptest::collection::vec(0.0f64..1.0, M + 1),
        prop_oneof![8 => Just(0u8), 2 => 1u8..8],
        any::<prop::sample::Index>(),
    )
        .prop_map(move |(mut cuts, mutation, at)| {
            cuts.truncate(segments.saturating_sub(1));
            cuts.sort_by(f64::total_cmp);
            let mut k = vec![lo];
            k.extend(cuts.iter().map(|c| lo + (hi - lo) * c));
            if segments > 0 {
                k.push(hi);
            }
            let n = k.len();
            let i = if n > 0 { at.index(n) } else { 0 };
            match mutation {
                1 if n >= 2 => k.swap(i.max(1) - 1, i.max(1)),
                2 if n >= 2 => k[i.max(1)] = k[i.max(1) - 1],
                3 if n >= 1 => k[i] = hi + (hi - lo).abs() + 1.0,
                4 if n >= 1 => k[i] = f64::NAN,
                5 if n >= 1 => {
                    k[i] = if i == 0 {
                        f64::NEG_INFINITY
                    } else {
                        f64::INFINITY
                    }
                }
                6 if n >= 2 => k[0] = lo + 0.25 * (hi - lo),
                7 if n >= 2 => {
                    let last = n - 1;
                    k[last] = hi - 0.25 * (hi - lo);
                }
                _ => {}
            }
            k
        })
}

/// Segment counts per path: mostly 1–3 each, sometimes 0 or more than the capacity allows.
fn segment_counts() -> impl Strategy<Value = (usize, usize)> {
    prop_oneof![
        8 => (1usize..=3, 1usize..=3),
        1 => (0usize..=M + 1, 0usize..=M + 1),
    ]
}

fn knot_spec() -> impl Strategy<Value = KnotSpec> {
    (interval(), segment_counts()).prop_flat_map(|((lo, hi), (na, nd))| {
        prop_oneof![
            5 => (mutated(lo, hi, na), mutated(lo, hi, nd)).prop_map(|(a, d)| KnotSpec::New(a, d)),
            1 => mutated(lo, hi, na + nd / 2).prop_map(KnotSpec::Shared),
            2 => Just(KnotSpec::Uniform(lo, hi, na, nd)),
        ]
    })
}

fn to_t<T: Real>(v: &[f64]) -> Vec<T> {
    v.iter().map(|&x| T::of(x)).collect()
}

/// Index of the first knot that is not finite or not above its predecessor (≥ 1), if any.
fn first_bad<T: Real>(k: &[T]) -> Option<usize> {
    k.windows(2)
        .position(|w| !(w[0].finite() && w[1].finite() && w[1] > w[0]))
        .map(|i| i + 1)
}

/// The knots `Knots::uniform` documents: `u_min + (u_max − u_min)·i/n`, the last `u_max`.
fn uniform_knots<T: Real>(lo: T, hi: T, n: usize) -> Vec<T> {
    (0..=n)
        .map(|i| {
            if i == n {
                hi
            } else {
                lo + (hi - lo) * T::of_usize(i) / T::of_usize(n.max(1))
            }
        })
        .collect()
}

/// The ascending and descending knot vectors a spec asks for, in `T`.
fn requested<T: Real>(spec: &KnotSpec) -> (Vec<T>, Vec<T>) {
    match spec {
        KnotSpec::New(a, d) => (to_t(a), to_t(d)),
        KnotSpec::Shared(k) => (to_t(k), to_t(k)),
        KnotSpec::Uniform(lo, hi, na, nd) => {
            let (lo, hi) = (T::of(*lo), T::of(*hi));
            (uniform_knots(lo, hi, *na), uniform_knots(lo, hi, *nd))
        }
    }
}

/// The oracle: is the knot configuration valid (from the documented rules)?
fn knots_valid<T: Real>(spec: &KnotSpec) -> bool {
    let (a, d) = requested::<T>(spec);
    let paths_ok =
        a.len() >= 2 && d.len() >= 2 && first_bad(&a).is_none() && first_bad(&d).is_none();
    match spec {
        KnotSpec::New(..) => {
            paths_ok
                && a[0] == d[0]
                && a[a.len() - 1] == d[d.len() - 1]
                && a.len() + d.len() - 2 <= M
        }
        // n + 1 knots are stored in the capacity M.
        KnotSpec::Shared(_) => paths_ok && a.len() <= M,
        KnotSpec::Uniform(lo, hi, na, nd) => {
            let (lo, hi) = (T::of(*lo), T::of(*hi));
            lo.finite()
                && hi.finite()
                && lo < hi
                && *na >= 1
                && *nd >= 1
                && na + nd <= M
                && paths_ok
        }
    }
}

/// Is the error's claim true of the requested knots?
fn knots_claim_holds<T: Real>(spec: &KnotSpec, e: &Error) -> Result<(), TestCaseError> {
    let (a, d) = requested::<T>(spec);
    let path_of = |p: Direction| if p == Direction::Ascending { &a } else { &d };
    match (*e, spec) {
        (Error::InvalidInterval { u_min, u_max }, KnotSpec::Uniform(lo, hi, ..)) => {
            let (l, h) = (T::of(*lo), T::of(*hi));
            prop_assert!(!(l.finite() && h.finite() && l < h));
            prop_assert!(
                u_min.to_bits() == l.to_f64().to_bits() || (u_min.is_nan() && l.to_f64().is_nan())
            );
            prop_assert!(
                u_max.to_bits() == h.to_f64().to_bits() || (u_max.is_nan() && h.to_f64().is_nan())
            );
        }
        (
            Error::SegmentCount {
                expected,
                ascending,
                descending,
            },
            KnotSpec::New(..),
        ) => {
            prop_assert_eq!(expected, M);
            prop_assert_eq!(
                (ascending, descending),
                (a.len().saturating_sub(1), d.len().saturating_sub(1)),
                "{}",
                e
            );
            prop_assert!(ascending + descending > M, "{}", e);
        }
        (
            Error::SegmentCount {
                expected,
                ascending,
                descending,
            },
            KnotSpec::Shared(k),
        ) => {
            prop_assert_eq!(expected, M - 1);
            prop_assert_eq!((ascending, descending), (k.len().saturating_sub(1), 0));
            prop_assert!(ascending >= M);
        }
        (
            Error::SegmentCount {
                expected,
                ascending,
                descending,
            },
            KnotSpec::Uniform(_, _, na, nd),
        ) => {
            prop_assert_eq!(expected, M);
            prop_assert_eq!((ascending, descending), (*na, *nd), "{}", e);
            prop_assert!(na + nd > M);
        }
        (Error::TooFewKnots { path, count }, _) => {
            prop_assert_eq!(path_of(path).len(), count, "{}", e);
            prop_assert!(count < 2);
        }
        (Error::KnotsNotIncreasing { path, index }, _) => {
            prop_assert_eq!(first_bad(path_of(path)), Some(index), "{}", e);
        }
        (
            Error::KnotEndpoints {
                end,
                ascending,
                descending,
            },
            KnotSpec::New(..),
        ) => {
            // The first differing end is named, with both paths' knots there.
            let (ea, ed) = if a[0] != d[0] {
                prop_assert_eq!(end, KnotEnd::First);
                (a[0], d[0])
            } else {
                prop_assert_eq!(end, KnotEnd::Last);
                (a[a.len() - 1], d[d.len() - 1])
            };
            prop_assert!(ea != ed);
            prop_assert_eq!(ascending, ea.to_f64());
            prop_assert_eq!(descending, ed.to_f64());
            prop_assert!(
                e.to_string().contains(&format!("ascending {ascending}")),
                "{}",
                e
            );
        }
        (other, _) => prop_assert!(false, "unexpected error {other:?} ({other}) for {spec:?}"),
    }
    prop_assert!(!e.to_string().is_empty());
    Ok(())
}

fn build<T: Real>(spec: &KnotSpec) -> Result<Knots<T, M>, Error> {
    match spec {
        KnotSpec::New(a, d) => Knots::new(&to_t::<T>(a), &to_t::<T>(d)),
        KnotSpec::Shared(k) => Knots::shared(&to_t::<T>(k)),
        KnotSpec::Uniform(lo, hi, na, nd) => Knots::uniform(T::of(*lo), T::of(*hi), *na, *nd),
    }
}

/// Everything else in the settings, generated independently of the knots.
#[derive(Clone, Debug)]
struct Rest {
    f: usize,
    p: usize,
    order: Option<usize>,
    /// Mode (hold, known, estimate), hold length, settle as a fraction of it, known value.
    mu0: (u8, usize, f64, f64),
    ramp: bool,
    method: u8,
    lambda: Option<f64>,
    samples: usize,
    seed: u64,
    plant: Lti,
    workspace: i64,
}

fn rest() -> impl Strategy<Value = Rest> {
    // Mostly valid horizons (2 <= f, 1 <= p, f + p <= K), sometimes anything.
    let horizons = prop_oneof![
        6 => (2usize..=5).prop_flat_map(|f| (Just(f), 1..=K - f)),
        1 => (0usize..=18, 0usize..=K + 1),
    ];
    (
        horizons,
        prop_oneof![6 => Just(None), 3 => (1usize..=4).prop_map(Some), 1 => (0usize..=10).prop_map(Some)],
        (
            prop_oneof![Just(0u8), Just(1u8), Just(2u8)],
            1usize..40,
            prop_oneof![8 => 0.0f64..1.0, 1 => 1.0f64..1.5],
            prop_oneof![8 => -2.0f64..2.0, 1 => Just(f64::NAN), 1 => Just(f64::INFINITY)],
        ),
        (any::<bool>(), 0u8..4),
        prop_oneof![
            6 => Just(None),
            3 => (0.9f64..1.0).prop_map(Some),
            1 => Just(Some(1.0)),
            1 => prop_oneof![Just(0.0), Just(-0.5), Just(1.0 + 1e-6), Just(f64::NAN)].prop_map(Some),
        ],
        prop_oneof![0usize..40, 40usize..400],
        any::<u64>(),
        plant(),
        prop_oneof![4 => Just(0i64), 1 => -3i64..200],
    )
        .prop_map(
            |((f, p), order, mu0, (ramp, method), lambda, samples, seed, plant, workspace)| Rest {
                f,
                p,
                order,
                mu0,
                ramp,
                method,
                lambda,
                samples,
                seed,
                plant,
                workspace,
            },
        )
}

fn method_of(r: &Rest) -> Method {
    match r.method {
        0 => Method::PiMoesp,
        1 => Method::PoMoesp,
        2 => Method::N4sid,
        _ => Method::Cva,
    }
}

fn mu0_of<T: Real>(r: &Rest) -> MuZero<T> {
    match r.mu0.0 {
        0 => MuZero::Hold {
            len: r.mu0.1,
            settle: (r.mu0.1 as f64 * r.mu0.2) as usize,
        },
        1 => MuZero::Known(T::of(r.mu0.3)),
        _ => MuZero::Estimate,
    }
}

/// The oracle for `Identifier::new` with valid knots.
fn settings_claim_holds<T: Real>(s: &Settings<T, M>, e: &Error) -> Result<(), TestCaseError> {
    let (f, p) = (s.f, s.p);
    match *e {
        Error::InvalidHorizon {
            f: ef,
            k,
            max_f,
            max_k,
        } => {
            prop_assert_eq!((ef, k), (f, f + p));
            prop_assert_eq!((max_f, max_k), (hsid::DEFAULT_HORIZON, K));
            prop_assert!(f < 2 || p == 0 || f > hsid::DEFAULT_HORIZON || f + p > K);
        }
        Error::InvalidOrder { order, f: ef } => {
            prop_assert_eq!(s.order, Order::Fixed(order));
            prop_assert_eq!(ef, f);
            prop_assert!(order == 0 || order >= f);
        }
        Error::TooFewInstruments {
            f: ef,
            p: ep,
            channels,
            past_outputs,
        } => {
            prop_assert_eq!((ef, ep), (f, p));
            prop_assert_eq!(channels, s.knots.channels());
            prop_assert_eq!(past_outputs, s.method != Method::PiMoesp);
            prop_assert!(!enough_instruments(s));
            let msg = e.to_string();
            let says = msg.contains(&format!("f = {f}")) && msg.contains("raise p");
            prop_assert!(says, "{}", msg);
        }
        Error::HoldTooShort { len, settle } => {
            prop_assert_eq!(s.mu0, MuZero::Hold { len, settle });
            prop_assert!(settle >= len);
        }
        Error::InvalidForgetting { lambda } => {
            let Forgetting::Exponential { lambda: l } = s.forgetting else {
                return Err(TestCaseError::fail(format!("{e} without forgetting")));
            };
            prop_assert!(
                lambda.to_bits() == l.to_f64().to_bits() || (lambda.is_nan() && !l.finite())
            );
            prop_assert!(!(l > T::zero() && l <= T::one() && l.finite()));
        }
        // A non-finite known μ0, named with its value.
        Error::InvalidMu0 { value } => {
            let MuZero::Known(v) = s.mu0 else {
                return Err(TestCaseError::fail(format!("InvalidMu0 for {:?}", s.mu0)));
            };
            prop_assert!(!v.finite());
            prop_assert!(
                value.to_bits() == v.to_f64().to_bits() || (value.is_nan() && v.to_f64().is_nan())
            );
        }
        other => prop_assert!(false, "unexpected error {other:?} ({other}) for {s:?}"),
    }
    Ok(())
}

fn settings_valid<T: Real>(s: &Settings<T, M>) -> bool {
    let (f, p) = (s.f, s.p);
    let horizon = (2..=hsid::DEFAULT_HORIZON).contains(&f) && p >= 1 && f + p <= K;
    let order = match s.order {
        Order::Fixed(n) => n >= 1 && n < f,
        Order::Auto => true,
    };
    let mu0 = match s.mu0 {
        MuZero::Hold { len, settle } => settle < len,
        MuZero::Known(v) => v.finite(),
        MuZero::Estimate => true,
    };
    let forgetting = match s.forgetting {
        Forgetting::None => true,
        Forgetting::Exponential { lambda } => {
            lambda > T::zero() && lambda <= T::one() && lambda.finite()
        }
    };
    horizon && order && enough_instruments(s) && mu0 && forgetting
}

fn property<T: Real>(spec: KnotSpec, r: Rest, tally: &Tally) -> Result<(), TestCaseError> {
    // 1. Knots.
    let knots = build::<T>(&spec);
    tally.count(if knots.is_ok() {
        "knots accepted"
    } else {
        "knots refused"
    });
    match &knots {
        Ok(_) => prop_assert!(knots_valid::<T>(&spec), "accepted invalid knots {spec:?}"),
        Err(e) => {
            knots_claim_holds::<T>(&spec, e)?;
            prop_assert!(
                !knots_valid::<T>(&spec),
                "refused valid knots {spec:?}: {e}"
            );
        }
    }
    let Ok(knots) = knots else { return Ok(()) };

    // 2. Settings.
    let mut s = Settings::new(knots.clone(), r.f, r.p, mu0_of::<T>(&r));
    s.basis = if r.ramp { Basis::Ramp } else { Basis::Hat };
    s.order = r.order.map_or(Order::Auto, Order::Fixed);
    s.method = method_of(&r);
    if let Some(l) = r.lambda {
        s.forgetting = Forgetting::Exponential { lambda: T::of(l) };
    }
    let id = Id::<T>::new(s.clone());
    match &id {
        Ok(_) => prop_assert!(settings_valid(&s), "accepted invalid settings {s:?}"),
        Err(e) => {
            settings_claim_holds(&s, e)?;
            prop_assert!(!settings_valid(&s), "refused valid settings {s:?}: {e}");
        }
    }
    tally.count(if id.is_ok() {
        "settings accepted"
    } else {
        "settings refused"
    });
    let Ok(mut id) = id else { return Ok(()) };

    // 3. A short Table I record through a hysteresis (x² up, √x down, on the normalised
    // input) and the plant; the hold (if any) comes first.
    let (lo, hi) = (knots.u_min().to_f64(), knots.u_max().to_f64());
    let mut plant = r.plant.clone();
    let mut up = false;
    let mut prev = lo;
    let hold = s.mu0.hold_len();
    let data: Vec<(T, T)> = hsid::Excitation::<T, _>::new(
        knots.u_min(),
        knots.u_max(),
        hold,
        <rand_pcg::Pcg32 as rand_core::SeedableRng>::seed_from_u64(r.seed),
    )
    .unwrap()
    .take(hold + r.samples)
    .map(|u| {
        let uf = u.to_f64();
        if uf > prev {
            up = true;
        } else if uf < prev {
            up = false;
        }
        prev = uf;
        let x = ((uf - lo) / (hi - lo)).clamp(0.0, 1.0);
        let w = if up { x * x } else { x.sqrt() };
        (u, T::of(plant.step(w)))
    })
    .collect();
    for &(u, y) in &data {
        id.push(u, y);
    }
    prop_assert_eq!(id.fault(), None);
    prop_assert_eq!(id.samples(), data.len() as u64);

    // 4. Solve with the recommended workspace; then with another size.
    let mut ws = vec![T::zero(); id.workspace_len()];
    let out = id.solve(&mut ws);
    tally.count(match &out {
        Ok(_) => "solve Ok".to_string(),
        Err(e) => format!("solve Err {}", variant(e)),
    });
    match &out {
        Ok(m) => check_model(m, s.f)?,
        Err(e) => check_solve_error(e, &id, &data)?,
    }
    if r.workspace != 0 {
        let len = (id.min_workspace_len() as i64 + r.workspace - 2).max(0) as usize;
        let mut ws2 = vec![T::zero(); len];
        let other = id.solve(&mut ws2);
        if len < id.min_workspace_len() {
            prop_assert_eq!(
                other.err(),
                Some(Error::WorkspaceTooSmall {
                    need: id.min_workspace_len(),
                    have: len
                })
            );
        } else {
            prop_assert_eq!(outcome_bits(&other), outcome_bits(&out));
        }
    }
    Ok(())
}

/// The variant name of an error (for the tallies).
fn variant(e: &Error) -> String {
    let d = format!("{e:?}");
    d.split([' ', '(', '{']).next().unwrap_or("").to_string()
}

fn suite<T: Real>(seed: u64, name: &str) {
    let tally = Tally::default();
    run_cases(CASES, seed, (knot_spec(), rest()), |(spec, r)| {
        property::<T>(spec, r, &tally)
    });
    tally.print(name);
    // Not vacuous: many configurations reach the solve, and many of those succeed.
    assert!(tally.get("settings accepted") >= CASES as usize / 10);
    assert!(tally.get("solve Ok") >= CASES as usize / 20);
}

#[test]
fn random_configurations_f64() {
    suite::<f64>(0x4853_4944_0001, "random configurations, f64");
}

#[test]
fn random_configurations_f32() {
    suite::<f32>(0x4853_4944_0002, "random configurations, f32");
}
