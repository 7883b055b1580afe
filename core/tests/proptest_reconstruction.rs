//! Reconstruction properties: noise-free data from the exact model class — a switch whose
//! borders are piecewise linear on the identification knots (random knots, random border
//! values, hysteresis), followed by a random stable `G(q)` of order 1 or 2 with `G(1) = 1` —
//! recorded with the Table I excitation. Every weighting, both bases, μ0 from a hold or given,
//! automatic or fixed order, with and without light exponential forgetting, `f32` and `f64`.
//!
//! Properties: `solve` succeeds, finds the true order, and recovers the borders at the knots,
//! μ0, the poles (as the characteristic polynomial) and the Markov parameters `h_0 … h_9`, to
//! `1e-6` in `f64` and `2e-2` in `f32` (absolute; borders and `h_k` are of order 1).
//!
//! Cases: 2 × 1,000 (seeded, see `proptest_common::config`).
#![allow(clippy::unwrap_used, clippy::expect_used)]

use crate::proptest_common;

use hsid::{Basis, Direction, Forgetting, Knots, Method, MuZero, Order, Real, Settings};
use proptest::prelude::*;
use proptest_common::{
    Id, K, Lti, M, PwlSwitch, Tally, borders, check_model, enough_instruments, knot_vector,
    noisy_record, plant, run_cases,
};

/// Cases per scalar type.
const CASES: u32 = 1_000;

#[derive(Clone, Debug)]
struct Case {
    asc: Vec<f64>,
    desc: Vec<f64>,
    /// Border values at the knots after u_min (μ0 first is implied), per path.
    values: (Vec<f64>, Vec<f64>),
    mu0: f64,
    plant: Lti,
    f: usize,
    p: usize,
    ramp: bool,
    method: Method,
    hold: bool,
    auto: bool,
    lambda: Option<f64>,
    samples: usize,
    seed: u64,
    /// White noise added to `y` (standard deviation 1e-6 in `f64`, 1e-2 in `f32`: single
    /// precision does not resolve higher SNRs, see `proptest_regressions.rs`) or none.
    noisy: bool,
}

fn case() -> impl Strategy<Value = Case> {
    (1usize..=3, 1usize..=3, plant())
        .prop_flat_map(|(na, nd, plant)| {
            let n = plant.order();
            (
                knot_vector(-2.0, 4.0, na, 0.15),
                knot_vector(-2.0, 4.0, nd, 0.15),
                (
                    proptest::collection::vec(-1.0f64..1.0, na),
                    proptest::collection::vec(-1.0f64..1.0, nd),
                ),
                -1.0f64..1.0,
                Just(plant),
                (n + 1..=5).prop_flat_map(move |f| (Just(f), n.max(1)..=(K - f).max(n))),
                (
                    any::<bool>(),
                    prop_oneof![
                        Just(Method::PiMoesp),
                        Just(Method::PoMoesp),
                        Just(Method::N4sid),
                        Just(Method::Cva)
                    ],
                ),
                (any::<bool>(), any::<bool>()),
                prop_oneof![3 => Just(None), 1 => (0.995f64..1.0).prop_map(Some)],
                800usize..2000,
                any::<u64>(),
                prop_oneof![3 => Just(true), 1 => Just(false)],
            )
        })
        .prop_map(
            |(
                asc,
                desc,
                values,
                mu0,
                plant,
                (f, p),
                (ramp, method),
                (hold, auto),
                lambda,
                samples,
                seed,
                noisy,
            )| Case {
                asc,
                desc,
                values,
                mu0,
                plant,
                f,
                p,
                ramp,
                method,
                hold,
                lambda,
                samples,
                seed,
                // Exactly noise-free data leave the noise-floor directions at rounding level,
                // which the automatic order may count as states (see proptest_regressions.rs).
                auto: auto && noisy,
                noisy,
            },
        )
}

/// The settings of a case in the scalar type `T` (knots given already rounded to `T`).
fn settings<T: Real>(c: &Case, a: &[f64], d: &[f64]) -> Settings<T, M> {
    let a: Vec<T> = a.iter().map(|&v| T::of(v)).collect();
    let d: Vec<T> = d.iter().map(|&v| T::of(v)).collect();
    let knots = Knots::<T, M>::new(&a, &d).unwrap();
    let mu0 = if c.hold {
        MuZero::Hold {
            len: 200,
            settle: 180,
        }
    } else {
        MuZero::Known(T::of(c.mu0))
    };
    let mut s = Settings::new(knots, c.f, c.p, mu0);
    s.basis = if c.ramp { Basis::Ramp } else { Basis::Hat };
    s.method = c.method;
    s.order = if c.auto {
        Order::Auto
    } else {
        Order::Fixed(c.plant.order())
    };
    if let Some(l) = c.lambda {
        s.forgetting = Forgetting::Exponential { lambda: T::of(l) };
    }
    s
}

fn solve<T: Real>(
    s: &Settings<T, M>,
    data: &[(f64, f64)],
) -> Result<hsid::Model<T, M>, hsid::Error> {
    let mut id = Id::<T>::new(s.clone())?;
    for &(u, y) in data {
        id.push(T::of(u), T::of(y));
    }
    let mut ws = vec![T::zero(); id.workspace_len()];
    id.solve(&mut ws)
}

/// Largest differences of `m` from `(μ0, borders, Markov parameters)`.
fn distance<T: Real>(
    m: &hsid::Model<T, M>,
    mu0: f64,
    ba: &[f64],
    bd: &[f64],
    h: &[f64],
) -> (f64, f64, f64) {
    let mut borders = 0.0f64;
    for (dir, truth) in [(Direction::Ascending, ba), (Direction::Descending, bd)] {
        for (&got, &want) in m.border_values(dir).iter().zip(truth) {
            borders = borders.max((got.to_f64() - want).abs());
        }
    }
    let markov = h
        .iter()
        .enumerate()
        .map(|(k, &hk)| (m.markov(k).to_f64() - hk).abs())
        .fold(0.0, f64::max);
    ((m.mu0().to_f64() - mu0).abs(), borders, markov)
}

fn property<T: Real>(c: Case, tally: &Tally) -> Result<(), TestCaseError> {
    let single = T::BYTES == 4;
    // Noise: none, or 1e-6 in f64 and 1e-2 in f32. Tolerances against the truth: in f64,
    // 1e-8 on noise-free data and 1e-4 with noise, on everything (poles, μ0, borders, Markov
    // parameters); in f32 the truth bounds μ0 and, without noise, the poles (1e-3), and the
    // f32 model must be within 1e-3 (5e-3 in the ramp basis) of the f64 model on the same
    // data, relative to the largest border or Markov parameter (1e-3 on the characteristic
    // polynomial). CVA may refuse noise-free data (and f32 data at 1e-2) with
    // `RankDeficient { CvaWeighting }`, never return a wrong model.
    let (noise, tol) = match (c.noisy, single) {
        (false, false) => (0.0, 1e-8),
        (false, true) => (0.0, 1e-3),
        (true, false) => (1e-6, 1e-4),
        (true, true) => (1e-2, 0.1),
    };
    // Knots as the identifier sees them (rounded to T).
    let ka: Vec<f64> = c.asc.iter().map(|&v| T::of(v).to_f64()).collect();
    let kd: Vec<f64> = c.desc.iter().map(|&v| T::of(v).to_f64()).collect();
    let s = settings::<T>(&c, &ka, &kd);
    if !enough_instruments(&s) {
        // Refused by `new` (`TooFewInstruments`; the oracle of `proptest_config.rs`).
        let refused = matches!(
            Id::<T>::new(s.clone()),
            Err(hsid::Error::TooFewInstruments { .. })
        );
        prop_assert!(refused, "not refused with TooFewInstruments");
        tally.count("settings refused: too few instruments");
        return Ok(());
    }
    let (ba, bd) = (borders(c.mu0, &c.values.0), borders(c.mu0, &c.values.1));
    let mut switch = PwlSwitch::new(ka.clone(), ba.clone(), kd.clone(), bd.clone());
    let mut plant = c.plant.clone();
    // Start at rest at μ0, as after a long hold.
    for _ in 0..400 {
        plant.step(c.mu0);
    }
    let hold = if c.hold { 200 } else { 0 };
    let data = noisy_record(
        &s.knots,
        hold,
        hold + c.samples,
        c.seed,
        noise,
        &mut switch,
        &mut plant,
    );
    let m = match solve(&s, &data) {
        Ok(m) => m,
        // An over-counted automatic order can make the B, D least squares rank deficient, or
        // add a spurious pole outside the unit circle: the same statistical false positive as
        // below, if the true order solves.
        Err(hsid::Error::RankDeficient { .. } | hsid::Error::UnstableModel { .. })
            if c.auto && {
                let mut fixed = s.clone();
                fixed.order = Order::Fixed(c.plant.order());
                solve(&fixed, &data).is_ok()
            } =>
        {
            tally.count("auto order");
            tally.count("auto order off the truth");
            return Ok(());
        }
        // CVA's weighting is the inverse square root of the residual Gram of Ȳ_f: without
        // noise it is singular, and in f32 at 1e-2 noise it can be singular to the rounding
        // of the sums (amplified by the conditioning of the instruments). A refusal, never a
        // wrong model; with 1e-6 noise in f64 it must not happen.
        Err(hsid::Error::RankDeficient {
            stage: hsid::Stage::CvaWeighting,
        }) if c.method == Method::Cva && (single || !c.noisy) => {
            tally.count("CVA refused: weighting singular to rounding");
            return Ok(());
        }
        Err(e) => {
            tally.count(format!("Err {e:?} {:?}", c.method));
            let f64_outcome = solve(&settings::<f64>(&c, &ka, &kd), &data).map(|m| m.order());
            return Err(TestCaseError::fail(format!(
                "exact-model-class data refused: {e} (f64 on the same data: {f64_outcome:?})"
            )));
        }
    };
    tally.count(format!("Ok {:?}", c.method));
    check_model(&m, c.f)?;
    let n = c.plant.order();
    if c.auto {
        tally.count("auto order");
        // The automatic order may, rarely, count a noise direction (a whitened value of pure
        // noise above the threshold: a statistical false positive, f64 alike) or, in f32 at
        // 1e-2 noise with forgetting (≈ 200 effective samples), miss a weak state. Such
        // cases are tallied and bounded in `suite`; in f64 at 1e-6 noise a miss is an error.
        if m.order() > n || (single && m.order() < n) {
            tally.count("auto order off the truth");
            return Ok(());
        }
    }
    prop_assert_eq!(
        m.order(),
        n,
        "order: sv {:?} whitened {:?}",
        m.singular_values(),
        m.whitened_singular_values()
    );
    if !(single && c.noisy) {
        check_poles(&m, &c.plant, tol)?;
    }
    let h = c.plant.markov(10);
    let (dmu, dborders, dmarkov) = distance(&m, c.mu0, &ba, &bd, &h);
    prop_assert!(dmu < tol, "mu0 {:?} vs {}", m.mu0(), c.mu0);
    if !single {
        prop_assert!(
            dborders < tol,
            "borders {:?} {:?} vs {ba:?} {bd:?}",
            m.border_values(Direction::Ascending),
            m.border_values(Direction::Descending)
        );
        prop_assert!(dmarkov < tol, "Markov parameters off by {dmarkov:e}");
    } else {
        // Numerics: the f32 model against the f64 model on the same data.
        let s64 = settings::<f64>(&c, &ka, &kd);
        if let Ok(m64) = solve(&s64, &data)
            && m64.order() == n
        {
            let h64: Vec<f64> = (0..10).map(|k| m64.markov(k)).collect();
            let ba64 = m64.border_values(Direction::Ascending).to_vec();
            let bd64 = m64.border_values(Direction::Descending).to_vec();
            let (dmu, db, dh) = distance(&m, m64.mu0(), &ba64, &bd64, &h64);
            let scale = h64
                .iter()
                .chain(&ba64)
                .chain(&bd64)
                .fold(1.0f64, |a, b| a.max(b.abs()));
            // The ramp coordinates are worse conditioned (README: f32 against f64 to 1e-3 in
            // the hat basis, 5e-3 in the ramp basis).
            let rel = if c.ramp { 5e-3 } else { 1e-3 };
            prop_assert!(
                dmu.max(db).max(dh) < rel * scale,
                "f32 vs f64: mu0 {dmu:e}, borders {db:e}, Markov {dh:e}"
            );
            let poly = |i: usize, j: usize| m64.a(i, j);
            let (tr, det) = if n == 1 {
                (poly(0, 0), 0.0)
            } else {
                (
                    poly(0, 0) + poly(1, 1),
                    poly(0, 0) * poly(1, 1) - poly(0, 1) * poly(1, 0),
                )
            };
            let mut as_plant = c.plant.clone();
            as_plant.a = [-tr, det];
            check_poles(&m, &as_plant, 1e-3)?;
            tally.count("f32 compared with f64");
        }
    }
    Ok(())
}

/// The characteristic polynomial `z² + a1 z + a2` (or `z + a1`) of `A` against the plant's.
fn check_poles<T: Real>(m: &hsid::Model<T, M>, plant: &Lti, tol: f64) -> Result<(), TestCaseError> {
    let am = |i, j| m.a(i, j).to_f64();
    if m.order() == 1 {
        prop_assert!(
            (am(0, 0) + plant.a[0]).abs() < tol,
            "pole {} vs {}",
            am(0, 0),
            -plant.a[0]
        );
    } else {
        let tr = am(0, 0) + am(1, 1);
        let det = am(0, 0) * am(1, 1) - am(0, 1) * am(1, 0);
        prop_assert!(
            (tr + plant.a[0]).abs() < tol && (det - plant.a[1]).abs() < tol,
            "trace {} det {} vs {:?}",
            tr,
            det,
            plant.a
        );
    }
    Ok(())
}

fn suite<T: Real>(seed: u64, name: &str) {
    let tally = Tally::default();
    run_cases(CASES, seed, case(), |c| property::<T>(c, &tally));
    tally.print(name);
    let (over, auto) = (
        tally.get("auto order off the truth"),
        tally.get("auto order"),
    );
    assert!(
        over * 50 <= auto,
        "the automatic order missed the truth in {over} of {auto} cases"
    );
}

#[test]
fn exact_model_class_is_recovered_f64() {
    suite::<f64>(0x4853_4944_0021, "reconstruction, f64");
}

#[test]
fn exact_model_class_is_recovered_f32() {
    suite::<f32>(0x4853_4944_0022, "reconstruction, f32");
}
