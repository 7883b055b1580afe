//! The numerical rank and the extreme eigenvalues of a symmetric positive semidefinite matrix
//! (a Gram matrix), in `d³/6` multiply-adds: a Cholesky factorisation with diagonal pivoting
//! (the rank: the pivots above a tolerance), power iteration for the largest eigenvalue and
//! inverse iteration through the factor for the smallest. A full symmetric eigendecomposition
//! costs about 25 times more, which matters at the thousand-odd rows of a Hankel Gram.

/// What [`spectrum`] finds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spectrum {
    /// The numerical rank: pivots of the pivoted Cholesky factorisation above `tol` times the
    /// largest diagonal element.
    pub rank: usize,
    /// The largest eigenvalue (power iteration).
    pub max: f64,
    /// The smallest eigenvalue when the matrix is of full numerical rank (inverse iteration),
    /// else `None`.
    pub min: Option<f64>,
}

impl Spectrum {
    /// `max / min`: infinite when rank deficient.
    pub fn condition(&self) -> f64 {
        match self.min {
            Some(min) if min > 0.0 => self.max / min,
            _ => f64::INFINITY,
        }
    }
}

/// The most iterations of the power and the inverse iteration; each stops earlier once its
/// Rayleigh quotient changes by less than [`CONVERGED`] (relative).
const ITERATIONS: usize = 300;
const CONVERGED: f64 = 1e-6;

/// The [`Spectrum`] of the `d × d` symmetric positive semidefinite matrix `a` (row major, both
/// triangles), rank at the relative tolerance `tol`.
pub fn spectrum(a: &[f64], d: usize, tol: f64) -> Spectrum {
    assert_eq!(a.len(), d * d, "a is d × d");
    let max = largest(a, d);
    let (l, _, rank) = pivoted_cholesky(a, d, tol);
    let min = (rank == d && d > 0).then(|| smallest(&l, d));
    Spectrum { rank, max, min }
}

/// `L` (row major, the first `rank` columns), the permutation (`perm[i]`: the row of `a` at
/// position `i`) and the rank of `P a Pᵀ = L Lᵀ`, stopping at the first pivot below
/// `tol · max diag(a)`. Left-looking, so every inner product runs along rows of `L`.
fn pivoted_cholesky(a: &[f64], d: usize, tol: f64) -> (Vec<f64>, Vec<usize>, usize) {
    let mut perm: Vec<usize> = (0..d).collect();
    let mut diag: Vec<f64> = (0..d).map(|i| a[i * d + i]).collect();
    let top = diag.iter().copied().fold(0.0_f64, f64::max);
    let floor = tol * top;
    let mut l = vec![0.0; d * d];
    for j in 0..d {
        let (p, &best) = diag[j..]
            .iter()
            .enumerate()
            .max_by(|x, y| x.1.total_cmp(y.1))
            .map(|(i, v)| (i + j, v))
            .unwrap_or((j, &0.0));
        if best.is_nan() || best <= floor {
            return (l, perm, j);
        }
        perm.swap(j, p);
        diag.swap(j, p);
        for k in 0..j {
            l.swap(j * d + k, p * d + k);
        }
        let ljj = best.sqrt();
        l[j * d + j] = ljj;
        let (done, rest) = l.split_at_mut((j + 1) * d);
        let lj = &done[j * d..j * d + j];
        for (i, row) in (j + 1..d).zip(rest.chunks_exact_mut(d)) {
            let v = (a[perm[i] * d + perm[j]] - dot(&row[..j], lj)) / ljj;
            row[j] = v;
            diag[i] -= v * v;
        }
    }
    (l, perm, d)
}

/// The largest eigenvalue of `a` by power iteration from the all-ones vector (PSD: the
/// Rayleigh quotient rises to it).
fn largest(a: &[f64], d: usize) -> f64 {
    let x = vec![1.0 / (d.max(1) as f64).sqrt(); d];
    rayleigh(x, |x| a.chunks_exact(d).map(|row| dot(row, x)).collect()).unwrap_or(0.0)
}

/// The smallest eigenvalue of `a = Pᵀ L Lᵀ P` (that of `L Lᵀ`) by inverse iteration (solves
/// with `L`).
fn smallest(l: &[f64], d: usize) -> f64 {
    // In the permuted basis: (L Lᵀ)⁻¹ has the same eigenvalues as a⁻¹.
    let mut x: Vec<f64> = (0..d).map(|i| 1.0 + (i % 7) as f64 / 7.0).collect();
    let norm0 = x.iter().map(|v| v * v).sum::<f64>().sqrt();
    x.iter_mut().for_each(|v| *v /= norm0);
    let solve = |x: &[f64]| {
        // y = (L Lᵀ)⁻¹ x: forward with L, back with Lᵀ.
        let mut y = x.to_vec();
        for i in 0..d {
            let s = dot(&l[i * d..i * d + i], &y[..i]);
            y[i] = (y[i] - s) / l[i * d + i];
        }
        // Lᵀ by columns: the solved y[i] taken out of the rows above, row by row of L.
        for i in (0..d).rev() {
            y[i] /= l[i * d + i];
            let yi = y[i];
            for (yk, lik) in y[..i].iter_mut().zip(&l[i * d..i * d + i]) {
                *yk -= lik * yi;
            }
        }
        y
    };
    match rayleigh(x, solve) {
        Some(mu) if mu > 0.0 => 1.0 / mu,
        _ => 0.0,
    }
}

/// The Rayleigh quotient `xᵀ A x` of the iteration `x ← A x / ‖A x‖` from the unit vector `x`
/// (`apply` gives `A x`), until it changes by less than [`CONVERGED`] (relative) or for
/// [`ITERATIONS`]; `None` when `A x` vanishes or is not finite.
fn rayleigh(mut x: Vec<f64>, apply: impl Fn(&[f64]) -> Vec<f64>) -> Option<f64> {
    let mut quotient = 0.0;
    for _ in 0..ITERATIONS {
        let y = apply(&x);
        let next = dot(&x, &y);
        let norm = dot(&y, &y).sqrt();
        if !(norm.is_finite() && norm > 0.0) {
            return None;
        }
        x = y.into_iter().map(|v| v / norm).collect();
        let done = (next - quotient).abs() <= CONVERGED * next.abs();
        quotient = next;
        if done {
            break;
        }
    }
    Some(quotient)
}

/// `Σ x_k y_k` in four lanes (the compiler vectorises it; a plain fold it may not reorder).
fn dot(x: &[f64], y: &[f64]) -> f64 {
    let mut acc = [0.0; 4];
    let (xc, yc) = (x.chunks_exact(4), y.chunks_exact(4));
    let tail: f64 = xc
        .remainder()
        .iter()
        .zip(yc.remainder())
        .map(|(a, b)| a * b)
        .sum();
    for (a, b) in xc.zip(yc) {
        for k in 0..4 {
            acc[k] += a[k] * b[k];
        }
    }
    acc[0] + acc[1] + acc[2] + acc[3] + tail
}

#[cfg(test)]
mod tests {
    use super::spectrum;
    use nalgebra::DMatrix;

    /// A Gram `X Xᵀ` of fewer or more columns than rows: the rank, and the extreme eigenvalues
    /// against nalgebra's symmetric eigendecomposition (to 0.1 %: a check's threshold, not a
    /// decomposition).
    #[test]
    fn rank_and_extreme_eigenvalues_match_the_eigendecomposition() {
        let d = 30;
        for cols in [12, 30, 45] {
            let x = DMatrix::from_fn(d, cols, |i, j| {
                (((i * 31 + j * 17 + i * j) % 23) as f64 / 23.0 - 0.5) * (1.0 + (i % 5) as f64)
            });
            let g = &x * x.transpose();
            let flat: Vec<f64> = (0..d * d).map(|k| g[(k / d, k % d)]).collect();
            let s = spectrum(&flat, d, 1e-9);
            let ev = g.clone().symmetric_eigenvalues();
            let top = ev.max();
            let rank = ev.iter().filter(|&&v| v > 1e-9 * top).count();
            assert_eq!(s.rank, rank, "{cols} columns");
            assert!((s.max - top).abs() <= 1e-3 * top, "{} vs {top}", s.max);
            match s.min {
                Some(min) => {
                    let low = ev.min();
                    assert!((min - low).abs() <= 1e-3 * low, "{min} vs {low}");
                }
                None => assert!(rank < d),
            }
        }
    }
}
