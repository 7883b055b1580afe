//! PI-MOESP from the accumulated Gram (see the [module docs](super)): the steps in order, each
//! in its own file; the outcome, [`Projection`], in its own.

use super::bf::regression;
use super::blocks::{l33, load_l32, qr_scratch, r_transposed};
use super::gram::{Source, diagonal_blocks};
use super::layout::Layout;
use super::order::whitened;
use super::outcome::Projection;
use super::rounding::Rounding;
use super::schur::schur_complement;
use super::weighting::Weighting;
use super::workspace::too_small;
use crate::accumulation::{Accumulator, OutputRounding};
use crate::error::{Error, Stage};
use crate::linalg::{at, cholesky_packed, packed};
use crate::regressor::{Basis, Knots};
use crate::scalar::Real;

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
    check_horizons::<K, H>(lay)?;
    let (f, q, pm, w) = (lay.f, lay.q(), lay.p * lay.m, lay.w());
    let ws_len = ws.len();
    let [lff, schur, wgram, tail] = lay.carve_front(ws)?;
    // Until step 4 the raw diagonals (below) sit at the end of the tail, and the rest of it
    // (B_f, the column blocks and the scratch) is the cache of step 2.
    let (xs, g) = tail
        .split_at_mut_checked(tail.len().saturating_sub(q))
        .ok_or(too_small(lay, ws_len))?;
    let sums = centred.then(|| acc.row_sums(knots, basis));
    let src = Source::new(acc, knots, basis, lay, sums.as_ref());
    let j_eff = acc.effective_columns().to_f64();
    let rounding = Rounding::<T>::new(j_eff, lay.d() + q, output_rounding);
    let tol = T::EPS * T::of_usize(8 * (lay.d() + q));

    // 1. G_{Z_f Z_f} and G_{QQ} (Q = [Z_p; Ȳ_f]), their rounding floors, and L₁₁.
    let floor = input_blocks(&src, &rounding, lff, schur, wgram, g)?;
    let floor = &floor[..(q - pm).min(K)];
    cholesky_packed(lff, lay.fm(), lay.fm(), tol, &[]).map_err(|_| Error::RankDeficient {
        stage: Stage::InputHankel,
    })?;

    // 2. The Schur complement S, 3. B_f at the start of the cache.
    let y_at = schur_complement(&src, lff, schur, xs, ws_len)?;
    regression(&src, lff, schur, xs, y_at, ws_len)?;

    // 4. Cholesky of S: Z_p rows must be positive definite; Ȳ_p and Ȳ_f rows may be singular
    // (noise-free data).
    cholesky_packed(schur, q, pm, tol, floor).map_err(|_| Error::RankDeficient {
        stage: Stage::InputHankel,
    })?;
    let dof = (rounding.j_eff - (lay.d() + lay.py()) as f64).max(1.0);
    let (res_floor, white_floor) = rounding.residual_floors::<H>(schur, g, lay, dof);

    // 5. Rᵀ from the QR of L₃₂ᵀ (w × f) in the scratch, and the weighting's Γ_f and
    // singular values.
    let (x, tau) = qr_scratch(lay, tail, ws_len)?;
    load_l32(x, schur, w, f);
    let mut rt = r_transposed::<T, H>(x, tau, w, f);
    let mut l33 = l33::<T, H>(schur, w, f);
    let (gamma, sv) = Weighting {
        lay,
        schur,
        rt: &rt,
        l33: &l33,
        res_floor: &res_floor,
        tol,
        floor,
        sqrt_j: T::of(libm::sqrt(rounding.j_eff)),
    }
    .gamma(wgram, x, tau)?;

    // 6. Whitened singular values for the order.
    let sv_white = whitened(&mut l33, &white_floor, &mut rt, dof, lay)?;
    Ok(Projection {
        j: acc.columns(),
        sv: leading(&sv, f),
        sv_white,
        gamma,
    })
}

/// Step 1 of the solve: `G_{Z_f Z_f}` into `lff`, `G_QQ` into `schur` (and `wgram`), the raw
/// diagonal of every row of `[Z_p; Ȳ_p; Ȳ_f]` into `g`.
/// Returns the rounding floors of the rows of `S` that may be singular. (`L₁₁`'s factorisation
/// stays in [`pi_moesp`]: factored here, the Cortex-M4 firmware's solve took 26,442,800
/// instead of 26,197,840 instructions, `scripts/firmware-measure.sh`.)
fn input_blocks<T: Real, const M: usize, const K: usize>(
    src: &Source<'_, T, M, K>,
    rounding: &Rounding<T>,
    lff: &mut [T],
    schur: &mut [T],
    wgram: &mut [T],
    g: &mut [T],
) -> Result<[T; K], Error> {
    let (q, pm) = (src.lay.q(), src.lay.p * src.lay.m);
    diagonal_blocks(src, lff, schur, wgram)?;
    let floor = rounding.input_floors::<K>(schur, pm, q);
    for (r, g) in g.iter_mut().enumerate().take(q) {
        *g = at(schur, packed(r, r)).abs();
    }
    Ok(floor)
}

/// The horizons' checks: both refused by `Identifier::new`; kept here so that no layout can
/// index past the QR or the small matrices.
pub(super) fn check_horizons<const K: usize, const H: usize>(lay: Layout) -> Result<(), Error> {
    let f = lay.f;
    if !(2..=H).contains(&f) {
        return Err(Error::InvalidHorizon {
            f,
            k: f + lay.p,
            max_f: H,
            max_k: K,
        });
    }
    if lay.w() < f {
        return Err(Error::TooFewInstruments {
            f,
            p: lay.p,
            channels: lay.m,
            past_outputs: lay.method.past_outputs(),
        });
    }
    Ok(())
}

/// The first `n` entries of `v`, zero after them.
pub(super) fn leading<T: Real, const H: usize>(v: &[T; H], n: usize) -> [T; H] {
    let mut out = [T::zero(); H];
    for (o, &s) in out.iter_mut().zip(v).take(n) {
        *o = s;
    }
    out
}
