//! Benchmarks of the streaming identifier at the paper's size (Section IV: j = 4000,
//! f = p = 10, 7 uniform segments per path, a hold of 300 samples), in `f64` and `f32`:
//!
//! * `whole/*`: one whole identification, every sample pushed and the final solve;
//! * `solve/*`: the final solve alone, on an identifier that has seen all samples (the dense
//!   solve, and `solve/structured *` the structured one);
//! * `push/*`: the per-sample update, 1000 samples per iteration on an identifier already past
//!   its hold (reported per sample).
//!
//! Run with `cargo bench -p hsid-host --bench identify`.
#![allow(clippy::panic)]

use std::hint::black_box;
use std::time::Duration;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use hsid::{Basis, Identifier, Knots, MuZero, Real, Settings};
use hsid_host::paper::{Case, PaperConfig, experiment};

/// Channel capacity: 7 + 7 segments.
const M: usize = 14;
/// Block-row capacity: f + p.
const K: usize = 20;
/// Samples pushed per iteration of the `push` benchmarks.
const PUSH_BATCH: usize = 1000;

/// The paper's settings in scalar type `T`.
fn settings<T: Real>(cfg: &PaperConfig) -> Settings<T, M> {
    let knots = Knots::<T, M>::uniform(
        T::of(cfg.u_min),
        T::of(cfg.u_max),
        cfg.segments,
        cfg.segments,
    )
    .unwrap_or_else(|e| panic!("knots: {e}"));
    let mut s = Settings::new(
        knots,
        cfg.f,
        cfg.p,
        MuZero::Hold {
            len: cfg.hold,
            settle: cfg.settle,
        },
    );
    s.basis = Basis::Hat;
    s
}

/// A fresh identifier with the paper's settings (boxed: the sums are a few tens of kB).
fn fresh<T: Real>(cfg: &PaperConfig) -> Box<Identifier<T, M, K>> {
    Box::new(Identifier::new(settings(cfg)).unwrap_or_else(|e| panic!("identifier: {e}")))
}

/// Pushes the whole record and solves; returns the order, so the work cannot be optimised away.
fn identify<T: Real>(cfg: &PaperConfig, u: &[T], y: &[T], ws: &mut [T]) -> usize {
    let mut id = fresh::<T>(cfg);
    for (&ui, &yi) in u.iter().zip(y) {
        id.push(ui, yi);
    }
    id.solve(ws)
        .unwrap_or_else(|e| panic!("solve: {e}"))
        .order()
}

/// Benchmarks of one scalar type.
fn bench_type<T: Real>(c: &mut Criterion, name: &str, cfg: &PaperConfig, u: &[f64], y: &[f64]) {
    let u: Vec<T> = u.iter().map(|&v| T::of(v)).collect();
    let y: Vec<T> = y.iter().map(|&v| T::of(v)).collect();

    // Sanity: the benchmark identifies the paper's order-2 model.
    let mut ws = vec![T::default(); fresh::<T>(cfg).workspace_len()];
    assert_eq!(
        identify(cfg, &u, &y, &mut ws),
        2,
        "{name}: unexpected order"
    );

    let mut g = c.benchmark_group("whole");
    g.throughput(Throughput::Elements(u.len() as u64));
    g.bench_function(name, |b| {
        b.iter(|| identify(cfg, black_box(&u), black_box(&y), &mut ws))
    });
    g.finish();

    let mut prepared = fresh::<T>(cfg);
    for (&ui, &yi) in u.iter().zip(&y) {
        prepared.push(ui, yi);
    }
    let mut g = c.benchmark_group("solve");
    g.bench_function(name, |b| {
        b.iter(|| {
            black_box(&prepared)
                .solve(&mut ws)
                .unwrap_or_else(|e| panic!("solve: {e}"))
                .order()
        })
    });
    let mut small = vec![T::default(); prepared.structured_workspace_len()];
    g.bench_function(format!("structured {name}"), |b| {
        b.iter(|| {
            black_box(&prepared)
                .solve_structured(&mut small)
                .unwrap_or_else(|e| panic!("structured solve: {e}"))
                .order()
        })
    });
    g.finish();

    // The per-sample update past the hold: keep pushing excitation samples, cycling through the
    // record after the hold. The cycle is cut to a whole number of Table I periods (4 samples),
    // so the wrap from its last sample (u_min) to its first (a random level) follows the pattern.
    let mut id = fresh::<T>(cfg);
    for (&ui, &yi) in u.iter().zip(&y).take(cfg.hold) {
        id.push(ui, yi);
    }
    let period = (u.len() - cfg.hold) / 4 * 4;
    let (eu, ey) = (
        &u[cfg.hold..cfg.hold + period],
        &y[cfg.hold..cfg.hold + period],
    );
    let mut at = 0usize;
    let mut g = c.benchmark_group("push");
    g.throughput(Throughput::Elements(PUSH_BATCH as u64));
    g.bench_function(name, |b| {
        b.iter(|| {
            for _ in 0..PUSH_BATCH {
                id.push(black_box(eu[at]), black_box(ey[at]));
                at += 1;
                if at == eu.len() {
                    at = 0;
                }
            }
        })
    });
    g.finish();
    assert!(id.fault().is_none(), "{name}: push recorded a fault");
}

fn benches(c: &mut Criterion) {
    let cfg = PaperConfig::default();
    let e = experiment(Case::Backlash, &cfg, 0).unwrap_or_else(|e| panic!("experiment: {e}"));
    assert_eq!(e.u.len(), cfg.hold + cfg.j + cfg.f + cfg.p - 1);
    bench_type::<f64>(c, "f64", &cfg, &e.u, &e.y);
    bench_type::<f32>(c, "f32", &cfg, &e.u, &e.y);
}

fn config() -> Criterion {
    Criterion::default()
        .sample_size(20)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(3))
}

criterion_group! {
    name = identify_benches;
    config = config();
    targets = benches
}
criterion_main!(identify_benches);
