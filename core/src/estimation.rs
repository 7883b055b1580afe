//! From the projection to the model: `A`, `C` by shift invariance, `[D; B]` by least squares,
//! the rank-1 split of eq. (14) and γ so that `G(1) = 1`.
//!
//! `B` and `D` follow the MOESP procedure: with `U₂` the left singular vectors orthogonal to
//! `Γ_f`, `U₂ᵀ Γ_f = 0` removes the states from `Ȳ_f = Γ_f X + Ξ_f Z_f + V`, so
//! `U₂ᵀ Ξ_f(B, D) = U₂ᵀ Ȳ_f Z_fᵀ(Z_f Z_fᵀ)⁻¹ = U₂ᵀ L₃₁ L₁₁⁻¹`. `Ξ_f` is linear in `[D; B]`
//! and every input channel enters separately with the same coefficients, so one small least
//! squares with `m` right-hand sides gives the over-parameterised `[D; B]` ((n+1) × m).

use heapless::Vec;

use crate::direction::Direction;
use crate::error::{Error, Stage};
use crate::linalg::{
    Small, apply_q, at, el, householder_qr, least_squares, set, set_el, spectral_radius,
    svd_in_place,
};
use crate::model::Model;
use crate::regressor::{Basis, Knots};
use crate::scalar::Real;
use crate::subspace::{Layout, Projection, Slots, bf_at, too_small};

/// Relative rank tolerance of the small least-squares problems.
fn rank_tol<T: Real>(dim: usize) -> T {
    T::EPS * T::of_usize(64 * dim.max(1))
}

/// The first `len` scalars of `rest`, which keeps the others; `err` if it is shorter.
fn take<'a, T>(rest: &mut &'a mut [T], len: usize, err: Error) -> Result<&'a mut [T], Error> {
    let (head, tail) = core::mem::take(rest).split_at_mut_checked(len).ok_or(err)?;
    *rest = tail;
    Ok(head)
}

/// What the solve accepts as the identified linear part ([`Identifier::solve_with`](crate::Identifier::solve_with)).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Poles {
    /// Only a stable `A` (spectral radius below 1); anything else is
    /// [`Error::UnstableModel`]. What [`Identifier::solve`](crate::Identifier::solve) does.
    #[default]
    Stable,
    /// Any `A` with `I − A` invertible, for a caller that refines the poles afterwards.
    Any,
}

/// Where μ0 comes from in the final model.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Mu0<T, const M: usize> {
    /// Known (from the hold or given).
    Known(T),
    /// Estimated: `offset` was subtracted from `y` during the accumulation; with `G(1) = 1`,
    /// `μ0 = offset + mean(ȳ) − coef·mean(z)`.
    FromMeans {
        /// Provisional offset subtracted from every `y`.
        offset: T,
        /// Mean of `ȳ = y − offset`.
        mean_y: T,
        /// Mean of z.
        mean_z: [T; M],
    },
}

/// Where the model's step reads `B_f = L₃₁ L₁₁⁻¹` (`f × f·m`).
#[derive(Clone, Copy)]
pub(crate) enum BfSource<'a, T> {
    /// Row-major in the dense solve's workspace.
    Dense(&'a [T]),
    /// Over the identity slots of the structured solve's generator.
    Slots(&'a [T], Slots),
}

impl<T: Real> BfSource<'_, T> {
    /// `B_f[i, jj·m + c]`.
    #[inline]
    fn at(&self, i: usize, jj: usize, c: usize, m: usize, fm: usize) -> T {
        match *self {
            BfSource::Dense(bf) => at(bf, i * fm + jj * m + c),
            BfSource::Slots(x, sl) => bf_at(x, &sl, i, jj, c),
        }
    }
}

/// Builds the model of order `n` from the factored Gram in `ws` and the projection.
#[allow(clippy::too_many_arguments)]
pub(crate) fn estimate<T: Real, const M: usize, const K: usize, const H: usize>(
    proj: &Projection<T, H>,
    n: usize,
    lay: Layout,
    ws: &mut [T],
    knots: &Knots<T, M>,
    basis: Basis,
    mu0: Mu0<T, M>,
    poles: Poles,
) -> Result<Model<T, M, H>, Error> {
    let err = too_small(lay, ws.len());
    let [_, _, _, bf, _, scratch] = lay.carve(ws)?;
    let out = Outcome {
        knots,
        basis,
        mu0,
        poles,
    };
    estimate_from::<T, M, K, H>(proj, n, lay, BfSource::Dense(bf), scratch, err, out)
}

/// What the model is made of besides the subspace step: the regressor and μ0, and which
/// poles are accepted.
pub(crate) struct Outcome<'a, T, const M: usize> {
    /// The knots the regressor was accumulated with.
    pub knots: &'a Knots<T, M>,
    /// The regressor's basis.
    pub basis: Basis,
    /// Where μ0 comes from.
    pub mu0: Mu0<T, M>,
    /// Which poles are accepted.
    pub poles: Poles,
}

/// [`estimate`] with `B_f` read from `bf` and the steps' scratch in `scratch` (`err` if it is
/// too short).
pub(crate) fn estimate_from<T: Real, const M: usize, const K: usize, const H: usize>(
    proj: &Projection<T, H>,
    n: usize,
    lay: Layout,
    bf: BfSource<'_, T>,
    scratch: &mut [T],
    err: Error,
    out: Outcome<'_, T, M>,
) -> Result<Model<T, M, H>, Error> {
    let Outcome {
        knots,
        basis,
        mu0,
        poles,
    } = out;
    let (f, m) = (lay.f, lay.m);
    // Both refused by `Identifier::new` (and `n` by `select_order`); kept here so that no
    // order can index past the small matrices.
    if !(2..=H).contains(&f) {
        return Err(Error::InvalidHorizon {
            f,
            k: f + lay.p,
            max_f: H,
            max_k: K,
        });
    }
    if n == 0 || n >= f {
        return Err(Error::InvalidOrder { order: n, f });
    }

    // 1. Γ_f (first n columns of the weighting's estimate), C = first row, A from
    // Γ_under A = Γ_over.
    let gamma = &proj.gamma;
    // U₂: an orthonormal basis of the complement of range(Γ_f), from the QR of Γ_f.
    let mut u2 = Small::<T, H>::zeros();
    {
        let (lg, lt, le) = lay.u2_parts(n);
        let mut rest: &mut [T] = scratch;
        let g = take(&mut rest, lg, err)?;
        let tau = take(&mut rest, lt, err)?;
        let e = take(&mut rest, le, err)?;
        for c in 0..n {
            for r in 0..f {
                set(g, r + c * f, el(gamma, r, c));
            }
        }
        householder_qr(g, f, n, tau);
        for r in 0..f - n {
            e.fill(T::zero());
            set(e, n + r, T::one());
            apply_q(g, f, n, tau, e);
            for (i, &v) in e.iter().enumerate() {
                set_el(&mut u2, i, r, v);
            }
        }
    }
    let mut a = Small::<T, H>::zeros();
    {
        let rows = f - 1;
        let (la, lb, lt) = lay.shift_parts(n);
        let mut rest: &mut [T] = scratch;
        let ga = take(&mut rest, la, err)?;
        let gb = take(&mut rest, lb, err)?;
        let tau = take(&mut rest, lt, err)?;
        for c in 0..n {
            for r in 0..rows {
                set(ga, r + c * rows, el(gamma, r, c));
                set(gb, r + c * rows, el(gamma, r + 1, c));
            }
        }
        least_squares::<T, H>(ga, rows, n, gb, n, tau, rank_tol(rows)).map_err(|()| {
            Error::RankDeficient {
                stage: Stage::ShiftInvariance,
            }
        })?;
        for c in 0..n {
            for r in 0..n {
                set_el(&mut a, r, c, at(gb, r + c * rows));
            }
        }
    }
    // The paper's G is stable: a pole on or outside the unit circle (an integrating plant, a
    // drift) leaves G(1) undefined or meaningless, and γ would rescale the model by it.
    let rho = spectral_radius(&a, n);
    if rho.is_nan() || (poles == Poles::Stable && rho >= 1.0) {
        return Err(Error::UnstableModel {
            spectral_radius: rho,
        });
    }
    let mut cvec = [T::zero(); H];
    for (c, v) in cvec.iter_mut().enumerate().take(n) {
        *v = el(gamma, 0, c);
    }

    // 2. B_f = L₃₁ L₁₁⁻¹ (f × f·m) was left in the workspace by the projection step.

    // 3. [D; B] from U₂ᵀ Ξ_f = U₂ᵀ B_f. Rows (jj, r): block column jj, annihilator r.
    let nr = f - n;
    let rows = f * nr;
    let cols = n + 1;
    let (lk, lr, lt) = lay.bd_parts(n);
    let mut rest: &mut [T] = scratch;
    let kmat = take(&mut rest, lk, err)?;
    let rhs = take(&mut rest, lr, err)?;
    let tau = take(&mut rest, lt, err)?;
    let split = take(&mut rest, lay.split_len(n), err)?;
    bd_system(&u2, &a, &cvec, bf, lay, n, kmat, rhs);
    least_squares::<T, H>(kmat, rows, cols, rhs, m, tau, rank_tol(rows)).map_err(|()| {
        Error::RankDeficient {
            stage: Stage::InputMatrices,
        }
    })?;
    // X = [D; B] ((n+1) × m): X[q][c] = rhs[q + c·rows].

    // 4. Rank-1 split (eq. 14): X ≈ s u vᵀ.
    let (s1, s2, uvec, vvec) = dominant_triple::<T, M, H>(rhs, rows, cols, m, split, err)?;

    // 5. γ: G(1) = γ s (C (I − A)⁻¹ u_B + u_D) = 1, from (I − A) x = u_B.
    let mut xb = [T::zero(); H];
    {
        let (la, lb, lt) = lay.gain_parts(n);
        let mut rest: &mut [T] = scratch;
        let ma = take(&mut rest, la, err)?;
        let mb = take(&mut rest, lb, err)?;
        let tau = take(&mut rest, lt, err)?;
        for r in 0..n {
            set(mb, r, at(&uvec, 1 + r));
            for c in 0..n {
                let eye = if r == c { T::one() } else { T::zero() };
                set(ma, r + c * n, eye - el(&a, r, c));
            }
        }
        least_squares::<T, H>(ma, n, n, mb, 1, tau, rank_tol(n))
            .map_err(|()| Error::IntegratingModel)?;
        for (x, &v) in xb.iter_mut().zip(mb.iter()).take(n) {
            *x = v;
        }
    }
    let ud = at(&uvec, 0);
    let mut g0 = ud;
    let mut scale = ud.abs();
    for (&c, &x) in cvec.iter().zip(&xb).take(n) {
        g0 += c * x;
        scale += (c * x).abs();
    }
    // g0 is a sum of terms of total size `scale`; the rank-1 split's relative residual
    // s₂/s₁ (zero for data of the exact model class, the estimate's noise and misfit
    // otherwise) bounds the relative error of its direction u, so of each term: a g0 within
    // that error (or within √ε of rounding, for one channel where s₂ does not exist) is not
    // told from zero, and dividing by it would rescale the model by noise.
    let noise = if s1 > T::zero() { s2 / s1 } else { T::one() };
    let usable = g0.abs() > T::EPS.sqrt().max(noise) * scale && g0.finite();
    if !usable {
        return Err(Error::ZeroStaticGain);
    }
    // B = γ s u_B = u_B / g0, D = u_D / g0, μ = s g0 v.
    let mut bvec = [T::zero(); H];
    let mut dc_state = [T::zero(); H];
    for q in 0..n {
        set(&mut bvec, q, at(&uvec, 1 + q) / g0);
        set(&mut dc_state, q, at(&xb, q) / g0);
    }
    let dval = ud / g0;
    let mut coef = [T::zero(); M];
    for (c, v) in coef.iter_mut().enumerate() {
        *v = s1 * g0 * vvec[c];
    }

    let mu0 = match mu0 {
        Mu0::Known(v) => v,
        Mu0::FromMeans {
            offset,
            mean_y,
            mean_z,
        } => {
            let mut s = offset + mean_y;
            for (&c, &z) in coef.iter().zip(&mean_z) {
                s -= c * z;
            }
            s
        }
    };

    // 6. Border values at the knots.
    let border = |dir: Direction| -> Vec<T, M> {
        let k = knots.path(dir);
        let off = knots.offset(dir);
        let mut out = Vec::new();
        let mut acc = mu0;
        let _ = out.push(mu0);
        for i in 1..k.len() {
            let c = coef.get(off + i - 1).copied().unwrap_or_default();
            let v = match basis {
                Basis::Hat => mu0 + c,
                Basis::Ramp => {
                    acc += c * (k[i] - k[i - 1]);
                    acc
                }
            };
            let _ = out.push(v);
        }
        out
    };

    let mut sv = [T::zero(); H];
    let mut sv_white = [T::zero(); H];
    for (v, &p) in sv.iter_mut().zip(&proj.sv).take(f) {
        *v = p;
    }
    for (v, &p) in sv_white.iter_mut().zip(&proj.sv_white).take(f) {
        *v = p;
    }
    Ok(Model {
        n,
        a,
        b: bvec,
        c: cvec,
        d: dval,
        dc_state,
        mu0,
        knots: knots.clone(),
        border_asc: border(Direction::Ascending),
        border_desc: border(Direction::Descending),
        f,
        columns: proj.j,
        sv,
        sv_white,
    })
}

/// The least squares of step 3: `kmat` (`f(f−n) × (n+1)`, column-major) from `U₂` and the
/// observability rows `C A^k`, `rhs` (`f(f−n) × m`) from `U₂ᵀ B_f`. Not inlined: `C A^k` is
/// on the stack only while it is built.
#[inline(never)]
#[allow(clippy::too_many_arguments)]
fn bd_system<T: Real, const H: usize>(
    u2: &Small<T, H>,
    a: &Small<T, H>,
    cvec: &[T; H],
    bf: BfSource<'_, T>,
    lay: Layout,
    n: usize,
    kmat: &mut [T],
    rhs: &mut [T],
) {
    let (f, m) = (lay.f, lay.m);
    let fm = f * m;
    let nr = f - n;
    let rows = f * nr;
    // C A^k, k = 0 … f − 2.
    let mut ob = Small::<T, H>::zeros();
    let mut row = *cvec;
    for k in 0..f.saturating_sub(1) {
        for q in 0..n {
            set_el(&mut ob, k, q, at(&row, q));
        }
        let mut next = [T::zero(); H];
        for (q, nq) in next.iter_mut().enumerate().take(n) {
            for (p, &rp) in row.iter().enumerate().take(n) {
                *nq += rp * el(a, p, q);
            }
        }
        row = next;
    }
    for jj in 0..f {
        for r in 0..nr {
            let row = jj * nr + r;
            set(kmat, row, el(u2, jj, r));
            for q in 0..n {
                let mut s = T::zero();
                for kk in 0..(f - jj - 1) {
                    s += el(u2, jj + 1 + kk, r) * el(&ob, kk, q);
                }
                set(kmat, row + (1 + q) * rows, s);
            }
            for c in 0..m {
                let mut s = T::zero();
                for i in 0..f {
                    s += el(u2, i, r) * bf.at(i, jj, c, m, fm);
                }
                set(rhs, row + c * rows, s);
            }
        }
    }
}

/// Dominant singular triple of the `(n+1) × m` matrix stored column-major with leading
/// dimension `ld` in `x`. Returns `(s₁, s₂, u (n+1), v (m))` (`s₂` the second singular value,
/// 0 for a single row or column); `buf` is scratch of at least
/// `m·(n+1) + m + n + 1` scalars (`err` if it is shorter). Not inlined: its two small
/// matrices are on the stack only while it runs.
#[inline(never)]
fn dominant_triple<T: Real, const M: usize, const H: usize>(
    x: &[T],
    ld: usize,
    rows: usize,
    m: usize,
    buf: &mut [T],
    err: Error,
) -> Result<(T, T, [T; H], [T; M]), Error> {
    let mut u = [T::zero(); H];
    let mut v = [T::zero(); M];
    if m >= rows {
        // Xᵀ = Q R (m × rows), X = Rᵀ Qᵀ, SVD(Rᵀ) = U S Wᵀ: u = U₀, v = Q W₀.
        let mut rest = buf;
        let xt = take(&mut rest, m * rows, err)?;
        let tau = take(&mut rest, rows, err)?;
        let y = take(&mut rest, m, err)?;
        for q in 0..rows {
            for c in 0..m {
                set(xt, c + q * m, at(x, q + c * ld));
            }
        }
        householder_qr(xt, m, rows, tau);
        let mut rt = Small::<T, H>::zeros();
        for i in 0..rows {
            for k in 0..=i {
                set_el(&mut rt, i, k, at(xt, k + i * m));
            }
        }
        let mut w = Small::<T, H>::identity();
        let s = svd_in_place(&mut rt, Some(&mut w), rows, Stage::RankOneSplit)?;
        y.fill(T::zero());
        for i in 0..rows {
            set(&mut u, i, el(&rt, i, 0));
            set(y, i, el(&w, i, 0));
        }
        apply_q(xt, m, rows, tau, y);
        for (vi, &yi) in v.iter_mut().zip(y.iter()) {
            *vi = yi;
        }
        Ok((at(&s, 0), at(&s, 1), u, v))
    } else {
        // X = Q R (rows × m), SVD(R) = U S Wᵀ: u = Q U₀, v = W₀.
        let mut rest = buf;
        let xc = take(&mut rest, rows * m, err)?;
        let tau = take(&mut rest, m, err)?;
        let y = take(&mut rest, rows, err)?;
        for q in 0..rows {
            for c in 0..m {
                set(xc, q + c * rows, at(x, q + c * ld));
            }
        }
        householder_qr(xc, rows, m, tau);
        let mut r = Small::<T, H>::zeros();
        for c in 0..m {
            for k in 0..=c {
                set_el(&mut r, k, c, at(xc, k + c * rows));
            }
        }
        let mut w = Small::<T, H>::identity();
        let s = svd_in_place(&mut r, Some(&mut w), m, Stage::RankOneSplit)?;
        y.fill(T::zero());
        for i in 0..m {
            set(y, i, el(&r, i, 0));
            set(&mut v, i, el(&w, i, 0));
        }
        apply_q(xc, rows, m, tau, y);
        for (ui, &yi) in u.iter_mut().zip(y.iter()) {
            *ui = yi;
        }
        Ok((at(&s, 0), at(&s, 1), u, v))
    }
}
