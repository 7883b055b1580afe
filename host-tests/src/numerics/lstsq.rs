//! Linear least squares `min ‖X θ − y‖` through the normal equations `XᵀX θ = Xᵀy`: solved by
//! Cholesky, optionally equilibrated (scaled to a unit diagonal) first ([`lstsq`]), or
//! equilibrated and solved by a symmetric eigendecomposition for the minimum-norm solution of a
//! rank-deficient `X` ([`lstsq_min_norm`]).

use nalgebra::{DMatrix, DVector};

/// How the normal equations are scaled before the Cholesky factorisation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Scaling {
    /// As they are.
    None,
    /// Scaled to a unit diagonal (`S G S`, `S = diag(G)^-1/2`): columns of very different
    /// sizes (e.g. hat regressors next to filtered inputs) lose no precision.
    UnitDiagonal,
}

/// Solves `G θ = r` for a symmetric positive definite Gram matrix `G`; `None` if the Cholesky
/// factorisation meets a non-positive pivot (e.g. a column without information). Collinear
/// columns whose rounding leaves a tiny positive pivot are not detected here.
pub(crate) fn solve_normal(
    g: &DMatrix<f64>,
    r: &DVector<f64>,
    scaling: Scaling,
) -> Option<DVector<f64>> {
    match scaling {
        Scaling::None => g.clone().cholesky().map(|c| c.solve(r)),
        Scaling::UnitDiagonal => {
            let k = g.nrows();
            let s: Vec<f64> = (0..k).map(|i| 1.0 / g[(i, i)].max(1e-300).sqrt()).collect();
            let gs = DMatrix::from_fn(k, k, |i, j| g[(i, j)] * s[i] * s[j]);
            let rs = DVector::from_fn(k, |i, _| r[i] * s[i]);
            let x = gs.cholesky()?.solve(&rs);
            Some(DVector::from_fn(k, |i, _| x[i] * s[i]))
        }
    }
}

/// Least squares for a matrix `X`; `None` if `XᵀX` is singular.
pub fn lstsq(x: &DMatrix<f64>, y: &DVector<f64>, scaling: Scaling) -> Option<DVector<f64>> {
    let g = x.tr_mul(x);
    let r = x.tr_mul(y);
    solve_normal(&g, &r, scaling)
}

/// Rows of `X` gathered before their products are added in [`normal_by_rows`].
const ROW_BLOCK: usize = 1024;

/// The normal equations `(XᵀX, Xᵀy)` of a regression given a row at a time: `row(t, x)` writes
/// row `t` of `X` (`k` values) into `x` and returns `y(t)`, for `t` in `0..rows`. The rows are
/// gathered in blocks and each block's products added by a matrix product: no `rows × k`
/// matrix is formed.
pub(crate) fn normal_by_rows(
    rows: usize,
    k: usize,
    mut row: impl FnMut(usize, &mut [f64]) -> f64,
) -> (DMatrix<f64>, DVector<f64>) {
    let mut g = DMatrix::<f64>::zeros(k, k);
    let mut b = DVector::<f64>::zeros(k);
    let mut block = DMatrix::<f64>::zeros(ROW_BLOCK.min(rows.max(1)), k);
    let mut yb = DVector::<f64>::zeros(block.nrows());
    let mut x = vec![0.0; k];
    let mut filled = 0;
    for t in 0..rows {
        yb[filled] = row(t, &mut x);
        block.row_mut(filled).copy_from_slice(&x);
        filled += 1;
        if filled == block.nrows() || t + 1 == rows {
            let (xb, y) = (block.rows(0, filled), yb.rows(0, filled));
            g.gemm_tr(1.0, &xb, &xb, 1.0);
            b.gemv_tr(1.0, &xb, &y, 1.0);
            filled = 0;
        }
    }
    (g, b)
}

/// The minimum-norm solution of normal equations `(G, b)` equilibrated to a unit diagonal
/// first (what [`lstsq_min_norm`] solves); `None` if they are not finite or the
/// decomposition does not converge.
pub(crate) fn solve_normal_min_norm(g: &DMatrix<f64>, b: &DVector<f64>) -> Option<DVector<f64>> {
    let k = g.nrows();
    if g.iter().chain(b.iter()).any(|v| !v.is_finite()) {
        return None;
    }
    let scale: Vec<f64> = (0..k)
        .map(|i| {
            let d = g[(i, i)].sqrt();
            if d > 0.0 { 1.0 / d } else { 0.0 }
        })
        .collect();
    let gs = DMatrix::from_fn(k, k, |i, j| g[(i, j)] * scale[i] * scale[j]);
    let bs = DVector::from_fn(k, |i, _| b[i] * scale[i]);
    let beta = solve_min_norm(gs, &bs)?;
    Some(DVector::from_fn(k, |i, _| beta[i] * scale[i]))
}

/// Least squares for `X` given by its columns; `None` if `XᵀX` is singular.
pub(crate) fn lstsq_columns(cols: &[Vec<f64>], y: &[f64], scaling: Scaling) -> Option<Vec<f64>> {
    let k = cols.len();
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(a, b)| a * b).sum::<f64>();
    let g = DMatrix::from_fn(k, k, |i, j| dot(&cols[i], &cols[j]));
    let r = DVector::from_fn(k, |i, _| dot(&cols[i], y));
    solve_normal(&g, &r, scaling).map(|x| x.iter().copied().collect())
}

/// Dot product with four accumulators (vectorises).
pub fn dot(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len());
    let (a, b) = (&a[..n], &b[..n]);
    let mut s = [0.0f64; 4];
    let chunks = n / 4;
    for c in 0..chunks {
        let i = 4 * c;
        s[0] += a[i] * b[i];
        s[1] += a[i + 1] * b[i + 1];
        s[2] += a[i + 2] * b[i + 2];
        s[3] += a[i + 3] * b[i + 3];
    }
    let mut tail = 0.0;
    for i in 4 * chunks..n {
        tail += a[i] * b[i];
    }
    (s[0] + s[1]) + (s[2] + s[3]) + tail
}

/// Least squares `min ‖X β − y‖` through the equilibrated normal equations, solved by a
/// symmetric eigendecomposition with eigenvalues below `1e-13` of the largest left out
/// (a minimum-norm solution for rank-deficient `X`); `None` if not solvable. `O(N k²)` for
/// `N × k` data, which is what the diagnosis needs (tall, small `k`).
pub fn lstsq_min_norm(x: &DMatrix<f64>, y: &DVector<f64>) -> Option<DVector<f64>> {
    let (n, k) = (x.nrows(), x.ncols());
    if n == 0 || k == 0 || n != y.len() {
        return None;
    }
    if x.iter().chain(y.iter()).any(|v| !v.is_finite()) {
        return None;
    }
    // Column-major storage: column i is data[i n .. (i + 1) n].
    let data = x.as_slice();
    let col = |i: usize| &data[i * n..(i + 1) * n];
    let mut g = DMatrix::<f64>::zeros(k, k);
    for i in 0..k {
        for j in i..k {
            let v = dot(col(i), col(j));
            g[(i, j)] = v;
            g[(j, i)] = v;
        }
    }
    let b = DVector::from_fn(k, |i, _| dot(col(i), y.as_slice()));
    solve_normal_min_norm(&g, &b)
}

/// The minimum-norm solution of `G x = b` for a symmetric positive semi-definite `G`, by a
/// symmetric eigendecomposition with eigenvalues below `1e-13` of the largest left out; zero
/// when `G` has no positive eigenvalue, `None` if the decomposition does not converge.
pub(crate) fn solve_min_norm(g: DMatrix<f64>, b: &DVector<f64>) -> Option<DVector<f64>> {
    let k = g.nrows();
    let eig = nalgebra::SymmetricEigen::try_new(g, f64::EPSILON, 10_000)?;
    let max = eig.eigenvalues.iter().fold(0.0f64, |a, &v| a.max(v));
    let positive = max > 0.0;
    if !positive {
        return Some(DVector::zeros(k));
    }
    let qtb = eig.eigenvectors.tr_mul(b);
    let mut z = DVector::zeros(k);
    for i in 0..k {
        let l = eig.eigenvalues[i];
        if l > 1e-13 * max {
            z[i] = qtb[i] / l;
        }
    }
    Some(&eig.eigenvectors * z)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A tall system with a known exact solution plus a residual orthogonal to the columns.
    fn system() -> (DMatrix<f64>, DVector<f64>, [f64; 3]) {
        let n = 40;
        // Columns of very different scales: 1, t, 1000 sin t.
        let x = DMatrix::from_fn(n, 3, |t, j| {
            let t = t as f64;
            match j {
                0 => 1.0,
                1 => t,
                _ => 1000.0 * (0.3 * t).sin(),
            }
        });
        let theta = [0.5, -0.25, 0.002];
        let y = &x * DVector::from_column_slice(&theta);
        (x, y, theta)
    }

    #[test]
    fn recovers_an_exact_solution_with_and_without_scaling() {
        let (x, y, theta) = system();
        for scaling in [Scaling::None, Scaling::UnitDiagonal] {
            let got = lstsq(&x, &y, scaling).unwrap_or_else(|| DVector::zeros(3));
            for (g, t) in got.iter().zip(theta) {
                assert!((g - t).abs() < 1e-9 * (1.0 + t.abs()), "{scaling:?}: {got}");
            }
        }
    }

    #[test]
    fn agrees_with_an_svd_solution_on_noisy_data() {
        let (x, mut y, _) = system();
        // A deterministic disturbance: the least-squares solution is no longer exact.
        for (t, v) in y.iter_mut().enumerate() {
            *v += 0.1 * ((7 * t % 11) as f64 - 5.0);
        }
        let svd = x
            .clone()
            .svd(true, true)
            .solve(&y, 1e-14)
            .unwrap_or_else(|_| DVector::zeros(3));
        let cols: Vec<Vec<f64>> = (0..3)
            .map(|j| x.column(j).iter().copied().collect())
            .collect();
        let by_cols = lstsq_columns(&cols, y.as_slice(), Scaling::UnitDiagonal).unwrap_or_default();
        let by_matrix = lstsq(&x, &y, Scaling::None).unwrap_or_else(|| DVector::zeros(3));
        for j in 0..3 {
            assert!(
                (by_cols[j] - svd[j]).abs() < 1e-8 * (1.0 + svd[j].abs()),
                "{by_cols:?} {svd}"
            );
            assert!(
                (by_matrix[j] - svd[j]).abs() < 1e-8 * (1.0 + svd[j].abs()),
                "{by_matrix} {svd}"
            );
        }
    }

    #[test]
    fn a_column_without_information_is_refused() {
        // A zero column: the Gram matrix has a zero pivot, with and without scaling.
        let x = DMatrix::from_fn(10, 2, |t, j| if j == 0 { t as f64 } else { 0.0 });
        let y = DVector::from_fn(10, |t, _| t as f64);
        assert!(lstsq(&x, &y, Scaling::None).is_none());
        assert!(lstsq(&x, &y, Scaling::UnitDiagonal).is_none());
        let cols = vec![vec![1.0; 5], vec![0.0; 5]];
        assert!(lstsq_columns(&cols, &[1.0; 5], Scaling::UnitDiagonal).is_none());
    }
    #[test]
    fn the_minimum_norm_solution_splits_a_repeated_column_evenly() {
        // y = 2 t from the columns (t, t): every (a, 2 − a) fits; the smallest is (1, 1).
        let x = DMatrix::from_fn(20, 2, |t, _| t as f64 + 1.0);
        let y = DVector::from_fn(20, |t, _| 2.0 * (t as f64 + 1.0));
        let b = lstsq_min_norm(&x, &y).unwrap_or_else(|| DVector::zeros(2));
        assert!(
            (b[0] - 1.0).abs() < 1e-9 && (b[1] - 1.0).abs() < 1e-9,
            "{b}"
        );
        // A full-rank system: the one solution.
        let (x, y, theta) = system();
        let b = lstsq_min_norm(&x, &y).unwrap_or_else(|| DVector::zeros(3));
        for (g, t) in b.iter().zip(theta) {
            assert!((g - t).abs() < 1e-8 * (1.0 + t.abs()), "{b}");
        }
        // Nothing to fit: zero.
        assert_eq!(
            lstsq_min_norm(&DMatrix::zeros(5, 2), &DVector::zeros(5)),
            Some(DVector::zeros(2))
        );
    }
}
