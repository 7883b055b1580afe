//! PI-MOESP from the accumulated Gram (see the [module docs](super)) and its outcome.

use super::cross::cross_block;
use super::dense::{lower_solve, outer_gram, product, scale_columns, small_cholesky};
use super::gram::for_each_entry;
use super::schedule::Schedule;
use super::schur::subtract_products;
use super::triangular::back_substitution_transposed;
use super::{Layout, Method, too_small};
use crate::accumulation::{Accumulator, OutputRounding};
use crate::error::{Error, Stage};
use crate::linalg::{
    Small, all_finite, at, cholesky_packed, householder_qr, packed, set, set_el, sub, sub_mut,
    svd_small,
};
use crate::regressor::{Basis, Knots};
use crate::scalar::Real;

/// The outcome of the PI-MOESP step.
#[derive(Clone, Debug)]
pub(crate) struct Projection<T, const H: usize> {
    /// Hankel columns.
    pub j: u64,
    /// Singular values of `O_f / √j`, descending (first `f` valid).
    pub sv: [T; H],
    /// Whitened singular values (order selection), descending.
    pub sv_white: [T; H],
    /// `Γ_f` for every order: its first `n` columns are the estimate of order `n`.
    pub gamma: Small<T, H>,
}

/// PI-MOESP from the accumulated Gram: `L₁₁`, the Schur complement of `[Z_p; Ȳ_f]` given
/// `Z_f` (whose Cholesky factor holds `L₂₂`, `L₃₂`, `L₃₃`), `B_f = L₃₁L₁₁⁻¹`, and the SVD of
/// `L₃₂`. The cross block `G_{Z_f,[Z_p; Ȳ_f]}` is never stored whole: it is formed from the
/// lagged sums panel by panel (columns left of a panel regenerated), which keeps the workspace near
/// `(f·m)²/2 + (p·m + f)²/2` instead of `((f + p)·m + f)²/2`.
pub(crate) fn pi_moesp<T: Real, const M: usize, const K: usize, const H: usize>(
    acc: &Accumulator<T, M, K>,
    knots: &Knots<T, M>,
    basis: Basis,
    lay: Layout,
    centred: bool,
    output_rounding: OutputRounding,
    ws: &mut [T],
) -> Result<Projection<T, H>, Error> {
    let (f, m) = (lay.f, lay.m);
    let (fm, q, pm, d, w) = (lay.fm(), lay.q(), lay.p * m, lay.d(), lay.w());
    // Both refused by `Identifier::new`; kept here so that no layout can index past the QR
    // or the small matrices.
    if !(2..=H).contains(&f) {
        return Err(Error::InvalidHorizon {
            f,
            k: f + lay.p,
            max_f: H,
            max_k: K,
        });
    }
    if w < f {
        return Err(Error::TooFewInstruments {
            f,
            p: lay.p,
            channels: m,
            past_outputs: lay.method.past_outputs(),
        });
    }
    let ws_len = ws.len();
    let [lff, schur, wgram, tail] = lay.carve_front(ws)?;
    // Until step 4 the raw diagonals (below) sit at the end of the tail, and the rest of it
    // (B_f, the column blocks and the scratch) is the cache of step 2.
    let (xs, g) = tail
        .split_at_mut_checked(tail.len().saturating_sub(q))
        .ok_or(too_small(lay, ws_len))?;
    let sums = centred.then(|| acc.row_sums(knots, basis));
    let sums = sums.as_ref();

    // 1. G_{Z_f Z_f} and G_{QQ} (Q = [Z_p; Ȳ_f]) in one pass. Both must be finite: an
    // overflow of the sums (y² above the scalar's range) is reported as such, before any
    // factorisation (a non-finite cross block G_{Z_f Q} shows in the Schur complement).
    for_each_entry(
        acc,
        knots,
        basis,
        lay,
        sums,
        |_, _| true,
        |r, c, v| {
            if r < fm {
                set(lff, packed(r, c), v);
            } else if c >= fm {
                set(schur, packed(r - fm, c - fm), v);
                if r < fm + w {
                    set(wgram, packed(r - fm, c - fm), v);
                }
            }
        },
    );
    if !all_finite(lff) || !all_finite(schur) {
        return Err(Error::Overflow { stage: Stage::Sums });
    }
    // Rounding floors of the rows that may be singular (Ȳ_p, Ȳ_f): their raw Gram diagonals
    // times the relative rounding level of the sums and of the factorisations.
    let j_eff = acc.effective_columns().to_f64();
    // `level` for the input sums (always recursive) and anything that mixes them in,
    // `level_y` for what only the sums of products with the output carry.
    let level = rounding_level::<T>(j_eff, d + q);
    let level_y = match output_rounding {
        OutputRounding::Recursive => level,
        OutputRounding::Compensated => rounding_level::<T>(4.0, d + q),
    };
    // `q − pm = py + f <= p + f <= K` rows.
    let mut floor = [T::zero(); K];
    for (i, fl) in floor.iter_mut().enumerate().take(q - pm) {
        let r = pm + i;
        *fl = level * at(schur, packed(r, r)).abs();
    }
    let floor = &floor[..(q - pm).min(K)];
    // The raw diagonal of every row of [Z_p; Ȳ_p; Ȳ_f].
    for (r, g) in g.iter_mut().enumerate().take(q) {
        *g = at(schur, packed(r, r)).abs();
    }
    let tol = T::EPS * T::of_usize(8 * (d + q));
    cholesky_packed(lff, fm, fm, tol, &[]).map_err(|_| Error::RankDeficient {
        stage: Stage::InputHankel,
    })?;

    // 2. S = G_QQ − XᵀX with X = L₁₁⁻¹ G_{Z_f Q}: a panel of X's columns stays in the cache
    // while the columns left of it are regenerated a few at a time (see `Schedule`).
    let plan = Schedule::choose(lay, xs.len() / fm.max(1));
    let mut y_at = None;
    for p0 in (0..q).step_by(plan.width.max(1)) {
        let pw = plan.width.min(q - p0);
        let (xa, rest) = xs
            .split_at_mut_checked(pw * fm)
            .ok_or(too_small(lay, ws_len))?;
        cross_block(acc, knots, basis, lay, sums, lff, p0, pw, xa);
        subtract_products(schur, xa, xa, fm, p0, p0, true);
        let mut i0 = 0;
        while i0 < p0 {
            let iw = plan.stream.max(1).min(p0 - i0);
            let xb = rest.get_mut(..iw * fm).ok_or(too_small(lay, ws_len))?;
            cross_block(acc, knots, basis, lay, sums, lff, i0, iw, xb);
            subtract_products(schur, xa, xb, fm, p0, i0, false);
            i0 += iw;
        }
        // X_Y (the last f columns) for step 3, if this panel (the last) holds all of them.
        y_at = (p0 <= w && w + f <= p0 + pw).then_some((w - p0) * fm);
    }

    // 3. B_f = G_{Ȳ_f Z_f} G_{Z_f Z_f}⁻¹ = (L₁₁⁻ᵀ X_Y)ᵀ, X_Y the last f columns of X, moved
    // from the last panel to B_f's place at the start of the cache (or computed anew).
    let bf_len = lay.bf();
    match y_at {
        Some(from) if from.saturating_add(bf_len) <= xs.len() => {
            // Forwards, entry by entry: the source lies at or after the destination.
            for k in 0..bf_len {
                let v = at(xs, from + k);
                set(xs, k, v);
            }
        }
        _ => {
            let bf = xs.get_mut(..bf_len).ok_or(too_small(lay, ws_len))?;
            cross_block(acc, knots, basis, lay, sums, lff, w, f, bf);
        }
    }
    let bf = xs.get_mut(..bf_len).ok_or(too_small(lay, ws_len))?;
    for x in bf.chunks_exact_mut(fm.max(1)).take(f) {
        back_substitution_transposed(lff, x);
    }

    if !all_finite(schur) || !all_finite(bf) {
        return Err(Error::Overflow { stage: Stage::Sums });
    }
    // 4. Cholesky of S: Z_p rows must be positive definite; Ȳ_p and Ȳ_f rows may be singular
    // (noise-free data).
    cholesky_packed(schur, q, pm, tol, floor).map_err(|_| Error::RankDeficient {
        stage: Stage::InputHankel,
    })?;
    let j = acc.columns();
    // Rounding level of the residual L₃₃L₃₃ᵀ = S₃₃ − L₃₂L₃₂ᵀ, row by row: the row's own
    // (level · raw diagonal), plus what L₃₂ inherits from the pivots d_i of the instruments:
    // d_i² carries an error of level · g_i (g_i its raw diagonal), so column i of L₃₂ a
    // relative error of level · g_i / d_i², and the row's residual 2 Σ_i L₃₂[r,i]² times that.
    // Past outputs that the inputs nearly explain (high SNR) have small pivots and make this
    // large where the row leans on them. Besides, each entry L₃₂[r,i] carries an absolute
    // rounding error of about level · √(g_r g_i) / d_i, which looks like noise to the
    // whitening: its floor for L₃₃'s row is also the residual that noise of that size would
    // leave (dof/w times the mean squared error of the row). Below `res_floor` a residual is
    // rounding (the CVA weighting is then singular), below `white_floor` the whitening
    // cannot tell noise from rounding.
    let dof = (j_eff - (d + lay.py()) as f64).max(1.0);
    let per_col = T::of(dof / w as f64);
    let mut res_floor = [T::zero(); H];
    let mut white_floor = [T::zero(); H];
    for (r, (v, wf)) in res_floor
        .iter_mut()
        .zip(white_floor.iter_mut())
        .enumerate()
        .take(f)
    {
        let row = packed(w + r, 0);
        let gr = at(g, w + r);
        let (mut e, mut noise) = (T::zero(), T::zero());
        for (i, &gi) in g.iter().enumerate().take(w) {
            let d = at(schur, packed(i, i));
            if d > T::zero() {
                let l = at(schur, row + i) / d;
                e += (l + l) * l * gi;
                noise += gr * gi / (d * d);
            }
        }
        // The row's own diagonal and the cross products are output sums; the pivots d_i
        // come from the input sums.
        *v = level_y * gr + level * e;
        *wf = v.max(level_y * level_y * noise * per_col);
    }

    // 5. Rᵀ from the QR of L₃₂ᵀ (w × f): L₃₂ = Rᵀ Qᵀ, so the SVDs of L₃₂ reduce to f × f.
    // For N4SID the same is done for (L₃₂ L₂₂⁻¹ L_W)ᵀ below.
    // The scratch (after B_f and the column blocks) is free from here on.
    let scratch = tail
        .get_mut(lay.bf() + lay.cache()..)
        .ok_or(too_small(lay, ws_len))?;
    let (x, tau) = scratch
        .split_at_mut_checked(lay.qr_parts().0)
        .ok_or(too_small(lay, ws_len))?;
    let tau = tau
        .get_mut(..lay.qr_parts().1)
        .ok_or(too_small(lay, ws_len))?;
    let load_l32 = |x: &mut [T]| {
        for i in 0..f {
            let row = packed(w + i, 0);
            let dst = sub_mut(x, i * w, (i + 1) * w);
            for (d, &v) in dst.iter_mut().zip(sub(schur, row, row + w)) {
                *d = v;
            }
        }
    };
    let r_transposed = |x: &mut [T], tau: &mut [T]| {
        householder_qr(x, w, f, tau);
        let mut rt = Small::<T, H>::zeros();
        for i in 0..f {
            for k in 0..=i {
                set_el(&mut rt, i, k, at(x, k + i * w));
            }
        }
        rt
    };
    load_l32(x);
    let rt = r_transposed(x, tau);
    // L₃₃ (f × f, lower) for the whitening and CVA.
    let mut l33 = Small::<T, H>::zeros();
    for r in 0..f {
        let row = packed(w + r, w);
        for c in 0..=r {
            set_el(&mut l33, r, c, at(schur, row + c));
        }
    }
    // With forgetting, the weighted Gram has the weight of j_eff = Σλ^i columns.
    let sqrt_j = T::of(libm::sqrt(j_eff));
    let (gamma, sv) = match lay.method {
        Method::Cva => {
            // L_yy L_yyᵀ = Ȳ_f Π⊥ Ȳ_fᵀ = RᵀR + L₃₃L₃₃ᵀ; SVD of L_yy⁻¹ Rᵀ. The weighting is
            // its inverse square root: a pivot at the rounding level of its row (noise-free
            // data: Ȳ_f Π⊥ has rank n) would turn rounding into canonical correlations.
            let gram = outer_gram(&rt, f) + outer_gram(&l33, f);
            let lyy = small_cholesky(&gram, f, &res_floor).ok_or(Error::RankDeficient {
                stage: Stage::CvaWeighting,
            })?;
            let wtd = lower_solve(&lyy, &rt, f);
            let (u, s, _) = svd_small(wtd, f, Stage::Projection, false)?;
            let t = product(&lyy, &u, f);
            (scale_columns(t, &s, f, T::one()), s)
        }
        Method::N4sid => {
            // O = L₃₂ L₂₂⁻¹ L_W, L_W the Cholesky factor of the instruments' Gram W_p W_pᵀ.
            cholesky_packed(wgram, w, pm, tol, floor).map_err(|_| Error::RankDeficient {
                stage: Stage::InputHankel,
            })?;
            load_l32(x);
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
            let ot = r_transposed(x, tau);
            let (u, s, _) = svd_small(ot, f, Stage::Projection, false)?;
            let mut sv = s;
            for v in sv.iter_mut() {
                *v /= sqrt_j;
            }
            (scale_columns(u, &s, f, T::one()), sv)
        }
        Method::PiMoesp | Method::PoMoesp => {
            let (u, s, _) = svd_small(rt, f, Stage::Projection, false)?;
            let mut sv = s;
            for v in sv.iter_mut() {
                *v /= sqrt_j;
            }
            (scale_columns(u, &s, f, T::one()), sv)
        }
    };

    // 6. Whitened singular values of L₃₂: √((j − d)/w) · L₃₃⁻¹ Rᵀ, with L₃₃'s diagonal
    // floored at the rounding level of its row (a residual below it is rounding, not noise;
    // noise-free data then do not divide by zero, and rounding does not pass for a state).
    let mut l33f = l33;
    for (i, &fl) in white_floor.iter().enumerate().take(f) {
        l33f[(i, i)] = l33f[(i, i)].max(fl.sqrt());
    }
    let wh = lower_solve(&l33f, &rt, f);
    let scale = T::of(libm::sqrt(dof / w as f64));
    let (_, sw, _) = svd_small(wh, f, Stage::Projection, false)?;
    let mut sv_white = [T::zero(); H];
    for (v, &s) in sv_white.iter_mut().zip(&sw).take(f) {
        *v = s * scale;
    }
    let mut svo = [T::zero(); H];
    for (v, &s) in svo.iter_mut().zip(&sv).take(f) {
        *v = s;
    }
    Ok(Projection {
        j,
        sv: svo,
        sv_white,
        gamma,
    })
}

/// Relative rounding level of the Gram entries and of what is computed from them, for sums
/// over `j` (effective) columns and factorisations of dimension `dim`: recursive summation
/// leaves a relative error of about `ε·√j` in each sum, the Schur complement and the
/// Cholesky factorisation about `ε·dim` more. A residual variance below this level times
/// its row's Gram diagonal cannot be told from rounding.
fn rounding_level<T: Real>(j: f64, dim: usize) -> T {
    T::EPS * T::of(libm::sqrt(j.max(1.0)) + libm::sqrt(dim as f64))
}
