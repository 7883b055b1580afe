//! PI-MOESP (eq. 11) from the accumulated Gram: the projection, its SVD and the order.
//!
//! With `M = [Z_f; Z_p; Ȳ_f] = L Q` (LQ factorisation) the projection of eq. (11) is
//! `O_f = Ȳ_f Φᵀ(ΦΦᵀ)⁻¹Φ Π⊥_{Z_f} = L₃₂ Q₂`, so `O_f` and `L₃₂` have the same singular values
//! and left singular vectors. `L` is the Cholesky factor of `M Mᵀ`, which the accumulator
//! provides block by block; `Q` is never formed. The SVD of the `f × p·m` block `L₃₂` is taken
//! through the QR of `L₃₂ᵀ`, leaving an `f × f` SVD.
//!
//! **Order selection** ([`Order::Auto`]): the residual block `L₃₃` estimates the part of `Ȳ_f`
//! that no input explains. Whitening `L₃₂` with it, `W = √((j − d)/(p·m)) · L₃₃⁻¹ L₃₂`
//! (`d = (f+p)·m`), gives singular values near 1 for directions that carry only noise
//! (between `1 ± √(f/(p·m))`, the Marchenko–Pastur edges for an `f × p·m` noise matrix) and
//! far above 1 for directions that carry state. The order is the number of whitened singular
//! values above [`AUTO_ORDER_MARGIN`] times the upper edge, capped at `f − 1`.

use crate::MAX_HORIZON;
use crate::accumulation::Accumulator;
use crate::error::{Error, Stage};
use crate::linalg::{Small, cholesky_packed, householder_qr, packed, packed_len, svd_small};
use crate::regressor::{Basis, Knots};
use crate::scalar::Real;

/// How the model order is chosen.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Order {
    /// From the whitened singular values (see the [module docs](self)).
    #[default]
    Auto,
    /// Given by the user (`1 <= n < f`).
    Fixed(usize),
}

/// Margin over the noise-only edge `1 + √(f/(p·m))` that a whitened singular value must clear
/// to count as a state direction in [`Order::Auto`].
pub const AUTO_ORDER_MARGIN: f64 = 1.5;

/// Layout of the solve workspace for `m` channels and horizons `f`, `p`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Layout {
    pub m: usize,
    pub f: usize,
    pub p: usize,
}

impl Layout {
    /// Rows of `Φ = [Z_f; Z_p]`.
    pub const fn d(&self) -> usize {
        (self.f + self.p) * self.m
    }
    /// Rows of the whole Gram, `Φ` plus `Ȳ_f`.
    pub const fn dt(&self) -> usize {
        self.d() + self.f
    }
    /// Packed Gram length.
    pub const fn gram(&self) -> usize {
        packed_len(self.dt())
    }
    /// Length of `B_f = L₃₁ L₁₁⁻¹` (`f × f·m`).
    pub const fn bf(&self) -> usize {
        self.f * self.f * self.m
    }
    /// Scratch for the QR/least-squares steps.
    pub const fn scratch(&self) -> usize {
        let (f, m, p) = (self.f, self.m, self.p);
        let a = p * m * f + f;
        let b = f * f * (f + m + 1) + f;
        let c = m * f + m + f;
        let ab = if a > b { a } else { b };
        if ab > c { ab } else { c }
    }
    /// Whole workspace.
    pub const fn total(&self) -> usize {
        self.gram() + self.bf() + self.scratch()
    }
    /// Gram row of channel `c` of block row `a` of `z` (`Z_f` first, then `Z_p`).
    #[inline]
    pub fn z_row(&self, a: usize, c: usize) -> usize {
        if a >= self.p {
            (a - self.p) * self.m + c
        } else {
            self.f * self.m + a * self.m + c
        }
    }
    /// Gram row of `ȳ` in block row `a`, if it belongs to `Ȳ_f`.
    #[inline]
    pub fn y_row(&self, a: usize) -> Option<usize> {
        (a >= self.p).then(|| self.d() + (a - self.p))
    }
}

/// Scalars the solve workspace needs for `m` channels and horizons `f`, `p`: size a static
/// array with it, e.g. `[0.0f32; hsid::workspace_len(14, 10, 10)]`.
pub const fn workspace_len(m: usize, f: usize, p: usize) -> usize {
    Layout { m, f, p }.total()
}

/// The outcome of the PI-MOESP step.
#[derive(Clone, Debug)]
pub(crate) struct Projection<T> {
    /// Hankel columns.
    pub j: u64,
    /// Singular values of `O_f / √j`, descending (first `f` valid).
    pub sv: [T; MAX_HORIZON],
    /// Whitened singular values (order selection), descending.
    pub sv_white: [T; MAX_HORIZON],
    /// Left singular vectors of `O_f` (`f × f`).
    pub u: Small<T>,
}

/// Builds the Gram `[Z_f; Z_p; Ȳ_f][…]ᵀ` in `ws`, factors it and takes the SVD of `L₃₂`.
pub(crate) fn pi_moesp<T: Real, const M: usize, const K: usize>(
    acc: &Accumulator<T, M, K>,
    knots: &Knots<T, M>,
    basis: Basis,
    lay: Layout,
    centred: bool,
    ws: &mut [T],
) -> Result<Projection<T>, Error> {
    let (f, m) = (lay.f, lay.m);
    let (d, dt) = (lay.d(), lay.dt());
    let (gram, rest) = ws.split_at_mut(lay.gram());
    let scratch = &mut rest[lay.bf()..];

    // 1. The Gram, block by block, in the order [Z_f; Z_p; Ȳ_f]; rows centred if asked
    // (subtract the outer product of the row sums divided by j).
    let sums = centred.then(|| acc.row_sums(knots, basis));
    let inv_j = T::one() / T::of(acc.columns().max(1) as f64);
    acc.for_each_block(knots, basis, |a, b, blk| {
        let mut blk = *blk;
        if let Some(s) = &sums {
            let (za, zb, ya, yb) = (s.z[a], s.z[b], s.y[a] * inv_j, s.y[b] * inv_j);
            for (row, &zi) in blk.zz.iter_mut().zip(&za) {
                let zi = zi * inv_j;
                for (v, &zj) in row.iter_mut().zip(&zb) {
                    *v -= zi * zj;
                }
            }
            for (v, &zi) in blk.zy.iter_mut().zip(&za) {
                *v -= zi * yb;
            }
            for (v, &zj) in blk.yz.iter_mut().zip(&zb) {
                *v -= ya * zj;
            }
            blk.yy -= ya * s.y[b];
        }
        let blk = &blk;
        for i in 0..m {
            let ra = lay.z_row(a, i);
            for (jj, &v) in blk.zz[i].iter().enumerate().take(m) {
                let rb = lay.z_row(b, jj);
                gram[packed(ra.max(rb), ra.min(rb))] = v;
            }
            if let Some(rb) = lay.y_row(b) {
                gram[packed(rb.max(ra), rb.min(ra))] = blk.zy[i];
            }
        }
        if let Some(ra) = lay.y_row(a) {
            for (jj, &v) in blk.yz.iter().enumerate().take(m) {
                let rb = lay.z_row(b, jj);
                gram[packed(ra.max(rb), ra.min(rb))] = v;
            }
            if let Some(rb) = lay.y_row(b) {
                gram[packed(ra.max(rb), ra.min(rb))] = blk.yy;
            }
        }
    });

    // 2. Cholesky: Φ rows must be positive definite, Ȳ_f rows may be singular (no noise).
    let tol = T::EPS * T::of_usize(8 * dt);
    cholesky_packed(gram, dt, d, tol).map_err(|_| Error::RankDeficient {
        stage: Stage::InputHankel,
    })?;

    // 3. L₃₂ᵀ (p·m × f) into scratch, QR, and the f × f SVD of Rᵀ.
    let pm = lay.p * m;
    let (x, tau) = scratch.split_at_mut(pm * f);
    for i in 0..f {
        let row = packed(d + i, f * m);
        x[i * pm..(i + 1) * pm].copy_from_slice(&gram[row..row + pm]);
    }
    householder_qr(x, pm, f, &mut tau[..f]);
    let mut rt = Small::<T>::zeros();
    for i in 0..f {
        for k in 0..=i {
            rt[(i, k)] = x[k + i * pm];
        }
    }
    let (u, s, _) = svd_small(rt).ok_or(Error::NoConvergence {
        stage: Stage::Projection,
    })?;

    // 4. Whitened singular values: √((j − d)/(p·m)) · L₃₃⁻¹ Rᵀ, with L₃₃'s diagonal floored
    // at √ε·σ₁ so that noise-free data do not divide by zero.
    let j = acc.columns();
    let floor = T::EPS.sqrt() * s[0];
    let mut w = rt;
    for c in 0..f {
        for r in 0..f {
            let row = packed(d + r, d);
            let mut acc_v = w[(r, c)];
            for k in 0..r {
                acc_v -= gram[row + k] * w[(k, c)];
            }
            let diag = gram[row + r].max(floor);
            w[(r, c)] = if diag > T::zero() {
                acc_v / diag
            } else {
                T::zero()
            };
        }
    }
    let dof = (j as f64 - d as f64).max(1.0);
    let scale = T::of(libm::sqrt(dof / pm as f64));
    let (_, sw, _) = svd_small(w).ok_or(Error::NoConvergence {
        stage: Stage::Projection,
    })?;

    let sqrt_j = T::of(libm::sqrt(j as f64));
    let mut sv = [T::zero(); MAX_HORIZON];
    let mut sv_white = [T::zero(); MAX_HORIZON];
    for i in 0..f {
        sv[i] = s[i] / sqrt_j;
        sv_white[i] = sw[i] * scale;
    }
    Ok(Projection { j, sv, sv_white, u })
}

/// The order: fixed, or counted from the whitened singular values.
pub(crate) fn select_order<T: Real>(
    order: Order,
    proj: &Projection<T>,
    lay: Layout,
) -> Result<usize, Error> {
    match order {
        Order::Fixed(n) => Ok(n),
        Order::Auto => {
            let edge = 1.0 + libm::sqrt(lay.f as f64 / (lay.p * lay.m) as f64);
            let thr = T::of(AUTO_ORDER_MARGIN * edge);
            let n = proj.sv_white[..lay.f]
                .iter()
                .take_while(|&&s| s > thr)
                .count();
            match n {
                0 => Err(Error::NoDynamics),
                n => Ok(n.min(lay.f - 1)),
            }
        }
    }
}
