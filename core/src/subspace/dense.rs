//! Small dense `H × H` helpers of the weightings: the Cholesky factor, lower-triangular
//! solves, `A Aᵀ`, `A B`, and columns scaled by square roots of singular values.

use crate::linalg::Small;
use crate::scalar::Real;

/// Columns `i < f` of `t` times `√s_i`, in place.
pub(super) fn scale_columns_in_place<T: Real, const H: usize>(
    t: &mut Small<T, H>,
    s: &[T; H],
    f: usize,
) {
    let f = f.min(H);
    for (c, &sc) in s.iter().enumerate().take(f) {
        let w = sc.sqrt();
        for r in 0..f {
            t[(r, c)] *= w;
        }
    }
}

/// Columns `i < f` of `t` times `√s_i` (`s` raw singular values times `scale`).
pub(super) fn scale_columns<T: Real, const H: usize>(
    mut t: Small<T, H>,
    s: &[T; H],
    f: usize,
    scale: T,
) -> Small<T, H> {
    let f = f.min(H);
    for (c, &sc) in s.iter().enumerate().take(f) {
        let w = (sc * scale).sqrt();
        for r in 0..f {
            t[(r, c)] *= w;
        }
    }
    t
}

/// Cholesky factor of the leading `n × n` block of a symmetric positive definite matrix;
/// `None` if a pivot is not above `floor[i]` (zero where `floor` is shorter).
pub(super) fn small_cholesky<T: Real, const H: usize>(
    a: &Small<T, H>,
    n: usize,
    floor: &[T],
) -> Option<Small<T, H>> {
    let n = n.min(H);
    let mut l = Small::<T, H>::zeros();
    for i in 0..n {
        for j in 0..=i {
            let mut s = a[(i, j)];
            for k in 0..j {
                s -= l[(i, k)] * l[(j, k)];
            }
            if i == j {
                let fl = floor.get(i).copied().unwrap_or_default();
                let ok = s > fl.max(T::zero()) && s.finite();
                if !ok {
                    return None;
                }
                l[(i, i)] = s.sqrt();
            } else {
                l[(i, j)] = s / l[(j, j)];
            }
        }
    }
    Some(l)
}

/// `L⁻¹ B` for lower-triangular `L` (leading `n × n`), zero diagonal entries giving zero rows.
pub(super) fn lower_solve<T: Real, const H: usize>(
    l: &Small<T, H>,
    b: &Small<T, H>,
    n: usize,
) -> Small<T, H> {
    let mut x = *b;
    lower_solve_in_place(l, &mut x, n);
    x
}

/// [`lower_solve`] in place: `x ← L⁻¹ x` on the leading `n × n` block.
pub(super) fn lower_solve_in_place<T: Real, const H: usize>(
    l: &Small<T, H>,
    x: &mut Small<T, H>,
    n: usize,
) {
    let n = n.min(H);
    for c in 0..n {
        for r in 0..n {
            let mut v = x[(r, c)];
            for k in 0..r {
                v -= l[(r, k)] * x[(k, c)];
            }
            let d = l[(r, r)];
            x[(r, c)] = if d > T::zero() { v / d } else { T::zero() };
        }
    }
}

/// `A Aᵀ` of the leading `n × n` block (zero outside it).
pub(super) fn outer_gram<T: Real, const H: usize>(a: &Small<T, H>, n: usize) -> Small<T, H> {
    let n = n.min(H);
    let mut g = Small::<T, H>::zeros();
    for c in 0..n {
        for r in 0..n {
            let mut s = T::zero();
            for k in 0..n {
                s += a[(r, k)] * a[(c, k)];
            }
            g[(r, c)] = s;
        }
    }
    g
}

/// `A B` of the leading `n × n` blocks (zero outside them).
pub(super) fn product<T: Real, const H: usize>(
    a: &Small<T, H>,
    b: &Small<T, H>,
    n: usize,
) -> Small<T, H> {
    let n = n.min(H);
    let mut p = Small::<T, H>::zeros();
    for c in 0..n {
        for r in 0..n {
            let mut s = T::zero();
            for k in 0..n {
                s += a[(r, k)] * b[(k, c)];
            }
            p[(r, c)] = s;
        }
    }
    p
}

/// `t ← Uᵀ` (lower) of the upper triangle of the leading `n × n` block of `u` (zero elsewhere).
pub(super) fn transpose_lower_into<T: Real, const H: usize>(
    u: &Small<T, H>,
    t: &mut Small<T, H>,
    n: usize,
) {
    let n = n.min(H);
    t.fill(T::zero());
    for i in 0..n {
        for j in i..n {
            t[(j, i)] = u[(i, j)];
        }
    }
}
