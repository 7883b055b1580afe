//! Property tests over random and adversarial data on valid configurations, in `f32` and
//! `f64`: records from a Hammerstein plant perturbed by constants, spikes, scales from 1e-30
//! to 1e30, NaN/inf bursts in `u` or `y`, inputs outside the interval (by one ulp or far),
//! inputs exactly at knots, repeated samples, a broken hold, and very short runs.
//!
//! Properties: `push` never panics; the first bad sample is reported by `fault()` from the
//! moment it is pushed, with the right variant, index, signal and value (an oracle written
//! here), and the fault is sticky (later samples, good or bad, change nothing); `solve` returns
//! that fault, or, without a fault, either a finite model with `G(1) = 1` or a typed error
//! whose claim is checked; solving twice gives the same bits.
//!
//! Cases: 2 × 4,000 (seeded, see `proptest_common::config`).
#![allow(clippy::unwrap_used, clippy::expect_used)]

use crate::proptest_common;

use hsid::{Basis, Error, Forgetting, Knots, Method, MuZero, Order, Real, Settings, Signal};
use proptest::prelude::*;
use proptest_common::{
    Id, K, Lti, M, PwlSwitch, Tally, check_model, check_solve_error, enough_instruments,
    knot_vector, outcome_bits, plant, run_cases,
};

/// Cases per scalar type.
const CASES: u32 = 4_000;

/// A valid configuration.
#[derive(Clone, Debug)]
#[allow(dead_code)] // kept for the failure report (Debug)
struct Config {
    lo: f64,
    width: f64,
    asc: Vec<f64>,
    desc: Vec<f64>,
    f: usize,
    p: usize,
    order: Option<usize>,
    ramp: bool,
    method: u8,
    lambda: Option<f64>,
    mu0: (u8, usize, usize, f64),
    /// Border values at the knots (before μ0 is added), per path.
    values: (Vec<f64>, Vec<f64>),
    plant: Lti,
}

fn valid_config() -> impl Strategy<Value = Config> {
    let interval = prop_oneof![
        4 => Just((-3.0, 6.0)),
        2 => (-100.0f64..100.0, 0.1f64..100.0),
        1 => Just((1e6, 1.0)),
        1 => Just((-1e20, 2e20)),
    ];
    (interval, 1usize..=3, 1usize..=3)
        .prop_flat_map(|((lo, width), na, nd)| {
            let hi = lo + width;
            (
                Just((lo, width)),
                knot_vector(lo, hi, na, 0.1),
                knot_vector(lo, hi, nd, 0.1),
                (2usize..=4).prop_flat_map(|f| (Just(f), 1..=K - f)),
                prop_oneof![3 => Just(None), 1 => Just(Some(1))],
                (any::<bool>(), 0u8..4),
                prop_oneof![5 => Just(None), 1 => (0.95f64..1.0).prop_map(Some)],
                (0u8..3, 8usize..30, -2.0f64..2.0),
                (
                    proptest::collection::vec(-1.0f64..1.0, na),
                    proptest::collection::vec(-1.0f64..1.0, nd),
                ),
                plant(),
            )
        })
        .prop_map(
            |(
                (lo, width),
                asc,
                desc,
                (f, p),
                order,
                (ramp, method),
                lambda,
                (mode, len, v),
                values,
                plant,
            )| {
                Config {
                    lo,
                    width,
                    asc,
                    desc,
                    f,
                    p,
                    order,
                    ramp,
                    method,
                    lambda,
                    mu0: (mode, len, len / 2, v),
                    values,
                    plant,
                }
            },
        )
}

impl Config {
    fn settings<T: Real>(&self) -> Option<Settings<T, M>> {
        let a: Vec<T> = self.asc.iter().map(|&v| T::of(v)).collect();
        let d: Vec<T> = self.desc.iter().map(|&v| T::of(v)).collect();
        // In f32 knots of a narrow interval far from zero may round together: not this test.
        let knots = Knots::<T, M>::new(&a, &d).ok()?;
        let mu0 = match self.mu0.0 {
            0 => MuZero::Hold {
                len: self.mu0.1,
                settle: self.mu0.2,
            },
            1 => MuZero::Known(T::of(self.mu0.3)),
            _ => MuZero::Estimate,
        };
        let mut s = Settings::new(knots, self.f, self.p, mu0);
        s.basis = if self.ramp { Basis::Ramp } else { Basis::Hat };
        s.order = self.order.map_or(Order::Auto, Order::Fixed);
        s.method =
            [Method::PiMoesp, Method::PoMoesp, Method::N4sid, Method::Cva][self.method as usize];
        if let Some(l) = self.lambda {
            s.forgetting = Forgetting::Exponential { lambda: T::of(l) };
        }
        Some(s)
    }

    fn hold(&self) -> usize {
        if self.mu0.0 == 0 { self.mu0.1 } else { 0 }
    }
}

/// One perturbation of the record.
#[derive(Clone, Debug)]
enum Op {
    /// Multiply `y` by `10^e` from `at` on.
    Scale { at: usize, e: i32 },
    /// `u` constant over `[at, at + len)`.
    ConstU { at: usize, len: usize, which: u8 },
    /// `y` constant over `[at, at + len)`.
    ConstY { at: usize, len: usize, v: f64 },
    /// `y(at) = v`.
    Spike { at: usize, v: f64 },
    /// NaN or ±inf in `u` or `y` over `[at, at + len)`.
    NonFinite {
        at: usize,
        len: usize,
        input: bool,
        kind: u8,
    },
    /// `u(at)` just or far outside the interval.
    Outside { at: usize, above: bool, far: bool },
    /// `u(at)` exactly at a knot.
    AtKnot { at: usize, knot: usize, asc: bool },
    /// Repeat sample `at` over `[at, at + len)`.
    Repeat { at: usize, len: usize },
    /// Keep only the first `len` samples.
    Truncate { len: usize },
}

fn op() -> impl Strategy<Value = Op> {
    let at = 0usize..700;
    prop_oneof![
        (
            at.clone(),
            prop_oneof![
                Just(-30),
                Just(-20),
                Just(-10),
                Just(10),
                Just(20),
                Just(30),
                Just(38)
            ]
        )
            .prop_map(|(at, e)| Op::Scale { at, e }),
        (at.clone(), 1usize..300, 0u8..4).prop_map(|(at, len, which)| Op::ConstU {
            at,
            len,
            which
        }),
        (
            at.clone(),
            1usize..300,
            prop_oneof![Just(0.0), Just(1e30), -5.0f64..5.0]
        )
            .prop_map(|(at, len, v)| Op::ConstY { at, len, v }),
        (
            at.clone(),
            prop_oneof![
                Just(1e6),
                Just(-1e30),
                Just(3e38),
                Just(1e200),
                Just(f64::MIN_POSITIVE)
            ]
        )
            .prop_map(|(at, v)| Op::Spike { at, v }),
        (at.clone(), 1usize..20, any::<bool>(), 0u8..3).prop_map(|(at, len, input, kind)| {
            Op::NonFinite {
                at,
                len,
                input,
                kind,
            }
        }),
        (at.clone(), any::<bool>(), any::<bool>()).prop_map(|(at, above, far)| Op::Outside {
            at,
            above,
            far
        }),
        (at.clone(), 0usize..4, any::<bool>()).prop_map(|(at, knot, asc)| Op::AtKnot {
            at,
            knot,
            asc
        }),
        (at.clone(), 1usize..100).prop_map(|(at, len)| Op::Repeat { at, len }),
        prop_oneof![0usize..10, 10usize..120].prop_map(|len| Op::Truncate { len }),
    ]
}

/// The next representable value of `x` towards `+∞` (`up`) or `−∞`, in `T`.
fn next<T: Real>(x: T, up: bool) -> T {
    // Through the bit pattern: both types are IEEE binary formats.
    let v = x.to_f64();
    if T::BYTES == 4 {
        let b = (v as f32).to_bits();
        let n = if (v >= 0.0) == up { b + 1 } else { b - 1 };
        T::of(
            f64::from(f32::from_bits(if v == 0.0 { 1 } else { n }))
                * if v == 0.0 && !up { -1.0 } else { 1.0 },
        )
    } else {
        let b = v.to_bits();
        let n = if (v >= 0.0) == up { b + 1 } else { b - 1 };
        T::of(
            f64::from_bits(if v == 0.0 { 1 } else { n }) * if v == 0.0 && !up { -1.0 } else { 1.0 },
        )
    }
}

/// The record: a Table I experiment through the switch and plant, then the perturbations.
fn record<T: Real>(c: &Config, s: &Settings<T, M>, n: usize, seed: u64, ops: &[Op]) -> Vec<(T, T)> {
    let (lo, hi) = (s.knots.u_min(), s.knots.u_max());
    let mu0 = 0.3;
    let values = |v: &[f64]| -> Vec<f64> {
        let mut out = vec![mu0];
        out.extend(v.iter().map(|x| mu0 + x));
        out
    };
    let mut switch = PwlSwitch::new(
        c.asc.clone(),
        values(&c.values.0),
        c.desc.clone(),
        values(&c.values.1),
    );
    let mut plant = c.plant.clone();
    let mut data = proptest_common::table1(&s.knots, c.hold(), n, seed, &mut switch, &mut plant);
    let len = data.len();
    for op in ops {
        match *op {
            Op::Scale { at, e } => {
                let k = T::of(10f64.powi(e));
                for d in data.iter_mut().skip(at) {
                    d.1 *= k;
                }
            }
            Op::ConstU { at, len: l, which } => {
                let v = match which {
                    0 => lo,
                    1 => hi,
                    2 => s.knots.path(hsid::Direction::Ascending)
                        [s.knots.segments(hsid::Direction::Ascending) / 2],
                    _ => (lo + hi) / T::of(2.0),
                };
                for d in data.iter_mut().skip(at).take(l) {
                    d.0 = v;
                }
            }
            Op::ConstY { at, len: l, v } => {
                for d in data.iter_mut().skip(at).take(l) {
                    d.1 = T::of(v);
                }
            }
            Op::Spike { at, v } => {
                if let Some(d) = data.get_mut(at) {
                    d.1 = T::of(v);
                }
            }
            Op::NonFinite {
                at,
                len: l,
                input,
                kind,
            } => {
                let v = T::of([f64::NAN, f64::INFINITY, f64::NEG_INFINITY][kind as usize]);
                for d in data.iter_mut().skip(at).take(l) {
                    if input {
                        d.0 = v;
                    } else {
                        d.1 = v;
                    }
                }
            }
            Op::Outside { at, above, far } => {
                if let Some(d) = data.get_mut(at) {
                    let w = hi - lo;
                    d.0 = match (above, far) {
                        (true, false) => next(hi, true),
                        (false, false) => next(lo, false),
                        (true, true) => hi + w,
                        (false, true) => lo - w,
                    };
                }
            }
            Op::AtKnot { at, knot, asc } => {
                let dir = if asc {
                    hsid::Direction::Ascending
                } else {
                    hsid::Direction::Descending
                };
                let k = s.knots.path(dir);
                if let Some(d) = data.get_mut(at) {
                    d.0 = k[knot % k.len()];
                }
            }
            Op::Repeat { at, len: l } => {
                if let Some(&first) = data.get(at) {
                    for d in data.iter_mut().skip(at).take(l) {
                        *d = first;
                    }
                }
            }
            Op::Truncate { len: l } => data.truncate(l.min(len)),
        }
    }
    data
}

/// Whether sample `i` is bad, from the documented rules: non-finite `u`, then non-finite
/// `y`, then `u` outside `[u_min, u_max]`, then a hold sample not at `u_min`.
fn fault_at<T: Real>(s: &Settings<T, M>, i: usize, u: T, y: T) -> Option<Error> {
    let (lo, hi) = (s.knots.u_min(), s.knots.u_max());
    let index = i as u64;
    if !u.finite() {
        Some(Error::NonFinite {
            index,
            signal: Signal::Input,
        })
    } else if !y.finite() {
        Some(Error::NonFinite {
            index,
            signal: Signal::Output,
        })
    } else if u < lo || u > hi {
        Some(Error::InputOutOfRange {
            index,
            value: u.to_f64(),
        })
    } else if i < s.mu0.hold_len() && u != lo {
        Some(Error::HoldNotAtMin {
            index,
            value: u.to_f64(),
        })
    } else {
        None
    }
}

/// The first bad sample of the record.
fn expected_fault<T: Real>(s: &Settings<T, M>, data: &[(T, T)]) -> Option<Error> {
    data.iter()
        .enumerate()
        .find_map(|(i, &(u, y))| fault_at(s, i, u, y))
}

fn property<T: Real>(
    c: Config,
    n: usize,
    seed: u64,
    ops: Vec<Op>,
    tally: &Tally,
) -> Result<(), TestCaseError> {
    let Some(s) = c.settings::<T>() else {
        tally.count("knots collapse in this precision");
        return Ok(());
    };
    if !enough_instruments(&s) {
        // Refused by `new` (`TooFewInstruments`; the oracle of `proptest_config.rs`).
        let refused = matches!(
            Id::<T>::new(s.clone()),
            Err(Error::TooFewInstruments { .. })
        );
        prop_assert!(refused, "not refused with TooFewInstruments");
        tally.count("settings refused: too few instruments");
        return Ok(());
    }
    let mut id = Id::<T>::new(s.clone())
        .map_err(|e| TestCaseError::fail(format!("valid settings refused: {e}")))?;
    let data = record(&c, &s, c.hold() + n, seed, &ops);
    // The fault appears at the first bad sample and never changes.
    let mut seen: Option<Error> = None;
    for (i, &(u, y)) in data.iter().enumerate() {
        id.push(u, y);
        let want = seen.or_else(|| fault_at(&s, i, u, y));
        prop_assert_eq!(
            id.fault(),
            want,
            "after sample {} (u = {:?}, y = {:?})",
            i,
            u,
            y
        );
        seen = want;
    }
    prop_assert_eq!(id.fault(), expected_fault(&s, &data));
    prop_assert_eq!(id.samples(), data.len() as u64);
    let mut ws = vec![T::zero(); id.workspace_len()];
    let out = id.solve(&mut ws);
    match (&out, id.fault()) {
        (_, Some(fault)) => {
            tally.count(format!("fault {}", variant(&fault)));
            prop_assert_eq!(out.as_ref().err(), Some(&fault));
            // Sticky: more samples, good or bad, change nothing.
            id.push(s.knots.u_min(), T::zero());
            id.push(T::of(f64::NAN), T::of(f64::NAN));
            prop_assert_eq!(id.fault(), Some(fault));
            prop_assert_eq!(id.samples(), data.len() as u64 + 2);
        }
        (Ok(m), None) => {
            tally.count("solve Ok");
            check_model(m, s.f)?;
        }
        (Err(e), None) => {
            tally.count(format!("solve Err {}", variant(e)));
            check_solve_error(e, &id, &data)?;
        }
    }
    // Solving is repeatable, bit for bit.
    prop_assert_eq!(outcome_bits(&id.solve(&mut ws)), outcome_bits(&out));
    Ok(())
}

fn variant(e: &Error) -> String {
    let d = format!("{e:?}");
    d.split([' ', '(', '{']).next().unwrap_or("").to_string()
}

fn strategy() -> impl Strategy<Value = (Config, usize, u64, Vec<Op>)> {
    (
        valid_config(),
        prop_oneof![1 => 0usize..60, 4 => 60usize..600],
        any::<u64>(),
        prop_oneof![2 => Just(vec![]), 5 => proptest::collection::vec(op(), 1..4)],
    )
}

fn suite<T: Real>(seed: u64, name: &str) {
    let tally = Tally::default();
    run_cases(CASES, seed, strategy(), |(c, n, s, ops)| {
        property::<T>(c, n, s, ops, &tally)
    });
    tally.print(name);
    assert!(
        tally.get("solve Ok") >= CASES as usize / 5,
        "too few successful solves"
    );
}

#[test]
fn adversarial_data_f64() {
    suite::<f64>(0x4853_4944_0011, "adversarial data, f64");
}

#[test]
fn adversarial_data_f32() {
    suite::<f32>(0x4853_4944_0012, "adversarial data, f32");
}
