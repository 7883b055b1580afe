//! Dense kernels on caller-owned slices: packed Cholesky, Householder QR and least squares,
//! and a bounded SVD for the small square matrices of the final steps.
//!
//! Matrices are column-major (`a[r + c * rows]`) except the packed symmetric Gram, stored
//! row-major lower-triangular (`row * (row + 1) / 2 + col`, `col <= row`), which keeps each
//! Cholesky dot product contiguous.

use nalgebra::SMatrix;

use crate::error::{Error, Stage};
use crate::scalar::Real;

/// Offset of `(row, col)`, `col <= row`, in a packed lower triangle.
#[inline]
pub(crate) fn packed(row: usize, col: usize) -> usize {
    row * (row + 1) / 2 + col
}

/// Length of a packed lower triangle of dimension `n`.
pub(crate) const fn packed_len(n: usize) -> usize {
    n * (n + 1) / 2
}

/// `s[i]`, or zero where `i` is out of range.
///
/// The solve's sizes are validated by `Identifier::new` and its workspace is carved by
/// `Layout`, so none of these fallbacks (`at`, [`set`], [`sub`], [`sub_mut`], [`el`],
/// [`set_el`]) ever applies; they keep every path of the solve free of bounds panics, which
/// `examples/panic-proof` proves at link time.
#[inline(always)]
pub(crate) fn at<T: Copy + Default>(s: &[T], i: usize) -> T {
    s.get(i).copied().unwrap_or_default()
}

/// `s[i] = v`, ignored where `i` is out of range (see [`at`]).
#[inline(always)]
pub(crate) fn set<T>(s: &mut [T], i: usize, v: T) {
    if let Some(x) = s.get_mut(i) {
        *x = v;
    }
}

/// `&s[from..to]`, or an empty slice where the range is not in `s` (see [`at`]).
#[inline(always)]
pub(crate) fn sub<T>(s: &[T], from: usize, to: usize) -> &[T] {
    s.get(from..to).unwrap_or(&[])
}

/// `&mut s[from..to]`, or an empty slice where the range is not in `s` (see [`at`]).
#[inline(always)]
pub(crate) fn sub_mut<T>(s: &mut [T], from: usize, to: usize) -> &mut [T] {
    s.get_mut(from..to).unwrap_or(&mut [])
}

/// `m[(r, c)]`, or zero outside the matrix (see [`at`]).
#[inline(always)]
pub(crate) fn el<T: Real, const H: usize>(m: &Small<T, H>, r: usize, c: usize) -> T {
    m.get((r, c)).copied().unwrap_or_default()
}

/// `m[(r, c)] = v`, ignored outside the matrix (see [`at`]).
#[inline(always)]
pub(crate) fn set_el<T: Real, const H: usize>(m: &mut Small<T, H>, r: usize, c: usize, v: T) {
    if let Some(x) = m.get_mut((r, c)) {
        *x = v;
    }
}

/// Dot product of two equal-length slices (of the shorter length if they differ).
///
/// The products are added one after the other, in order (the same result, bit for bit, as a
/// plain loop); the loop takes eight at a time, which spares the loop's bookkeeping per
/// element: the solve spends most of its time here.
#[inline]
pub(crate) fn dot<T: Real>(a: &[T], b: &[T]) -> T {
    let n = a.len().min(b.len());
    let (a, b) = (a.get(..n).unwrap_or(&[]), b.get(..n).unwrap_or(&[]));
    let (a8, a_rest) = a.as_chunks::<8>();
    let (b8, b_rest) = b.as_chunks::<8>();
    let mut s = T::zero();
    for (x, y) in a8.iter().zip(b8) {
        s += x[0] * y[0];
        s += x[1] * y[1];
        s += x[2] * y[2];
        s += x[3] * y[3];
        s += x[4] * y[4];
        s += x[5] * y[5];
        s += x[6] * y[6];
        s += x[7] * y[7];
    }
    for (&x, &y) in a_rest.iter().zip(b_rest) {
        s += x * y;
    }
    s
}

/// Four dot products of `a` with `b[0]`, …, `b[3]` (of the shortest length), each adding in
/// order as [`dot`] does (the same bits): `a` is read once for all four, which spares a third
/// of the loads of four separate products.
#[inline(always)]
pub(crate) fn dot4<T: Real>(a: &[T], b: [&[T]; 4]) -> [T; 4] {
    let [b0, b1, b2, b3] = b;
    let n = a
        .len()
        .min(b0.len())
        .min(b1.len())
        .min(b2.len())
        .min(b3.len());
    let ((a4, ar), (c0, r0), (c1, r1)) = (head4(a, n), head4(b0, n), head4(b1, n));
    let ((c2, r2), (c3, r3)) = (head4(b2, n), head4(b3, n));
    let mut s = [T::zero(); 4];
    for ((((x, y0), y1), y2), y3) in a4.iter().zip(c0).zip(c1).zip(c2).zip(c3) {
        mac4(&mut s, x[0], [y0[0], y1[0], y2[0], y3[0]]);
        mac4(&mut s, x[1], [y0[1], y1[1], y2[1], y3[1]]);
        mac4(&mut s, x[2], [y0[2], y1[2], y2[2], y3[2]]);
        mac4(&mut s, x[3], [y0[3], y1[3], y2[3], y3[3]]);
    }
    for ((((&x, &y0), &y1), &y2), &y3) in ar.iter().zip(r0).zip(r1).zip(r2).zip(r3) {
        mac4(&mut s, x, [y0, y1, y2, y3]);
    }
    s
}

/// The first `n` entries of `x` in chunks of four, and the rest (empty if `x` is shorter).
#[inline(always)]
fn head4<T>(x: &[T], n: usize) -> (&[[T; 4]], &[T]) {
    x.get(..n).unwrap_or(&[]).as_chunks::<4>()
}

/// `s[c] += x · y[c]` for the four sums of [`dot4`].
#[inline(always)]
fn mac4<T: Real>(s: &mut [T; 4], x: T, y: [T; 4]) {
    s[0] += x * y[0];
    s[1] += x * y[1];
    s[2] += x * y[2];
    s[3] += x * y[3];
}

/// What the Cholesky factorisation found in a row.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Pivot {
    /// Rows `0..strict` must have pivots above `rel_tol` times their original diagonal.
    Deficient(usize),
}

/// In-place Cholesky `G = L Lᵀ` of a packed symmetric matrix of dimension `n`.
///
/// Rows `0..strict` must be positive definite (a pivot below `rel_tol` times the original
/// diagonal is reported as rank deficiency at that row). Rows from `strict` on may be
/// semi-definite: a pivot there at or below `floor[i − strict]` (zero where `floor` is
/// shorter: the rounding level of that row, below which the pivot is noise) is set to zero
/// together with the entries that would divide by it, which is the exact factor of a
/// singular residual block.
pub(crate) fn cholesky_packed<T: Real>(
    g: &mut [T],
    n: usize,
    strict: usize,
    rel_tol: T,
    floor: &[T],
) -> Result<(), Pivot> {
    for i in 0..n {
        let ri = packed(i, 0);
        // Entries left of the diagonal four at a time, the rest (and the pivot) one by one.
        let mut j0 = 0;
        while j0 + 4 <= i {
            let (head, row_i) = g.split_at_mut_checked(ri).unwrap_or((&mut [], &mut []));
            off_diagonal4(head, row_i, j0);
            j0 += 4;
        }
        for j in j0..=i {
            let rj = packed(j, 0);
            let (head, row_i) = g.split_at_mut_checked(ri).unwrap_or((&mut [], &mut []));
            let s = {
                let li = sub(row_i, 0, j);
                let lj: &[T] = if j == i { li } else { sub(head, rj, rj + j) };
                at(row_i, j) - dot(li, lj)
            };
            if j == i {
                let orig = at(row_i, j);
                if i < strict {
                    let positive = s > rel_tol * orig && s.finite();
                    if !positive {
                        return Err(Pivot::Deficient(i));
                    }
                    set(row_i, j, s.sqrt());
                } else {
                    let fl = floor.get(i - strict).copied().unwrap_or_default();
                    let keep = s > fl.max(T::zero());
                    set(row_i, j, if keep { s.sqrt() } else { T::zero() });
                }
            } else {
                let d = at(head, rj + j);
                set(row_i, j, if d > T::zero() { s / d } else { T::zero() });
            }
        }
    }
    Ok(())
}

/// Entries `j0 .. j0 + 4` (all left of the diagonal) of row `row_i` of the Cholesky factor,
/// the rows above it in `head`: the products over the first `j0` columns four at a time
/// ([`dot4`]), then each entry's remaining products in order, so every entry has the bits of
/// the one-by-one loop in [`cholesky_packed`].
#[inline(always)]
fn off_diagonal4<T: Real>(head: &[T], row_i: &mut [T], j0: usize) {
    let row = |r: usize| sub(head, packed(r, 0), packed(r, 0) + r + 1);
    let rows = [row(j0), row(j0 + 1), row(j0 + 2), row(j0 + 3)];
    let prefix = rows.map(|r| r.get(..j0).unwrap_or(&[]));
    let mut acc = dot4(sub(row_i, 0, j0), prefix);
    for (c, (lj, sum)) in rows.iter().zip(acc.iter_mut()).enumerate() {
        let j = j0 + c;
        for k in j0..j {
            *sum += at(row_i, k) * at(lj, k);
        }
        let d = at(lj, j);
        let s = at(row_i, j) - *sum;
        set(row_i, j, if d > T::zero() { s / d } else { T::zero() });
    }
}

/// Applies the reflector `I − t v vᵀ` (`v = [1; v[1..]]`, `v[0]` not read) to `y`.
#[inline]
fn reflect<T: Real>(v: &[T], t: T, y: &mut [T]) {
    let (Some((_, vt)), Some((y0, yt))) = (v.split_first(), y.split_first_mut()) else {
        return;
    };
    let s = (*y0 + dot(vt, yt)) * t;
    *y0 -= s;
    for (yi, &vi) in yt.iter_mut().zip(vt) {
        *yi -= s * vi;
    }
}

/// Householder QR of the column-major `rows × cols` matrix `a` (`rows >= cols`), in place:
/// `R` in the upper triangle, reflectors below it with scalars in `tau` (length `cols`).
pub(crate) fn householder_qr<T: Real>(a: &mut [T], rows: usize, cols: usize, tau: &mut [T]) {
    for k in 0..cols.min(rows) {
        let x = sub_mut(a, k * rows + k, (k + 1) * rows);
        let Some((x0, tail)) = x.split_first_mut() else {
            set(tau, k, T::zero());
            continue;
        };
        let alpha = *x0;
        let norm_tail = dot(tail, tail);
        if norm_tail == T::zero() {
            set(tau, k, T::zero());
            continue;
        }
        let norm = (alpha * alpha + norm_tail).sqrt();
        let beta = if alpha >= T::zero() { -norm } else { norm };
        let v0 = alpha - beta;
        for v in tail.iter_mut() {
            *v /= v0;
        }
        *x0 = beta;
        let t = (beta - alpha) / beta;
        set(tau, k, t);
        // Apply H = I - t v vᵀ (v = [1; x[1..]]) to the remaining columns.
        for c in (k + 1)..cols {
            let (left, right) = a
                .split_at_mut_checked(c * rows)
                .unwrap_or((&mut [], &mut []));
            reflect(
                sub(left, k * rows + k, (k + 1) * rows),
                t,
                sub_mut(right, k, rows),
            );
        }
    }
}

/// Applies `Qᵀ` (from [`householder_qr`]) to the column-major `rows × nrhs` matrix `b`.
pub(crate) fn apply_qt<T: Real>(
    a: &[T],
    rows: usize,
    cols: usize,
    tau: &[T],
    b: &mut [T],
    nrhs: usize,
) {
    for k in 0..cols.min(rows) {
        let v = sub(a, k * rows + k, (k + 1) * rows);
        let t = at(tau, k);
        if t == T::zero() {
            continue;
        }
        for c in 0..nrhs {
            reflect(v, t, sub_mut(b, c * rows + k, (c + 1) * rows));
        }
    }
}

/// Applies `Q` (from [`householder_qr`]) to the vector `x` of length `rows`.
pub(crate) fn apply_q<T: Real>(a: &[T], rows: usize, cols: usize, tau: &[T], x: &mut [T]) {
    for k in (0..cols.min(rows)).rev() {
        let v = sub(a, k * rows + k, (k + 1) * rows);
        reflect(v, at(tau, k), sub_mut(x, k, rows));
    }
}

/// Least squares `min ‖A X − B‖` for column-major `A` (`rows × cols`, `rows >= cols`) and
/// `B` (`rows × nrhs`), both overwritten; the solution is left in the first `cols` rows of
/// each column of `b`. The columns of `A` are scaled to unit norm first (and the solution
/// back), so that the rank test does not depend on their units: it fails if the scaled `R`
/// has a diagonal entry below `rel_tol · max|R_ii|`, or `A` has a zero column or more than
/// more than `H` columns (the solve's horizon capacity: its problems have at most `f` columns).
pub(crate) fn least_squares<T: Real, const H: usize>(
    a: &mut [T],
    rows: usize,
    cols: usize,
    b: &mut [T],
    nrhs: usize,
    tau: &mut [T],
    rel_tol: T,
) -> Result<(), ()> {
    if rows < cols || cols > H {
        return Err(());
    }
    let mut scale = [T::one(); H];
    for (k, sc) in scale.iter_mut().enumerate().take(cols) {
        let col = sub_mut(a, k * rows, (k + 1) * rows);
        // By the largest entry first, so that the squares cannot overflow.
        let big = col.iter().fold(T::zero(), |m, v| m.max(v.abs()));
        if !(big > T::zero() && big.finite()) {
            return Err(());
        }
        for v in col.iter_mut() {
            *v /= big;
        }
        let norm = dot(col, col).sqrt();
        for v in col.iter_mut() {
            *v /= norm;
        }
        *sc = big * norm;
    }
    householder_qr(a, rows, cols, tau);
    let mut rmax = T::zero();
    for k in 0..cols {
        rmax = rmax.max(at(a, k * rows + k).abs());
    }
    for k in 0..cols {
        let d = at(a, k * rows + k).abs();
        let independent = d > rel_tol * rmax && d.finite();
        if !independent {
            return Err(());
        }
    }
    apply_qt(a, rows, cols, tau, b, nrhs);
    for c in 0..nrhs {
        let x = sub_mut(b, c * rows, c * rows + cols);
        for i in (0..cols).rev() {
            let mut s = at(x, i);
            for j in (i + 1)..cols {
                s -= at(a, j * rows + i) * at(x, j);
            }
            set(x, i, s / at(a, i * rows + i));
        }
        for (v, &sc) in x.iter_mut().zip(&scale) {
            *v /= sc;
        }
    }
    Ok(())
}

/// A square matrix of at most `H` rows (the horizon capacity), padded with zeros. Every
/// kernel below works on a leading `n × n` block only, so the padding never enters a result:
/// the same data give the same bits whatever `H >= n`.
pub(crate) type Small<T, const H: usize> = SMatrix<T, H, H>;

/// Left singular vectors, singular values (descending) and right singular vectors.
pub(crate) type Svd<T, const H: usize> = (Small<T, H>, [T; H], Small<T, H>);

/// `true` if every entry of `m` is finite.
pub(crate) fn all_finite<T: Real>(m: &[T]) -> bool {
    m.iter().all(|v| v.finite())
}

/// The first `n` rows of columns `p < q` of `m`, both mutable (empty outside the matrix).
fn columns<T: Real, const H: usize>(
    m: &mut Small<T, H>,
    p: usize,
    q: usize,
    n: usize,
) -> (&mut [T], &mut [T]) {
    let (left, right) = m
        .as_mut_slice()
        .split_at_mut_checked(q * H)
        .unwrap_or((&mut [], &mut []));
    (sub_mut(left, p * H, p * H + n), sub_mut(right, 0, n))
}

/// Sweeps of the one-sided Jacobi SVD before [`Error::NoConvergence`]: it converges
/// quadratically, in 5–10 sweeps for the matrices of the solve.
pub(crate) const JACOBI_SWEEPS: usize = 64;

/// Singular values (descending) and left/right singular vectors of the leading `n × n` block
/// of `m` (the rest is ignored), by one-sided Jacobi rotations (Hestenes): the columns of
/// `m V` are made orthogonal, their norms are the singular values and their directions the
/// left singular vectors. Every singular value is computed to high relative accuracy, the
/// small ones included, which the rank decisions of the solve rely on. (nalgebra's
/// bidiagonal SVD was used before; it can lose all accuracy on matrices with small non-zero
/// singular values, e.g. a 2 × 2 rank-one split with σ₂/σ₁ = 1e-14 gave a first left singular
/// vector off by 2e-2: nalgebra issue #1172.)
///
/// Sweeps are bounded by [`JACOBI_SWEEPS`]. A matrix with a non-finite entry is
/// [`Error::Overflow`] at `stage` (the sums it comes from overflowed), sweeps that did not
/// suffice [`Error::NoConvergence`]. Left singular vectors of zero singular values are zero;
/// without `want_v` the right singular vectors are not accumulated (the identity is returned).
pub(crate) fn svd_small<T: Real, const H: usize>(
    a: Small<T, H>,
    n: usize,
    stage: Stage,
    want_v: bool,
) -> Result<Svd<T, H>, Error> {
    svd_small_bounded(a, n, stage, want_v, JACOBI_SWEEPS)
}

/// [`svd_small`] with at most `sweeps` sweeps.
fn svd_small_bounded<T: Real, const H: usize>(
    mut a: Small<T, H>,
    n: usize,
    stage: Stage,
    want_v: bool,
    sweeps: usize,
) -> Result<Svd<T, H>, Error> {
    let mut v = Small::<T, H>::identity();
    let s = svd_in_place_bounded(&mut a, want_v.then_some(&mut v), n, stage, sweeps)?;
    Ok((a, s, v))
}

/// [`svd_small`] in place, for callers short of stack: `a` becomes `U`, `v` (if given, the
/// identity on entry) `V`; returns the singular values.
pub(crate) fn svd_in_place<T: Real, const H: usize>(
    a: &mut Small<T, H>,
    v: Option<&mut Small<T, H>>,
    n: usize,
    stage: Stage,
) -> Result<[T; H], Error> {
    svd_in_place_bounded(a, v, n, stage, JACOBI_SWEEPS)
}

/// [`svd_in_place`] with at most `sweeps` sweeps.
fn svd_in_place_bounded<T: Real, const H: usize>(
    a: &mut Small<T, H>,
    mut v: Option<&mut Small<T, H>>,
    n: usize,
    stage: Stage,
    sweeps: usize,
) -> Result<[T; H], Error> {
    if !all_finite(a.as_slice()) {
        return Err(Error::Overflow { stage });
    }
    let n = n.min(H);
    let tol = T::EPS * T::of_usize(n.max(1));
    let big = T::one() / T::EPS.sqrt();
    let mut converged = false;
    for _ in 0..sweeps {
        let mut rotated = false;
        for p in 0..n {
            for q in (p + 1)..n {
                let (mut alpha, mut beta, mut gamma) = (T::zero(), T::zero(), T::zero());
                let (cp, cq) = columns(a, p, q, n);
                for (&ap, &aq) in cp.iter().zip(cq.iter()) {
                    alpha += ap * ap;
                    beta += aq * aq;
                    gamma += ap * aq;
                }
                if gamma == T::zero() || gamma.abs() <= tol * alpha.sqrt() * beta.sqrt() {
                    continue;
                }
                rotated = true;
                let zeta = (beta - alpha) / (gamma + gamma);
                let t = if zeta.abs() > big {
                    T::one() / (zeta + zeta)
                } else {
                    let r = T::one() / (zeta.abs() + (T::one() + zeta * zeta).sqrt());
                    if zeta >= T::zero() { r } else { -r }
                };
                let c = T::one() / (T::one() + t * t).sqrt();
                let s = c * t;
                for (ap, aq) in cp.iter_mut().zip(cq.iter_mut()) {
                    (*ap, *aq) = (c * *ap - s * *aq, s * *ap + c * *aq);
                }
                if let Some(v) = v.as_deref_mut() {
                    let (vp, vq) = columns(v, p, q, n);
                    for (vp, vq) in vp.iter_mut().zip(vq.iter_mut()) {
                        (*vp, *vq) = (c * *vp - s * *vq, s * *vp + c * *vq);
                    }
                }
            }
        }
        if !rotated {
            converged = true;
            break;
        }
    }
    if !converged {
        return Err(Error::NoConvergence { stage });
    }
    let mut s = [T::zero(); H];
    for (c, sc) in s.iter_mut().enumerate().take(n) {
        let mut norm = T::zero();
        for r in 0..n {
            norm += a[(r, c)] * a[(r, c)];
        }
        *sc = norm.sqrt();
    }
    if !all_finite(&s) {
        return Err(Error::Overflow { stage });
    }
    // Descending order (selection sort, moving the columns of a and v along).
    for i in 0..n {
        let mut k = i;
        for j in (i + 1)..n {
            if at(&s, j) > at(&s, k) {
                k = j;
            }
        }
        if k != i && k < n {
            s.swap(i, k);
            a.swap_columns(i, k);
            if let Some(v) = v.as_deref_mut() {
                v.swap_columns(i, k);
            }
        }
    }
    // U: the columns over their norms (zero columns stay zero), and nothing outside n × n.
    for c in 0..H {
        let sc = at(&s, c);
        for r in 0..H {
            let x = a[(r, c)];
            a[(r, c)] = if c < n && r < n && sc > T::zero() {
                x / sc
            } else {
                T::zero()
            };
        }
    }
    Ok(s)
}

/// Squarings of [`spectral_radius`]: `‖A^N‖^{1/N}` with `N = 2^24`.
pub(crate) const SPECTRAL_SQUARINGS: usize = 24;

/// Spectral radius of the leading `n × n` block of `a` by Gelfand's formula
/// `ρ(A) = lim ‖A^N‖^{1/N}`, with `N = 2^`[`SPECTRAL_SQUARINGS`] reached by repeated squaring,
/// the matrix rescaled to a largest entry of 1 before each squaring (no overflow) and the
/// logarithms of the scales accumulated in `f64`. A bounded computation without iterations
/// to converge: the estimate is `ρ · c^{1/N}` with `c` the conditioning of `A`'s eigenvector
/// basis, so within a relative 1e-5 of ρ for any `c` below 1e30. A nilpotent matrix gives 0.
#[inline(never)]
pub(crate) fn spectral_radius<T: Real, const H: usize>(a: &Small<T, H>, n: usize) -> f64 {
    let n = n.min(H);
    let mut b = Small::<T, H>::zeros();
    for c in 0..n {
        for r in 0..n {
            b[(r, c)] = a[(r, c)];
        }
    }
    let mut log_rho = 0.0f64;
    let mut weight = 1.0f64;
    for _ in 0..SPECTRAL_SQUARINGS {
        let big = b.iter().fold(T::zero(), |m, v| m.max(v.abs()));
        if !(big > T::zero() && big.finite()) {
            return if big == T::zero() { 0.0 } else { f64::INFINITY };
        }
        log_rho += weight * libm::log(big.to_f64());
        b /= big;
        // b ← b², on the leading n × n block only.
        let mut sq = Small::<T, H>::zeros();
        for c in 0..n {
            for k in 0..n {
                let bkc = b[(k, c)];
                if bkc != T::zero() {
                    for r in 0..n {
                        sq[(r, c)] += b[(r, k)] * bkc;
                    }
                }
            }
        }
        b = sq;
        weight *= 0.5;
    }
    let big = b.iter().fold(T::zero(), |m, v| m.max(v.abs()));
    if big > T::zero() {
        log_rho += weight * libm::log(big.to_f64());
        libm::exp(log_rho)
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The unrolled dot product adds in the plain loop's order: equal bits for every length
    /// around the unrolling (values of mixed magnitude, so another order would round apart).
    #[test]
    fn dot_adds_in_order() {
        let a: [f32; 21] = core::array::from_fn(|i| {
            libm::sinf(i as f32 * 0.73) * libm::powf(10.0, (i % 7) as f32 - 3.0)
        });
        let b: [f32; 21] = core::array::from_fn(|i| libm::cosf(i as f32 * 1.31) + 0.1);
        for n in 0..=21 {
            let plain = a
                .iter()
                .zip(&b)
                .take(n)
                .fold(0.0f32, |s, (&x, &y)| s + x * y);
            assert_eq!(
                dot(&a[..n], &b[..n]).to_bits(),
                plain.to_bits(),
                "length {n}"
            );
        }
        // Unequal lengths: the shorter one.
        assert_eq!(dot(&a[..5], &b).to_bits(), dot(&a[..5], &b[..5]).to_bits());
        // Four at a time: each the bits of its own dot product.
        let (c, d) = (&a[1..], &b[2..]);
        for n in 0..=19 {
            let four = dot4(&b[..n], [&a[..n], c, d, &b[..n]]);
            let one = [
                dot(&b[..n], &a[..n]),
                dot(&b[..n], c),
                dot(&b[..n], d),
                dot(&b[..n], &b[..n]),
            ];
            assert_eq!(four.map(f32::to_bits), one.map(f32::to_bits), "length {n}");
        }
    }

    fn small(n: usize, entries: &[f64]) -> Small<f64, 12> {
        let mut m = Small::<f64, 12>::zeros();
        for r in 0..n {
            for c in 0..n {
                m[(r, c)] = entries[r * n + c];
            }
        }
        m
    }

    #[test]
    fn spectral_radius_of_known_matrices() {
        // (matrix, n, ρ): a complex pair 0.9 e^{±0.5j} (rotation), a real pair with the
        // larger pole negative, a non-normal matrix (ρ 0.5, a large off-diagonal), a Jordan
        // block at 1 (integrator), an unstable pole, a nilpotent matrix.
        let (c, s) = (0.9 * 0.5f64.cos(), 0.9 * 0.5f64.sin());
        let cases: [(&[f64], usize, f64); 6] = [
            (&[c, -s, s, c], 2, 0.9),
            (&[0.5, 0.0, 0.0, -0.95], 2, 0.95),
            (&[0.5, 1e4, 0.0, 0.5], 2, 0.5),
            (&[1.0, 1.0, 0.0, 1.0], 2, 1.0),
            (
                &[1.2, 0.3, 0.1, 0.4, 0.2, 0.0, 0.0, 0.0, -0.3],
                3,
                1.308_276_253,
            ),
            (&[0.0, 1.0, 0.0, 0.0], 2, 0.0),
        ];
        for (entries, n, rho) in cases {
            let got = spectral_radius(&small(n, entries), n);
            assert!(
                (got - rho).abs() <= 1e-4 * rho.max(1e-300),
                "{entries:?}: {got}, want {rho}"
            );
        }
        // The integrator is not below 1 (the solve refuses ρ >= 1).
        assert!(spectral_radius(&small(2, &[1.0, 1.0, 0.0, 1.0]), 2) >= 1.0);
    }

    /// A sweep bound that does not suffice is `NoConvergence` at the caller's stage, never a
    /// panic or a half-converged result; the bound the solve uses converges on the same
    /// matrix, in a few sweeps, and the result reconstructs it.
    #[test]
    #[allow(clippy::unwrap_used)]
    fn jacobi_svd_out_of_sweeps_is_no_convergence() {
        let entries = [
            4.0, 1.0, -2.0, 0.5, //
            1.0, 3.0, 0.7, -1.0, //
            -2.0, 0.7, 5.0, 2.0, //
            0.5, -1.0, 2.0, 1.5,
        ];
        let a = small(4, &entries);
        for sweeps in [0, 1] {
            assert_eq!(
                svd_small_bounded(a, 4, Stage::Projection, true, sweeps).err(),
                Some(Error::NoConvergence {
                    stage: Stage::Projection
                }),
                "{sweeps} sweep(s)"
            );
        }
        let first_ok = (1..=JACOBI_SWEEPS)
            .find(|&k| svd_small_bounded(a, 4, Stage::Projection, true, k).is_ok())
            .unwrap_or(usize::MAX);
        assert!(
            (2..=10).contains(&first_ok),
            "converged after {first_ok} sweeps"
        );
        let (u, s, v) = svd_small(a, 4, Stage::Projection, true).unwrap();
        for r in 0..4 {
            for c in 0..4 {
                let x: f64 = (0..4).map(|k| u[(r, k)] * s[k] * v[(c, k)]).sum();
                assert!((x - entries[r * 4 + c]).abs() < 1e-12, "({r}, {c}): {x}");
            }
        }
    }
}
