//! The weightings of Remark 4 ([`Method`]): `Γ_f` and the singular values of `O_f / √j` from
//! `Rᵀ` (`L₃₂ = Rᵀ Qᵀ`), `L₃₃` and, for N4SID, the instruments' Gram.

use super::blocks::{load_l32, r_transposed};
use super::dense::{
    lower_solve, outer_gram, product, scale_columns, scale_columns_in_place, small_cholesky,
};
use super::layout::Layout;
use super::settings::Method;
use crate::error::{Error, Stage};
use crate::linalg::{Small, Svd, at, cholesky_packed, packed, set, svd_in_place, svd_small};
use crate::scalar::Real;

/// What the weightings read: the factored Schur complement and the pieces of step 4 and 5.
pub(super) struct Weighting<'a, T, const H: usize> {
    /// The layout, with the weighting.
    pub lay: Layout,
    /// The Schur complement's Cholesky factor, packed (`L₂₂`, `L₃₂`, `L₃₃`).
    pub schur: &'a [T],
    /// `Rᵀ` from the QR of `L₃₂ᵀ`.
    pub rt: &'a Small<T, H>,
    /// `L₃₃`.
    pub l33: &'a Small<T, H>,
    /// Rounding floors of `L₃₃`'s rows (the CVA weighting's pivots must clear them).
    pub res_floor: &'a [T; H],
    /// Pivot tolerance of the packed Cholesky factorisations.
    pub tol: T,
    /// Rounding floors of the rows of `S` that may be singular.
    pub floor: &'a [T],
    /// `√j_eff` (with forgetting, the weighted Gram has the weight of `j_eff = Σλ^i` columns).
    pub sqrt_j: T,
}

impl<T: Real, const H: usize> Weighting<'_, T, H> {
    /// Step 5 of the solve: `(Γ_f, singular values of O_f / √j)` for the method; `wgram` is
    /// the instruments' packed Gram (factored here for N4SID), `x` and `tau` the QR's scratch.
    pub(super) fn gamma(
        &self,
        wgram: &mut [T],
        x: &mut [T],
        tau: &mut [T],
    ) -> Result<(Small<T, H>, [T; H]), Error> {
        match self.lay.method {
            Method::Cva => self.cva(),
            Method::N4sid => {
                let ot = self.oblique(wgram, x, tau)?;
                self.scaled(svd_small(ot, self.lay.f, Stage::Projection, false)?)
            }
            Method::PiMoesp | Method::PoMoesp => {
                let mut gamma = Small::zeros();
                let sv = pi_moesp_gamma(self.rt, self.lay.f, self.sqrt_j, &mut gamma)?;
                Ok((gamma, sv))
            }
        }
    }

    /// CVA: `L_yy L_yyᵀ = Ȳ_f Π⊥ Ȳ_fᵀ = RᵀR + L₃₃L₃₃ᵀ`; SVD of `L_yy⁻¹ Rᵀ`. The weighting is
    /// its inverse square root: a pivot at the rounding level of its row (noise-free data:
    /// `Ȳ_f Π⊥` has rank `n`) would turn rounding into canonical correlations.
    fn cva(&self) -> Result<(Small<T, H>, [T; H]), Error> {
        let f = self.lay.f;
        let gram = outer_gram(self.rt, f) + outer_gram(self.l33, f);
        let lyy = small_cholesky(&gram, f, self.res_floor).ok_or(Error::RankDeficient {
            stage: Stage::CvaWeighting,
        })?;
        let wtd = lower_solve(&lyy, self.rt, f);
        let (u, s, _) = svd_small(wtd, f, Stage::Projection, false)?;
        let t = product(&lyy, &u, f);
        Ok((scale_columns(t, &s, f, T::one()), s))
    }

    /// N4SID: `Oᵀ`'s `Rᵀ` (from its QR) for `O = L₃₂ L₂₂⁻¹ L_W`, `L_W` the Cholesky factor of
    /// the instruments' Gram `W_p W_pᵀ`.
    fn oblique(&self, wgram: &mut [T], x: &mut [T], tau: &mut [T]) -> Result<Small<T, H>, Error> {
        let (w, f, schur) = (self.lay.w(), self.lay.f, self.schur);
        let pm = self.lay.p * self.lay.m;
        cholesky_packed(wgram, w, pm, self.tol, self.floor).map_err(|_| Error::RankDeficient {
            stage: Stage::InputHankel,
        })?;
        load_l32(x, schur, w, f);
        for col in x.chunks_exact_mut(w.max(1)).take(f) {
            // x L₂₂ = l₃₂ (back substitution), then x L_W.
            for c in (0..w).rev() {
                let mut s = at(col, c);
                for (r, &xr) in col.iter().enumerate().skip(c + 1) {
                    s -= xr * at(schur, packed(r, c));
                }
                let dgn = at(schur, packed(c, c));
                set(col, c, if dgn > T::zero() { s / dgn } else { T::zero() });
            }
            for c in 0..w {
                let mut s = T::zero();
                for (r, &xr) in col.iter().enumerate().skip(c) {
                    s += xr * at(wgram, packed(r, c));
                }
                set(col, c, s);
            }
        }
        Ok(r_transposed(x, tau, w, f))
    }

    /// `Γ_f = U S^½` and the singular values over `√j` from an SVD.
    fn scaled(&self, svd: Svd<T, H>) -> Result<(Small<T, H>, [T; H]), Error> {
        Ok(scaled(svd, self.lay.f, self.sqrt_j))
    }
}

/// PI-MOESP's (and PO-MOESP's) `Γ_f` into `gamma` and the singular values of `O_f / √j`
/// (returned) from `Rᵀ` (`L₃₂ = Rᵀ Qᵀ`): the SVD of `Rᵀ`, `f × f`, in `gamma`'s place.
pub(super) fn pi_moesp_gamma<T: Real, const H: usize>(
    rt: &Small<T, H>,
    f: usize,
    sqrt_j: T,
    gamma: &mut Small<T, H>,
) -> Result<[T; H], Error> {
    *gamma = *rt;
    let s = svd_in_place(gamma, None, f, Stage::Projection)?;
    let mut sv = s;
    for v in sv.iter_mut() {
        *v /= sqrt_j;
    }
    scale_columns_in_place(gamma, &s, f);
    Ok(sv)
}

/// `Γ_f = U S^½` and the singular values over `sqrt_j` from an SVD.
fn scaled<T: Real, const H: usize>(
    (u, s, _): Svd<T, H>,
    f: usize,
    sqrt_j: T,
) -> (Small<T, H>, [T; H]) {
    let mut sv = s;
    for v in sv.iter_mut() {
        *v /= sqrt_j;
    }
    (scale_columns(u, &s, f, T::one()), sv)
}
