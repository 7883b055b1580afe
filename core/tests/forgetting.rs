//! Online use: with exponential forgetting the identification follows a servo whose backlash
//! gap grows halfway through a long run.
#![allow(clippy::unwrap_used, clippy::expect_used, missing_docs)]

use hsid::{
    Compensated, Direction, Excitation, Forgetting, Identifier, Knots, MuZero, Plain, Real,
    Settings, Summation,
};
use rand_core::{Rng, SeedableRng};
use rand_pcg::Pcg32;

const CHANGE: usize = 20_000;

/// The backlash's true ascending/descending paths over a Table I cycle on [-3, 3] with gap `g`.
fn true_paths(g: f64, u: f64) -> (f64, f64) {
    let asc = ((-3.0f64) + g).atan().max((u - g).atan());
    let desc = (3.0 - g).atan().min((u + g).atan());
    (asc, desc)
}

fn border_rms<T: Real>(m: &hsid::Model<T, 14>, g: f64) -> f64 {
    let mut s = 0.0;
    let n = 301;
    for i in 0..n {
        let u = -3.0 + 6.0 * i as f64 / (n - 1) as f64;
        let (a, d) = true_paths(g, u);
        s += (m.border(Direction::Ascending, T::of(u)).to_f64() - a).powi(2)
            + (m.border(Direction::Descending, T::of(u)).to_f64() - d).powi(2);
    }
    (s / (2 * n) as f64).sqrt()
}

/// Runs the experiment and solves at the given sample counts; returns the border RMS errors
/// against the gap in force at that time.
fn run(forgetting: Forgetting<f64>, at: &[usize]) -> Vec<(usize, f64, f64)> {
    run_as::<f64, Plain>(forgetting, at)
}

/// [`run`] in the scalar `T` with the summation `S` (the data are computed in `f64`).
fn run_as<T: Real, S: Summation<T, 14, 20>>(
    forgetting: Forgetting<f64>,
    at: &[usize],
) -> Vec<(usize, f64, f64)> {
    let forgetting = match forgetting {
        Forgetting::None => Forgetting::None,
        Forgetting::Exponential { lambda } => Forgetting::Exponential {
            lambda: T::of(lambda),
        },
    };
    let knots = Knots::<T, 14>::uniform(T::of(-3.0), T::of(3.0), 7, 7).unwrap();
    let mut s = Settings::new(knots, 10, 10, MuZero::Estimate);
    s.order = hsid::Order::Fixed(2);
    s.forgetting = forgetting;
    let mut id = Identifier::<T, 14, 20, S>::new(s).unwrap();
    let (mut w, mut y1, mut y2, mut w1, mut w2) = (0.0f64, 0.0, 0.0, 0.0, 0.0);
    let mut noise = Pcg32::seed_from_u64(5);
    let mut ws = vec![T::zero(); id.workspace_len()];
    let mut out = Vec::new();
    let last = at.iter().copied().max().unwrap_or(0);
    let exc = Excitation::<f64, _>::new(-3.0, 3.0, 1, Pcg32::seed_from_u64(8)).unwrap();
    for (t, u) in exc.take(last).enumerate() {
        let g = if t < CHANGE { 1.0 } else { 1.5 };
        w = w.max((u - g).atan()).min((u + g).atan());
        let y = 1.8858 * y1 - 0.9048 * y2 + 0.1994 * w1 - 0.1804 * w2;
        (w2, w1, y2, y1) = (w1, w, y1, y);
        let e = (noise.next_u32() as f64 / 4294967296.0 - 0.5) * 0.04;
        id.push(T::of(u), T::of(y + e));
        if at.contains(&(t + 1)) {
            let m = id.solve(&mut ws).unwrap();
            out.push((t + 1, border_rms(&m, 1.0), border_rms(&m, 1.5)));
        }
    }
    out
}

#[test]
fn forgetting_tracks_a_growing_backlash_gap() {
    // λ = 0.9995: the model remembers ≈ 2000 samples.
    let f = Forgetting::Exponential { lambda: 0.9995 };
    let r = run(f, &[CHANGE, CHANGE + 1000, CHANGE + 5000, CHANGE + 8000]);
    for (n, old, new) in &r {
        println!("after {n} samples: border RMS vs old gap {old:.4}, vs new gap {new:.4}");
    }
    // Before the change the model matches the old gap.
    assert!(r[0].1 < 0.05, "{:?}", r[0]);
    // 5000 samples (2.5 memory lengths) after the change it matches the new one.
    assert!(r[2].2 < 0.05, "{:?}", r[2]);
    assert!(r[3].2 < 0.05, "{:?}", r[3]);
    assert!(
        r[2].1 > 2.0 * r[2].2,
        "it must have left the old gap: {:?}",
        r[2]
    );

    // Without forgetting the same run is stuck between the two gaps.
    let g = run(Forgetting::None, &[CHANGE + 5000]);
    println!(
        "no forgetting, after {} samples: vs old {:.4}, vs new {:.4}",
        g[0].0, g[0].1, g[0].2
    );
    assert!(g[0].2 > 2.0 * r[2].2, "{:?} vs {:?}", g[0], r[2]);
}

/// Forgetting with compensated `f32` sums (the running scale is folded back into the sums and
/// their carries every 22,177 samples at λ = 0.9995, twice in this run): the same tracking,
/// and borders within 5e-3 of the `f64` model's.
#[test]
fn forgetting_with_compensated_f32_sums() {
    let f = Forgetting::Exponential { lambda: 0.9995 };
    let at = [CHANGE, CHANGE + 5000, CHANGE + 30_000];
    let r = run(f, &at);
    let c = run_as::<f32, Compensated>(f, &at);
    for ((n, old, new), (_, old32, new32)) in r.iter().zip(&c) {
        println!(
            "after {n} samples: f64 vs old/new gap {old:.4}/{new:.4}, compensated f32 {old32:.4}/{new32:.4}"
        );
        assert!((old - old32).abs() < 5e-3 && (new - new32).abs() < 5e-3);
    }
    assert!(c[0].1 < 0.05, "{:?}", c[0]);
    assert!(c[1].2 < 0.05 && c[2].2 < 0.05, "{c:?}");
    assert!(
        c[1].1 > 2.0 * c[1].2,
        "it must have left the old gap: {c:?}"
    );
}

/// Forgetting with λ = 1 is no forgetting, bit for bit, and invalid factors are refused.
#[test]
fn forgetting_factor_is_validated() {
    let knots = Knots::<f64, 14>::uniform(-3.0, 3.0, 7, 7).unwrap();
    for bad in [0.0, -0.5, 1.5, f64::NAN] {
        let mut s = Settings::new(knots.clone(), 10, 10, MuZero::Estimate);
        s.forgetting = Forgetting::Exponential { lambda: bad };
        assert!(matches!(
            Identifier::<f64, 14, 20>::new(s),
            Err(hsid::Error::InvalidForgetting { .. })
        ));
    }
    let a = run(Forgetting::None, &[6000]);
    let b = run(Forgetting::Exponential { lambda: 1.0 }, &[6000]);
    assert_eq!(a[0].1.to_bits(), b[0].1.to_bits());
}
