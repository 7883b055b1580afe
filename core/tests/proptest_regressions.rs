//! Minimal, deterministic cases of the contract violations the property tests found, one test
//! per defect, each stating the input, what used to happen and what happens now. They were
//! fixed; the properties cover their regions again (no region is skipped), and these tests keep
//! the fixes from regressing. `docs/reliability.md` lists them with the fixes.
#![allow(clippy::panic, clippy::unwrap_used, clippy::expect_used)]

use crate::proptest_common;

use std::panic::{AssertUnwindSafe, catch_unwind};

use hsid::{
    Basis, CheckpointError, Direction, Error, Excitation, Identifier, Knots, Method, MuZero, Order,
    Real, Settings,
};
use proptest_common::{
    Id, Lti, M, PwlSwitch, borders, fix_checksums, noisy_record, settings_end, table1,
};
use rand_core::SeedableRng;
use rand_pcg::Pcg32;

/// Runs `f`, turning a panic into a test failure that says so.
fn no_panic<R>(what: &str, f: impl FnOnce() -> R) -> R {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(r) => r,
        Err(p) => {
            let msg = p
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_default();
            panic!("{what} panicked: {msg}")
        }
    }
}

/// A Table I record on `[-3, 3]` through a smooth hysteresis and a first-order plant.
fn record(n: usize, seed: u64) -> Vec<(f64, f64)> {
    let mut plant = Lti::new(1, 0.5, 0.0, false, 0.0, 0.0);
    let (mut up, mut prev) = (false, -3.0);
    Excitation::<f64, _>::new(-3.0, 3.0, 1, Pcg32::seed_from_u64(seed))
        .unwrap()
        .take(n)
        .map(|u| {
            if u > prev {
                up = true;
            } else if u < prev {
                up = false;
            }
            prev = u;
            let x = (u + 3.0) / 6.0;
            (u, plant.step(if up { x * x } else { x.sqrt() }))
        })
        .collect()
}

fn solve<const MM: usize, const KK: usize>(
    id: &Identifier<f64, MM, KK>,
) -> Result<hsid::Model<f64, MM>, Error> {
    let mut ws = vec![0.0; id.workspace_len()];
    no_panic("solve", || id.solve(&mut ws))
}

/// `solve` indexed past the QR scratch when the instruments had fewer rows than `f`
/// (`p·m < f`; here m = 2, f = 3, p = 1): "index out of bounds" in `subspace.rs`. The settings
/// are now refused by `new` with `TooFewInstruments`, which names f, p and m and what to
/// change; with past outputs (every weighting but PI-MOESP) the instruments have `p·(m + 1)`
/// rows. Where the rule allows the settings, the same record solves without panicking.
#[test]
fn solve_with_fewer_instrument_rows_than_f_does_not_panic() {
    let knots = Knots::<f64, 6>::uniform(-3.0, 3.0, 1, 1).unwrap();
    let data = record(300, 1);
    for method in [Method::PiMoesp, Method::PoMoesp, Method::N4sid, Method::Cva] {
        for (f, p) in [(3, 1), (2, 1), (4, 1), (5, 2), (4, 2), (6, 2), (7, 1)] {
            let mut s = Settings::new(knots.clone(), f, p, MuZero::Known(0.0));
            s.method = method;
            let per = 2 + usize::from(method != Method::PiMoesp);
            match Identifier::<f64, 6, 8>::new(s) {
                Err(e) => {
                    assert!(p * per < f, "{method:?} f = {f}, p = {p}: refused: {e}");
                    assert_eq!(
                        e,
                        Error::TooFewInstruments {
                            f,
                            p,
                            channels: 2,
                            past_outputs: method != Method::PiMoesp
                        }
                    );
                    let msg = e.to_string();
                    let want = format!("raise p to at least {}", f.div_ceil(per));
                    assert!(
                        msg.contains(&format!("f = {f}")) && msg.contains(&want),
                        "{msg}"
                    );
                }
                Ok(mut id) => {
                    assert!(p * per >= f, "{method:?} f = {f}, p = {p} accepted");
                    for &(u, y) in &data {
                        id.push(u, y);
                    }
                    let _ = solve(&id);
                }
            }
        }
    }
}

/// With one channel (`Knots::shared(&[-3.0, 3.0])`) and `f = 2`, the rank-1 split's scratch
/// was `B_f` (`f²·m` = 4 scalars), shorter than the `(n+1)·m + m + n + 1` = 5 it needs:
/// "range end index 2 out of range for slice of length 1" in `estimation.rs`. The split now
/// has its own part of the scratch, sized by the formula the slicing uses. Here: it solves
/// (one channel, `f = 2` and other small sizes), and on noise-free data of the exact model
/// class (a linear static map, a first-order plant with pole 0.5) the pole is right.
#[test]
fn rank_one_split_with_one_channel_does_not_panic() {
    let k = [-3.0, 3.0];
    let knots = Knots::<f64, M>::shared(&k).unwrap();
    for (f, p) in [(2, 2), (2, 3), (3, 3), (2, 6)] {
        let mut s = Settings::new(knots.clone(), f, p, MuZero::Estimate);
        s.order = Order::Fixed(1);
        let mut id = Id::<f64>::new(s).unwrap();
        let mut sw = PwlSwitch::new(k.to_vec(), vec![0.3, 1.5], k.to_vec(), vec![0.3, 1.5]);
        let mut plant = Lti::new(1, 0.5, 0.0, false, 0.0, 0.0);
        for _ in 0..400 {
            plant.step(0.3);
        }
        for (u, y) in table1(&knots, 0, 600, 7, &mut sw, &mut plant) {
            id.push(u, y);
        }
        let m = solve(&id).unwrap_or_else(|e| panic!("f = {f}, p = {p}: {e}"));
        assert!(
            (m.a(0, 0) - 0.5).abs() < 1e-8,
            "f = {f}, p = {p}: A = {}",
            m.a(0, 0)
        );
    }
}

/// Regression: `Knots::uniform(-3, 3, 1, 6)` with capacity 6 used to truncate the descending
/// knots to the capacity and report mismatched end points (and (6, 6) `SegmentCount` with
/// 5 + 5 segments). It reports the segment counts asked for.
#[test]
fn uniform_knots_beyond_the_capacity_report_the_segment_count() {
    for (na, nd) in [(1, 6), (6, 1), (6, 6), (3, 4)] {
        assert_eq!(
            Knots::<f64, 6>::uniform(-3.0, 3.0, na, nd).err(),
            Some(Error::SegmentCount {
                expected: 6,
                ascending: na,
                descending: nd
            }),
            "uniform(-3, 3, {na}, {nd})"
        );
    }
}

/// Regression: `Knots::new` with a path of fewer than two knots and the other path longer
/// than the capacity used to report `SegmentCount` with wrong counts ("0 ascending + 0
/// descending segments exceed the capacity"). The short path is named: `TooFewKnots`.
#[test]
fn a_short_path_is_reported_as_too_few_knots() {
    let long = [-3.0, -2.0, -1.0, 0.0, 1.0, 2.0, 3.0];
    assert_eq!(
        Knots::<f64, 6>::new(&[-3.0], &long).err(),
        Some(Error::TooFewKnots {
            path: Direction::Ascending,
            count: 1
        })
    );
    assert_eq!(
        Knots::<f64, 6>::new(&long, &[]).err(),
        Some(Error::TooFewKnots {
            path: Direction::Descending,
            count: 0
        })
    );
}

/// Regression: ascending knots `[-3, 0, 2.5]` with descending `[-3, 0, 3]` used to be
/// reported as "descending knots run from -3 to 3", not naming the 2.5. The error names the
/// end that differs and both paths' knots there.
#[test]
fn mismatched_ends_name_the_mismatching_knot() {
    let e = Knots::<f64, 6>::new(&[-3.0, 0.0, 2.5], &[-3.0, 0.0, 3.0]).unwrap_err();
    assert!(matches!(e, Error::KnotEndpoints { .. }), "{e:?}");
    assert_eq!(
        e,
        Error::KnotEndpoints {
            end: hsid::KnotEnd::Last,
            ascending: 2.5,
            descending: 3.0
        }
    );
    let msg = e.to_string();
    assert!(
        msg.contains("2.5"),
        "the message should name the ascending end 2.5: {msg}"
    );
}

/// In `f32`, outputs of magnitude 1e20 (finite, accepted by `push`) overflow the lagged sums
/// (`y² > f32::MAX`); `solve` reported `NoConvergence { stage: Projection }` ("no convergence
/// within the iteration bound at the projection O_f"). It now checks the sums before any
/// factorisation and returns `Overflow { stage: Sums }`, whose message names the overflow and
/// says to scale `y` or use `f64`. The same data scaled to 1e15 (squares within range) solve,
/// and in `f64` the 1e20 record solves too, to the same pole as the unscaled one.
#[test]
fn overflowing_sums_are_reported_as_such() {
    let knots = Knots::<f32, 6>::uniform(-3.0, 3.0, 2, 2).unwrap();
    let run = |scale: f64| {
        let mut s = Settings::new(knots.clone(), 3, 3, MuZero::Known(0.0));
        s.order = Order::Fixed(1);
        let mut id = Identifier::<f32, 6, 8>::new(s).unwrap();
        for (u, y) in record(400, 3) {
            id.push(u as f32, (y * scale) as f32);
        }
        solve_f32(&id)
    };
    let e = run(1e20).unwrap_err();
    assert_eq!(
        e,
        Error::Overflow {
            stage: hsid::Stage::Sums
        }
    );
    let msg = e.to_string();
    assert!(
        msg.contains("overflow") && msg.contains("scale y") && msg.contains("f64"),
        "{msg}"
    );
    let small = run(1e15).unwrap();
    let knots64 = Knots::<f64, 6>::uniform(-3.0, 3.0, 2, 2).unwrap();
    let pole = |scale: f64| {
        let mut s = Settings::new(knots64.clone(), 3, 3, MuZero::Known(0.0));
        s.order = Order::Fixed(1);
        let mut id = Identifier::<f64, 6, 8>::new(s).unwrap();
        for (u, y) in record(400, 3) {
            id.push(u, y * scale);
        }
        solve(&id).unwrap().a(0, 0)
    };
    let (p1, p20) = (pole(1.0), pole(1e20));
    assert!(
        (p20 - p1).abs() < 1e-9,
        "f64: pole {p20} at 1e20, {p1} at 1"
    );
    assert!(
        (f64::from(small.a(0, 0)) - p1).abs() < 1e-3,
        "f32 at 1e15: pole {} (f64 {p1})",
        small.a(0, 0)
    );
}

fn solve_f32(id: &Identifier<f32, 6, 8>) -> Result<hsid::Model<f32, 6>, Error> {
    let mut ws = vec![0.0f32; id.workspace_len()];
    no_panic("solve", || id.solve(&mut ws))
}

/// CVA on exactly noise-free data (ramp basis, f = p = 3, one segment per path, a
/// first-order plant with a small feed-through) returned `Ok` with `A = 1.187` (the true pole
/// is 0.1) and `P_a(4) = -2.87` (true 1.163): a silently wrong model. CVA's weighting
/// `(Ȳ_f Π⊥ Ȳ_fᵀ)^{-1/2}` is undefined without noise (the residual of Ȳ_f has rank n): the
/// solve now compares the pivots of `Ȳ_f Π⊥ Ȳ_fᵀ` with the rounding level of the residual
/// and returns `RankDeficient { stage: CvaWeighting }`, whose message says to use PI-MOESP;
/// PI-MOESP on the same data gives the true model.
#[test]
fn cva_on_noise_free_data_is_not_silently_wrong() {
    let mu0 = 0.559_244_191_709_063_6;
    let truth = [mu0, mu0 + 0.603_576_311_149_058_3];
    let k = [-2.0, 4.0];
    let knots = Knots::<f64, M>::new(&k, &k).unwrap();
    let mut s = Settings::new(knots.clone(), 3, 3, MuZero::Known(mu0));
    s.order = Order::Fixed(1);
    s.method = Method::Cva;
    s.basis = Basis::Ramp;
    let mut id = Id::<f64>::new(s).unwrap();
    // The noise-free record: a first-order plant at rest at μ0, then Table I.
    let feed = |id: &mut Id<f64>| {
        let mut sw = PwlSwitch::new(k.to_vec(), truth.to_vec(), k.to_vec(), vec![mu0, mu0 - 0.2]);
        let mut plant = Lti::new(1, 0.1, 0.0, false, 0.0, 0.0);
        plant.b = [-0.002_854_993_264_283_388, 0.902_854_993_264_283_4, 0.0];
        for _ in 0..400 {
            plant.step(mu0);
        }
        for (u, y) in table1(
            &knots,
            0,
            1081,
            15_029_245_326_058_622_124,
            &mut sw,
            &mut plant,
        ) {
            id.push(u, y);
        }
    };
    feed(&mut id);
    let e = solve(&id).unwrap_err();
    assert_eq!(
        e,
        Error::RankDeficient {
            stage: hsid::Stage::CvaWeighting
        }
    );
    let msg = e.to_string();
    assert!(
        msg.contains("noise-free") && msg.contains("PI-MOESP"),
        "{msg}"
    );
    let mut s = id.settings().clone();
    s.method = Method::PiMoesp;
    let mut pi = Id::<f64>::new(s).unwrap();
    feed(&mut pi);
    let m = solve(&pi).unwrap();
    let got = m.border_values(Direction::Ascending)[1];
    assert!(
        (got - truth[1]).abs() < 1e-8 && (m.a(0, 0) - 0.1).abs() < 1e-8,
        "PI-MOESP: A = {}, P_a(4) = {got} (true 0.1, {})",
        m.a(0, 0),
        truth[1]
    );
}

/// In `f32` the automatic order over-counted at high SNR: a first-order plant, PI-MOESP, one
/// segment per path, f = p = 4, 1,543 samples after a hold, white noise of standard deviation
/// 1e-4 on outputs of order 0.3 (about 70 dB): `f64` found n = 1 in 50 runs of 50, `f32` in
/// 27 (rounding in the Schur complement made residual pivots of L₃₃ tiny, and the whitening
/// divided by them; with past outputs among the instruments it happened at 1e-3 too). The
/// whitening now floors each row of L₃₃ at the rounding level of its residual (the sums'
/// relative error ε(√j + √dim) times the row's raw Gram diagonal, plus what L₃₂ inherits
/// from small pivots of the instruments), and the semi-definite rows of the Cholesky drop
/// pivots below the same level. Here: 50 of 50 in `f32` for PI-MOESP at 1e-4 and every
/// weighting at 1e-3 and 1e-6 (CVA may refuse, never over-count).
#[test]
fn f32_automatic_order_at_high_snr() {
    fn order<T: Real>(seed: u64, method: Method, noise: f64) -> Result<usize, Error> {
        let k = [-2.0, 4.0];
        let kt = [T::of(-2.0), T::of(4.0)];
        let knots = Knots::<T, M>::new(&kt, &kt).unwrap();
        let mut s = Settings::new(
            knots.clone(),
            4,
            4,
            MuZero::Hold {
                len: 200,
                settle: 180,
            },
        );
        s.basis = Basis::Ramp;
        s.method = method;
        let mut id = Id::<T>::new(s).unwrap();
        let mut sw = PwlSwitch::new(k.to_vec(), vec![0.0, 0.63], k.to_vec(), vec![0.0, 0.2]);
        let mut plant = Lti::new(1, -0.05, 0.0, false, 0.0, 0.0);
        let mut r = seed;
        for (u, y) in table1(
            &knots,
            200,
            1743,
            17_039_288_035_587_460_676,
            &mut sw,
            &mut plant,
        ) {
            r = r
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            let e = ((r >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * noise * 12f64.sqrt();
            id.push(u, y + T::of(e));
        }
        let mut ws = vec![T::zero(); id.workspace_len()];
        id.solve(&mut ws).map(|m| m.order())
    }
    let cases = [
        (Method::PiMoesp, 1e-4),
        (Method::PiMoesp, 1e-6),
        (Method::PoMoesp, 1e-3),
        (Method::N4sid, 1e-3),
        (Method::Cva, 1e-3),
        (Method::PoMoesp, 1e-6),
        (Method::N4sid, 1e-6),
        (Method::Cva, 1e-6),
    ];
    for (method, noise) in cases {
        let (mut right32, mut right64, mut refused32) = (0, 0, 0);
        for seed in 0..50 {
            right64 += usize::from(order::<f64>(seed, method, noise) == Ok(1));
            match order::<f32>(seed, method, noise) {
                Ok(n) => {
                    assert_eq!(n, 1, "{method:?} at {noise}, seed {seed}: f32 order {n}");
                    right32 += 1;
                }
                Err(e) => {
                    // CVA may find its weighting singular to rounding in f32; nothing else
                    // may refuse these data.
                    assert!(
                        method == Method::Cva
                            && e == Error::RankDeficient {
                                stage: hsid::Stage::CvaWeighting
                            },
                        "{method:?} at {noise}, seed {seed}: {e}"
                    );
                    refused32 += 1;
                }
            }
        }
        println!("{method:?} at {noise}: f32 {right32} right, {refused32} refused; f64 {right64}");
        assert_eq!(right64, 50, "{method:?} at {noise}");
        if method != Method::Cva {
            assert_eq!(right32, 50, "{method:?} at {noise}");
        }
    }
}

/// A checkpoint whose checksums are valid but whose sample counters are impossible was
/// restored as is: `count = u64::MAX` then overflowed `count + 1` in `Accumulator::columns`
/// (a panic with overflow checks; without them `j` wrapped to 0 and `solve` looped over 2^64
/// samples in `row_sums`), and `count > index` (more samples accumulated than pushed) was
/// accepted. `restore` refuses them (`CheckpointError::Invalid`).
#[test]
fn checkpoints_with_impossible_counters_are_refused() {
    let knots = Knots::<f64, 6>::uniform(-3.0, 3.0, 2, 2).unwrap();
    let mut id =
        Identifier::<f64, 6, 8>::new(Settings::new(knots, 3, 3, MuZero::Estimate)).unwrap();
    for (u, y) in record(100, 4) {
        id.push(u, y);
    }
    let mut good = vec![0u8; id.checkpoint_len()];
    id.save(&mut good).unwrap();
    let end = settings_end(&good, 8).unwrap();
    for (what, count, index) in [
        ("count = u64::MAX", u64::MAX, u64::MAX),
        ("count > index", 90, 50),
        ("index = u64::MAX", 100, u64::MAX),
    ] {
        let mut bad = good.clone();
        bad[end..end + 8].copy_from_slice(&count.to_le_bytes());
        bad[end + 8..end + 16].copy_from_slice(&index.to_le_bytes());
        fix_checksums(&mut bad, 8);
        let r = no_panic("restore", || Identifier::<f64, 6, 8>::restore(&bad));
        assert_eq!(
            r.err(),
            Some(Error::Checkpoint(CheckpointError::Invalid)),
            "{what}"
        );
    }
}

/// Regression: `MuZero::Known(NaN)` used to be refused as "sample 0: output y is NaN or
/// infinite" although no sample had been pushed. The error names μ0.
#[test]
fn a_non_finite_known_mu0_is_named() {
    let knots = Knots::<f64, 6>::uniform(-3.0, 3.0, 2, 2).unwrap();
    let e = Identifier::<f64, 6, 8>::new(Settings::new(knots, 3, 3, MuZero::Known(f64::NAN)))
        .unwrap_err();
    assert!(
        matches!(e, Error::InvalidMu0 { value } if value.is_nan()),
        "{e:?}"
    );
    let msg = e.to_string();
    assert!(msg.contains("mu0") || msg.contains("μ0"), "{e:?}: {msg}");
}

/// Exactly noise-free data from the exact model class: `A` came out exact (1e-16) but `D`
/// (and with it `B` and the borders) was off by 1.2e-2 for f = 3, p = 2 and 1,372 samples.
/// The least squares for `[D; B]` was right; the error came from the rank-1 split, whose
/// 2 × 2 SVD (nalgebra's bidiagonal SVD, σ₂/σ₁ ≈ 1e-14) returned a first left singular
/// vector off by 2e-2 (nalgebra issue #1172). The small SVDs are now one-sided Jacobi, which
/// computes small singular values and their vectors to high relative accuracy: `D` is 4e-15.
#[test]
fn noise_free_b_and_d_do_not_depend_on_rounding() {
    let mu0 = -0.929_702_026_786_703_9;
    let k = [-2.0, 4.0];
    let knots = Knots::<f64, M>::new(&k, &k).unwrap();
    let mut s = Settings::new(knots.clone(), 3, 2, MuZero::Known(mu0));
    s.order = Order::Fixed(1);
    let mut id = Id::<f64>::new(s).unwrap();
    let mut sw = PwlSwitch::new(
        k.to_vec(),
        vec![mu0, mu0 + 0.2],
        k.to_vec(),
        vec![mu0, mu0 + 0.455_710_346_569_417_4],
    );
    let mut plant = Lti::new(1, -0.05, 0.0, false, 0.0, 0.0);
    for _ in 0..400 {
        plant.step(mu0);
    }
    for (u, y) in table1(
        &knots,
        0,
        1372,
        16_463_568_061_613_932_314,
        &mut sw,
        &mut plant,
    ) {
        id.push(u, y);
    }
    let m = solve(&id).unwrap();
    assert!((m.a(0, 0) + 0.05).abs() < 1e-12);
    assert!(m.d().abs() < 1e-12, "D = {} (true 0)", m.d());
    let want = [mu0, mu0 + 0.455_710_346_569_417_4];
    let got = m.border_values(Direction::Descending);
    for (g, w) in got.iter().zip(want) {
        assert!((g - w).abs() < 1e-10, "P_d {got:?} (true {want:?})");
    }
}

/// The record of a reconstruction-property case: knots rounded to `T`, the switch with
/// [`borders`], the plant at rest at μ0, noise of standard deviation `noise`.
#[allow(clippy::too_many_arguments)]
fn case_record<T: Real>(
    asc: &[f64],
    desc: &[f64],
    values: (&[f64], &[f64]),
    mu0: f64,
    plant: &Lti,
    samples: usize,
    seed: u64,
    noise: f64,
) -> (Knots<T, M>, Vec<(f64, f64)>) {
    let a: Vec<T> = asc.iter().map(|&v| T::of(v)).collect();
    let d: Vec<T> = desc.iter().map(|&v| T::of(v)).collect();
    let knots = Knots::<T, M>::new(&a, &d).unwrap();
    let ka: Vec<f64> = a.iter().map(|v| v.to_f64()).collect();
    let kd: Vec<f64> = d.iter().map(|v| v.to_f64()).collect();
    let mut sw = PwlSwitch::new(ka, borders(mu0, values.0), kd, borders(mu0, values.1));
    let mut plant = plant.clone();
    for _ in 0..400 {
        plant.step(mu0);
    }
    let data = noisy_record(&knots, 0, samples, seed, noise, &mut sw, &mut plant);
    (knots, data)
}

fn case_solve<T: Real>(
    knots: Knots<T, M>,
    f: usize,
    p: usize,
    method: Method,
    order: usize,
    mu0: f64,
    data: &[(f64, f64)],
) -> Result<hsid::Model<T, M>, Error> {
    let mut s = Settings::new(knots, f, p, MuZero::Known(T::of(mu0)));
    s.basis = Basis::Ramp;
    s.method = method;
    s.order = Order::Fixed(order);
    let mut id = Id::<T>::new(s).unwrap();
    for &(u, y) in data {
        id.push(T::of(u), T::of(y));
    }
    let mut ws = vec![T::zero(); id.workspace_len()];
    no_panic("solve", || id.solve(&mut ws))
}

/// `f32` CVA at about 30 dB (noise 1e-2) — ramp basis, f = 4, p = 3, 3 + 1 segments, a
/// first-order plant with feed-through — returned `Ok` with Markov parameters off by 34 and
/// borders by 0.9 from the `f64` model on the same data, which is right. Cause: the past
/// outputs are nearly explained by the inputs (small pivots of `L₂₂`), so `L₃₂` inherits the
/// rounding of the `f32` sums amplified by `g_i / d_i²`, and `L₃₃² = S₃₃ − L₃₂L₃₂ᵀ` loses
/// the residual: two canonical correlations came out ≥ 1 (1.0002, 1.0000001; `f64`: 0.9999,
/// 0.139). The solve now estimates that rounding level row by row and refuses the CVA
/// weighting below it (`RankDeficient { CvaWeighting }`); PI-MOESP, PO-MOESP and N4SID on the
/// same `f32` data agree with `f64`.
#[test]
fn f32_cva_is_not_silently_wrong() {
    let mut plant = Lti::new(1, -0.403_720_715_923_295_4, 0.0, false, 0.0, 0.0);
    plant.b = [-1.147_893_918_945_150_2, 2.551_614_634_868_445_6, 0.0];
    let args = (
        &[-2.0, 0.927_284_305_904_891_9, 1.827_284_305_904_892_2, 4.0][..],
        &[-2.0, 4.0][..],
        (
            &[0.992_049_783_005_192_8, -0.134_011_220_548_561_52, 0.0][..],
            &[0.0][..],
        ),
    );
    let (k32, data) = case_record::<f32>(
        args.0,
        args.1,
        args.2,
        0.0,
        &plant,
        910,
        1_912_530_314_475_897_714,
        1e-2,
    );
    let (k64, _) = case_record::<f64>(
        args.0,
        args.1,
        args.2,
        0.0,
        &plant,
        910,
        1_912_530_314_475_897_714,
        1e-2,
    );
    let m64 = case_solve::<f64>(k64.clone(), 4, 3, Method::Cva, 1, 0.0, &data).unwrap();
    if let Ok(m32) = case_solve::<f32>(k32.clone(), 4, 3, Method::Cva, 1, 0.0, &data) {
        for k in 0..10 {
            let (a, b) = (f64::from(m32.markov(k)), m64.markov(k));
            assert!((a - b).abs() < 5e-3 * 2.6, "h_{k}: f32 {a}, f64 {b}");
        }
    }
    for method in [Method::PiMoesp, Method::PoMoesp, Method::N4sid] {
        let m32 = case_solve::<f32>(k32.clone(), 4, 3, method, 1, 0.0, &data).unwrap();
        let m64 = case_solve::<f64>(k64.clone(), 4, 3, method, 1, 0.0, &data).unwrap();
        for k in 0..10 {
            let (a, b) = (f64::from(m32.markov(k)), m64.markov(k));
            assert!(
                (a - b).abs() < 5e-3 * 3.1,
                "{method:?} h_{k}: f32 {a}, f64 {b}"
            );
        }
    }
}

/// `f32` PO-MOESP on exactly noise-free data (the only noise is the rounding of `y` to
/// `f32`) — ramp basis, f = 3, p = 5, 3 + 3 segments, a second-order plant with poles 0.6
/// and 0.43 — returned `Ok` with `A` of trace 0.93 and determinant 0.154 (true 1.045 and
/// 0.258). Cause: the past outputs given the inputs have rank n = 2 without noise, and the
/// Cholesky kept pivots of rounding size (> 0) for the dependent rows, whose columns of
/// `L₃₂` were rounding divided by rounding. Pivots of the rows that may be singular are now
/// dropped below the rounding level of their row (ε(√j + √dim) times the raw Gram diagonal);
/// the model is within 1e-4 of the truth.
#[test]
fn f32_past_outputs_on_noise_free_data_are_not_silently_wrong() {
    let plant = {
        let mut p = Lti::new(2, 0.6, 0.43, false, 0.0, 0.0);
        p.a = [-1.044_614_202_564_286, 0.257_636_882_516_072_25];
        p.b = [
            0.001_885_275_408_560_641_5,
            0.158_250_342_941_305_1,
            0.052_887_061_601_920_58,
        ];
        p
    };
    let mu0 = -0.769_049_842_276_201;
    let (k32, data) = case_record::<f32>(
        &[
            -2.0,
            -1.071_168_493_186_943_8,
            0.085_314_882_817_943_53,
            4.0,
        ],
        &[-2.0, 0.174_290_824_080_485_68, 2.136_720_888_351_658_4, 4.0],
        (
            &[
                -0.166_118_813_712_870_52,
                -0.035_632_765_733_078_47,
                -0.623_953_183_655_676_5,
            ],
            &[
                -0.008_948_508_057_661_286,
                0.205_165_972_623_520_52,
                0.424_020_855_354_940_9,
            ],
        ),
        mu0,
        &plant,
        1834,
        11_799_099_120_192_055_641,
        0.0,
    );
    let m = case_solve::<f32>(k32, 3, 5, Method::PoMoesp, 2, mu0, &data).unwrap();
    let a = |i, j| f64::from(m.a(i, j));
    let (tr, det) = (a(0, 0) + a(1, 1), a(0, 0) * a(1, 1) - a(0, 1) * a(1, 0));
    assert!(
        (tr - 1.044_614_202_564_286).abs() < 1e-4 && (det - 0.257_636_882_516_072_25).abs() < 1e-4,
        "trace {tr}, det {det} (true 1.0446, 0.2576)"
    );
}

/// The rounding floors of the rows that may be singular (past and future outputs, `p + f`
/// of them with past outputs) are held in an array of the block-row capacity `K`: a past
/// horizon with `p + f` beyond twice the horizon capacity `H = 12` (here p = 24, f = 12, K = 36) solves without
/// indexing past it, for every weighting.
#[test]
fn long_past_horizons_with_past_outputs_do_not_panic() {
    let knots = Knots::<f64, 2>::uniform(-3.0, 3.0, 1, 1).unwrap();
    let data = record(3000, 5);
    for method in [Method::PiMoesp, Method::PoMoesp, Method::N4sid, Method::Cva] {
        let mut s = Settings::new(knots.clone(), 12, 24, MuZero::Known(0.0));
        s.method = method;
        s.order = Order::Fixed(1);
        let mut id = Box::new(Identifier::<f64, 2, 36>::new(s).unwrap());
        for &(u, y) in &data {
            id.push(u, y);
        }
        let r = solve(&id);
        assert!(
            matches!(&r, Ok(m) if (m.a(0, 0) - 0.5).abs() < 0.2)
                || matches!(r, Err(Error::RankDeficient { .. })),
            "{method:?}: {:?}",
            r.map(|m| m.a(0, 0))
        );
    }
}
