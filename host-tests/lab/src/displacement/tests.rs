//! The structured solve against the dense one on explicit Hankel rows, in `f64` and `f32`.

#![allow(clippy::unwrap_used)]

use super::*;

/// SplitMix64: a small deterministic generator for the test records.
struct Rng(u64);

impl Rng {
    fn uniform(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }

    fn normal(&mut self) -> f64 {
        let (a, b) = (self.uniform().max(1e-300), self.uniform());
        (-2.0 * a.ln()).sqrt() * (std::f64::consts::TAU * b).cos()
    }
}

/// `n` samples of `w = [z; y]`: an AR(1) input on `[−1, 1]`, `m` hats of it (correlated
/// channels), a second-order ARX output of a weighted sum of the hats plus white noise.
fn record(m: usize, n: usize, seed: u64) -> Vec<f64> {
    let mut rng = Rng(seed);
    let h = 2.0 / m as f64;
    let coef: Vec<f64> = (0..m).map(|i| (i as f64 + 1.0).sin() + 0.5).collect();
    let (mut u, mut y1, mut y2, mut x1, mut x2) = (0.0f64, 0.0, 0.0, 0.0, 0.0);
    let mut w = Vec::with_capacity(n * (m + 1));
    for _ in 0..n + 100 {
        u = (0.5 * u + 1.2 * (2.0 * rng.uniform() - 1.0)).clamp(-1.0, 1.0);
        let z: Vec<f64> = (0..m)
            .map(|i| (1.0 - (u - (-1.0 + (i + 1) as f64 * h)).abs() / h).max(0.0))
            .collect();
        let x: f64 = z.iter().zip(&coef).map(|(a, b)| a * b).sum();
        let y = 1.5 * y1 - 0.7 * y2 + x1 + 0.5 * x2 + 0.1 * rng.normal();
        (y2, y1, x2, x1) = (y1, y, x1, x);
        w.extend(z);
        w.push(y);
    }
    w.split_off(100 * (m + 1))
}

/// `(channel, lag)` of each row of `[Z_f; Z_p; Ȳ_f]` in the natural order.
fn natural_rows(m: usize, f: usize, p: usize) -> Vec<(usize, usize)> {
    let k = f + p;
    let mut rows: Vec<(usize, usize)> = Vec::new();
    rows.extend((p..k).flat_map(|lag| (0..m).map(move |ch| (ch, lag))));
    rows.extend((0..p).flat_map(|lag| (0..m).map(move |ch| (ch, lag))));
    rows.extend((p..k).map(|lag| (m, lag)));
    rows
}

/// The Gram of the rows `[Z_f; Z_p; Ȳ_f]` (natural order) by `entry(channel, lag, channel,
/// lag)`.
fn gram_by<T: Real>(
    m: usize,
    f: usize,
    p: usize,
    entry: impl Fn(usize, usize, usize, usize) -> T,
) -> DMatrix<T> {
    let rows = natural_rows(m, f, p);
    DMatrix::from_fn(rows.len(), rows.len(), |a, b| {
        entry(rows[a].0, rows[a].1, rows[b].0, rows[b].1)
    })
}

/// The Gram of the explicit Hankel rows `[Z_f; Z_p; Ȳ_f]` of the record `w`.
fn hankel_gram(w: &[f64], m: usize, f: usize, p: usize) -> DMatrix<f64> {
    let c = m + 1;
    let j = w.len() / c + 1 - (f + p);
    let rows = natural_rows(m, f, p);
    let h = DMatrix::from_fn(rows.len(), j, |r, s| w[(rows[r].1 + s) * c + rows[r].0]);
    &h * h.transpose()
}

/// The four blocks the dense way from the Gram: its Cholesky factor and solves with
/// `G_{Z_f Z_f}`.
fn dense<T: Real>(g: &DMatrix<T>, m: usize, f: usize, p: usize) -> [DMatrix<T>; 4] {
    let (fm, pm) = (f * m, p * m);
    let l = g.clone().cholesky().map(|ch| ch.l()).unwrap_or_default();
    let l32 = l.view((fm + pm, fm), (f, pm)).into_owned();
    let l33 = l.view((fm + pm, fm + pm), (f, f)).into_owned();
    let gff = g.view((0, 0), (fm, fm)).into_owned();
    let gyf = g.view((fm + pm, 0), (f, fm)).into_owned();
    let gyy = g.view((fm + pm, fm + pm), (f, f)).into_owned();
    let x = gff
        .cholesky()
        .map(|ch| ch.solve(&gyf.transpose()))
        .unwrap_or_default();
    let s_f = &gyy - &gyf * &x;
    [
        s_f,
        &l33 * l33.transpose(),
        &l32 * l32.transpose(),
        x.transpose(),
    ]
}

fn rel(a: &DMatrix<f64>, b: &DMatrix<f64>) -> f64 {
    if a.shape() != b.shape() {
        return f64::INFINITY;
    }
    (a - b).norm() / b.norm()
}

fn to64<T: Real>(a: &DMatrix<T>) -> DMatrix<f64> {
    a.map(|v| v.to_f64())
}

/// Relative errors of `S_f`, `S_Φ`, `L₃₂L₃₂ᵀ`, `B_f` against the dense blocks.
fn errors<T: Real>(got: &Blocks<T>, want: &[DMatrix<f64>; 4]) -> [f64; 4] {
    let got = [&got.s_f, &got.s_phi, &got.l32_l32t, &got.b_f];
    core::array::from_fn(|i| rel(&to64(got[i]), &want[i]))
}

fn dense_errors<T: Real>(got: &[DMatrix<T>; 4], want: &[DMatrix<f64>; 4]) -> [f64; 4] {
    core::array::from_fn(|i| rel(&to64(&got[i]), &want[i]))
}

const CASES: [(usize, usize, usize, usize); 4] = [
    (3, 4, 4, 2000),
    (6, 8, 8, 4000),
    (14, 10, 10, 6000),
    (16, 12, 12, 8000),
];

/// One of the [`CASES`]: its record, the dense `f64` blocks and the lagged sums.
fn case(m: usize, f: usize, p: usize, n: usize) -> (Vec<f64>, [DMatrix<f64>; 4], LaggedSums<f64>) {
    let w = record(m, n, 7 + m as u64);
    let want = dense(&hankel_gram(&w, m, f, p), m, f, p);
    let sums = LaggedSums::from_samples(m, f, p, &w).unwrap();
    (w, want, sums)
}

#[test]
fn gram_entries_are_those_of_the_hankel_rows() {
    let (m, f, p) = (3, 3, 2);
    let w = record(m, 60, 1);
    let sums = LaggedSums::from_samples(m, f, p, &w).unwrap();
    let c = m + 1;
    for (i, a, i2, b) in [(0, 0, 0, 0), (1, 2, 3, 4), (3, 4, 0, 1), (2, 3, 2, 3)] {
        let want: f64 = (0..sums.j)
            .map(|s| w[(a + s) * c + i] * w[(b + s) * c + i2])
            .sum();
        assert!(
            (sums.gram(i, a, i2, b).unwrap_or(f64::NAN) - want).abs() < 1e-12 * want.abs().max(1.0)
        );
    }
}

#[test]
fn f64_matches_the_dense_solve() {
    for (m, f, p, n) in CASES {
        let (_, want, sums) = case(m, f, p, n);
        let got = pi_moesp_blocks(&sums).unwrap();
        let e = errors(&got, &want);
        println!(
            "f64 (m,f,p)=({m},{f},{p}) j={}: S_f {:.1e} S_phi {:.1e} L32L32' {:.1e} B_f {:.1e}",
            sums.j, e[0], e[1], e[2], e[3]
        );
        assert!(e.iter().all(|v| *v < 1e-9), "{e:?}");
        let diff = &got.s_f - &got.s_phi;
        assert!(rel(&diff, &got.l32_l32t) < 1e-9);
    }
}

#[test]
fn f32_against_the_f64_dense_solve() {
    for (m, f, p, n) in CASES {
        let (w, want, sums) = case(m, f, p, n);
        let rounded = pi_moesp_blocks(&sums.cast::<f32>()).unwrap();
        let w32: Vec<f32> = w.iter().map(|v| *v as f32).collect();
        let sums32 = LaggedSums::from_samples(m, f, p, &w32).unwrap();
        let acc32 = pi_moesp_blocks(&sums32).unwrap();
        let (e1, e2) = (errors(&rounded, &want), errors(&acc32, &want));
        println!(
            "f32 sums rounded from f64 ({m},{f},{p}): S_f {:.1e} S_phi {:.1e} L32L32' {:.1e} B_f {:.1e}",
            e1[0], e1[1], e1[2], e1[3]
        );
        println!(
            "f32 sums accumulated in f32 ({m},{f},{p}): S_f {:.1e} S_phi {:.1e} L32L32' {:.1e} B_f {:.1e}",
            e2[0], e2[1], e2[2], e2[3]
        );
        let g32 = gram_by(m, f, p, |i, a, i2, b| {
            sums32.gram(i, a, i2, b).unwrap_or(f32::NAN)
        });
        let e3 = dense_errors(&dense(&g32, m, f, p), &want);
        println!(
            "f32 dense solve of the same sums ({m},{f},{p}): S_f {:.1e} S_phi {:.1e} L32L32' {:.1e} B_f {:.1e}",
            e3[0], e3[1], e3[2], e3[3]
        );
        for e in [e1, e2] {
            assert!(
                e[0] < 2e-4 && e[1] < 2e-3 && e[2] < 2e-4 && e[3] < 2e-4,
                "{e:?}"
            );
        }
    }
}

#[test]
fn the_generator_of_the_largest_case_fits_the_documented_memory() {
    let (rows, r) = generator_shape(14, 10, 10);
    assert_eq!((rows, r, rows * r * 4), (304, 32, 38_912));
    let w = record(3, 200, 3);
    let sums = LaggedSums::from_samples(3, 4, 4, &w).unwrap();
    let got = pi_moesp_blocks(&sums).unwrap();
    assert_eq!((got.rank, got.generator_len), (10, 31 * 10));
}

#[test]
fn inconsistent_or_indefinite_sums_are_refused() {
    assert_eq!(
        LaggedSums::from_samples(0, 2, 2, &[0.0; 40]),
        Err(DisplacementError::Shape)
    );
    let w = record(2, 100, 5);
    let mut sums = LaggedSums::from_samples(2, 2, 2, &w).unwrap();
    sums.lags.pop();
    assert_eq!(pi_moesp_blocks(&sums), Err(DisplacementError::Shape));
    // A silent record: the lag-(k−1) channels have no energy.
    let silent = LaggedSums::from_samples(2, 2, 2, &[0.0f64; 60]).unwrap();
    assert_eq!(pi_moesp_blocks(&silent), Err(DisplacementError::FirstBlock));
    // R_0 = I, R_1 = 2·I and no edges: the Gram [[I, 2I], [2I, I], …] is indefinite, and the
    // second block's first pivot is 1 − 4 < 0.
    let (m, f, p, c) = (2, 2, 2, 3);
    let mut lags = vec![0.0; 4 * c * c];
    for i in 0..c {
        lags[i * c + i] = 1.0;
        lags[(c + i) * c + i] = 2.0;
    }
    let bad = LaggedSums {
        m,
        f,
        p,
        j: 50,
        lags,
        head: vec![0.0; 3 * c],
        tail: vec![0.0; 3 * c],
    };
    assert_eq!(
        pi_moesp_blocks(&bad),
        Err(DisplacementError::NonPositivePivot { step: m })
    );
}

#[test]
fn power_of_two_channel_scales_change_nothing() {
    let (m, f, p) = (4, 5, 5);
    let w = record(m, 800, 11);
    let scale: Vec<f64> = (0..=m).map(|i| 2f64.powi(3 * i as i32 - 7)).collect();
    let ws: Vec<f64> = w
        .iter()
        .enumerate()
        .map(|(t, v)| v * scale[t % (m + 1)])
        .collect();
    let plain = pi_moesp_blocks(&LaggedSums::from_samples(m, f, p, &w).unwrap()).unwrap();
    let scaled = pi_moesp_blocks(&LaggedSums::from_samples(m, f, p, &ws).unwrap()).unwrap();
    let sy2 = scale[m] * scale[m];
    assert_eq!(scaled.s_f.map(|v| v / sy2), plain.s_f);
    assert_eq!(scaled.s_phi.map(|v| v / sy2), plain.s_phi);
    assert_eq!(scaled.l32_l32t.map(|v| v / sy2), plain.l32_l32t);
    let b = DMatrix::from_fn(f, f * m, |r, col| {
        scaled.b_f[(r, col)] * scale[col % m] / scale[m]
    });
    assert_eq!(b, plain.b_f);
}
