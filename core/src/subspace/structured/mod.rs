//! PI-MOESP from the lagged sums by the generalised Schur algorithm (T. Kailath, A. H. Sayed,
//! *Displacement structure: theory and applications*, SIAM Review 37, 1995): the same
//! projection as [`pi_moesp`](super::pi_moesp) in a workspace of about `((k+1)·m + f)·(2m+4)`
//! scalars instead of the dense solve's `(f·m)²/2 + (p·m + f)²/2`, because neither the Gram nor
//! `L` is ever stored.
//!
//! # Displacement structure
//!
//! Order the rows of `M = [Z_f; Z_p; Ȳ_f]` by group and by *reversed* lag (`z` at lags
//! `k−1 … 0`, then `ȳ` at lags `k−1 … p`). The shift `F` (down one lag within a group) maps
//! the row of lag `ℓ + 1` onto that of lag `ℓ`, and two rows of the Gram differ from their
//! shifts only by the products of the samples at the window's two ends:
//! `G[(i,ℓ),(i',ℓ')] − G[(i,ℓ+1),(i',ℓ'+1)] = w_i(ℓ) w_i'(ℓ') − w_i(ℓ+j) w_i'(ℓ'+j)`, the
//! first rows `𝓕` (lag `k − 1`) keeping theirs. So `G − F G Fᵀ = X J Xᵀ` with the generator
//! `X = [u h₊ | v h₋]`, `u = G[:, 𝓕] L₀⁻ᵀ`, `v` = `u` off `𝓕`, `h₊ = w(ℓ)`, `h₋ = w(ℓ + j)`,
//! signature `J = diag(I_{c+1}, −I_{c+1})`: rank `r = 2c + 2` (`c = m + 1`), from the
//! accumulator's `R_τ` and its first and last samples. Bordering the Gram with the identity on
//! the `Z_f` rows (`[[G, E], [Eᵀ, 0]]`) costs no rank and gives `−B_f = −G_{Ȳ_f Z_f}
//! G_{Z_f Z_f}⁻¹` as the Schur complement's block between the output rows and the identity
//! rows once `Z_f` is eliminated; its rows enter in the slots of eliminated input rows, so the
//! generator never has more than `(k + 1)·m + f` rows ([`Slots`]).
//!
//! # Steps
//!
//! Each of the `(f + p)·m` input rows is eliminated in turn ([`step::reduce`]: two Householder
//! reflections and a hyperbolic rotation in the mixed form; `δ²` must clear the pivot
//! tolerance against the row's Gram diagonal, else [`Error::RankDeficient`]). After `Z_f`,
//! `B_f` is read by its Stein equation and written over the dead identity rows; the columns
//! of `L` from the `Z_p` steps are `L₃₂`'s, folded into `Rᵀ` (`L₃₂ = Rᵀ Qᵀ`) by Givens
//! rotations and into the residual rounding floors as they come; at the end `S_Φ = L₃₃L₃₃ᵀ`
//! is the Stein solution on the output rows, factored with the same floors as the dense
//! solve. From `Rᵀ` and `L₃₃` on, the solve is the dense one's ([`super::weighting`],
//! [`super::order`]). No pivot is taken on `Ȳ_f`: noise-free data are no failure.
//!
//! # Scope
//!
//! The shift structure needs the rows of the Gram to be one sequence's lags with equal weights:
//! no centring ([`MuZero::Estimate`](crate::MuZero::Estimate)), no forgetting, and no past
//! outputs among the instruments (PI-MOESP). Those are [`Error::NotShiftStructured`]; the
//! dense [`Identifier::solve`](crate::Identifier::solve) takes them.
//!
//! # Accuracy and cost
//!
//! The same model as the dense solve within `f32` rounding (the tests bound the poles at `1e-4`
//! relative and the borders at `1e-3`); about `(4c + 8)` multiply-adds per live row and step,
//! `≈ 3.8·10⁶` for the paper's `(m, f, p) = (14, 10, 10)`, plus the generator's build; the
//! firmware's measurement table (`scripts/firmware-measure.sh`) has both solves' counts.

mod generator;
mod slots;
mod stein;
mod step;

pub(crate) use slots::{Slots, structured_len};
pub(crate) use stein::bf_at;

use super::dense::transpose_lower_into;
use super::layout::Layout;
use super::order::whitened;
use super::outcome::Projection;
use super::projection::{check_horizons, leading};
use super::rounding::Rounding;
use super::weighting::pi_moesp_gamma;
use crate::accumulation::{Accumulator, OutputRounding};
use crate::error::{Error, Stage};
use crate::linalg::{Small, all_finite, at, cholesky_packed, el, packed, set_el, sub_mut};
use crate::regressor::{Basis, Knots};
use crate::scalar::Real;
use generator::{Sums, build};

/// The projection of PI-MOESP by the generalised Schur algorithm (see the module docs) into
/// `out` (in the caller's frame: no copy of it on the stack), `ws` at least [`structured_len`]
/// scalars; `B_f` is left in `ws`'s identity slots ([`bf_at`]), the rest of `ws` is free for
/// the model's steps from `fm · stride` on.
pub(crate) fn pi_moesp_structured<T: Real, const M: usize, const K: usize, const H: usize>(
    acc: &Accumulator<T, M, K>,
    knots: &Knots<T, M>,
    basis: Basis,
    lay: Layout,
    output_rounding: OutputRounding,
    ws: &mut [T],
    out: &mut Projection<T, H>,
) -> Result<(), Error> {
    check_horizons::<K, H>(lay)?;
    let need = structured_len(lay);
    if ws.len() < need {
        return Err(Error::WorkspaceTooSmall {
            need,
            have: ws.len(),
        });
    }
    let src = Sums {
        acc,
        knots,
        basis,
        sl: Slots::of(lay),
    };
    let j_eff = acc.effective_columns().to_f64();
    let rounding = Rounding::<T>::new(j_eff, lay.d() + lay.q(), output_rounding);
    let mut fac = Factors {
        rt: Small::zeros(),
        l33: Small::zeros(),
        white_floor: [T::zero(); H],
    };
    factor(&src, lay, &rounding, ws, &mut fac)?;
    // 4. Γ_f and the singular values from Rᵀ, the whitened ones for the order.
    let f = lay.f;
    let sv = pi_moesp_gamma(&fac.rt, f, T::of(libm::sqrt(j_eff)), &mut out.gamma)?;
    out.sv = leading(&sv, f);
    let dof = (j_eff - lay.d() as f64).max(1.0);
    out.sv_white = whitened(&mut fac.l33, &fac.white_floor, &mut fac.rt, dof, lay)?;
    out.j = acc.columns();
    Ok(())
}

/// What the generator's elimination leaves for the small steps: `Rᵀ` (`L₃₂ = Rᵀ Qᵀ`), `L₃₃`
/// and the whitening's rounding floors.
struct Factors<T, const H: usize> {
    rt: Small<T, H>,
    l33: Small<T, H>,
    white_floor: [T; H],
}

/// Steps 1–3 of the structured solve into `fac`. Not inlined, so that its scratch is off the
/// stack before the small SVDs run.
#[inline(never)]
fn factor<T: Real, const M: usize, const K: usize, const H: usize>(
    src: &Sums<'_, T, M, K>,
    lay: Layout,
    rounding: &Rounding<T>,
    ws: &mut [T],
    fac: &mut Factors<T, H>,
) -> Result<(), Error> {
    let sl = src.sl;
    let too_small = Error::WorkspaceTooSmall {
        need: structured_len(lay),
        have: ws.len(),
    };
    let (x, aux) = ws
        .split_at_mut_checked(sl.generator_len())
        .ok_or(too_small)?;
    let f = lay.f;
    let tol = T::EPS * T::of_usize(8 * (lay.d() + lay.q()));
    let deficient = Error::RankDeficient {
        stage: Stage::InputHankel,
    };

    // 1. The generator, and the raw diagonals of the output rows (natural order).
    if !build(src, x, aux, tol) {
        return Err(deficient);
    }
    if !all_finite(x) {
        return Err(Error::Overflow { stage: Stage::Sums });
    }
    let mut g_y = [T::zero(); H];
    for (a, g) in g_y.iter_mut().enumerate().take(f) {
        *g = src.diagonal(sl.m, lay.p + a, aux);
    }

    // 2. Eliminate Z_f (then B_f over the identity rows) and Z_p (Rᵀ and the floors' sums).
    let mut elim = Elimination::<T, H>::new();
    for s in 0..sl.km {
        let (ch, lag) = sl.z_row(s);
        let g = src.diagonal(ch, lag, aux);
        let d2 = step::reduce(x, &sl, s, aux)
            .filter(|&d2| d2 > tol * g && d2.finite())
            .ok_or(deficient)?;
        if s >= sl.fm {
            elim.add(x, &sl, d2, g);
        }
        step::shift(x, &sl, s);
        if s + 1 == sl.fm {
            let mut col = [T::zero(); H];
            stein::regression_in_place(x, &sl, &mut col);
        }
    }

    // 3. S_Φ (packed, over the dead Z_p slots) and its Cholesky factor L₃₃, with the dense
    // solve's floors.
    let (front, ys) = x.split_at_mut_checked(sl.off(sl.y(0))).ok_or(too_small)?;
    let sphi = sub_mut(front, sl.off(sl.z(sl.fm)), sl.off(sl.y(0)));
    stein::outputs_packed(ys, &sl, sphi);
    let mut floor = [T::zero(); H];
    for (fl, &g) in floor.iter_mut().zip(&g_y).take(f) {
        *fl = rounding.level * g.abs();
    }
    cholesky_packed(sphi, f, 0, tol, &floor[..f.min(H)]).map_err(|_| deficient)?;
    for r in 0..f {
        for c in 0..=r {
            set_el(&mut fac.l33, r, c, at(sphi, packed(r, c)));
        }
    }
    if !all_finite(fac.l33.as_slice()) {
        return Err(Error::Overflow { stage: Stage::Sums });
    }
    let j_eff = src.acc.effective_columns().to_f64();
    let dof = (j_eff - lay.d() as f64).max(1.0);
    fac.white_floor = rounding.floors(&g_y, &elim.e, &elim.noise, dof, lay).1;
    transpose_lower_into(&elim.r, &mut fac.rt, f);
    Ok(())
}

/// What the `Z_p` steps leave: `R` (upper, `RᵀR = L₃₂L₃₂ᵀ`) and, per output row `a`, the sums
/// of the residual floors (see [`Rounding::floors`]): `Σ_i 2 L₃₂[a,i]² g_i / d_i²` and
/// `Σ_i g_i / d_i²` (`d_i` the pivot, `g_i` its row's raw Gram diagonal).
struct Elimination<T, const H: usize> {
    r: Small<T, H>,
    e: [T; H],
    noise: [T; H],
}

impl<T: Real, const H: usize> Elimination<T, H> {
    fn new() -> Self {
        Self {
            r: Small::zeros(),
            e: [T::zero(); H],
            noise: [T::zero(); H],
        }
    }

    /// Folds in the column of `L` left in column 0 of the output rows by a `Z_p` step with
    /// pivot `d2 = δ²` and raw diagonal `g`.
    fn add(&mut self, x: &[T], sl: &Slots, d2: T, g: T) {
        let f = sl.f.min(H);
        let mut l = [T::zero(); H];
        for (a, v) in l.iter_mut().enumerate().take(f) {
            *v = at(x, sl.off(sl.y(f - 1 - a)));
        }
        let sums = self.e.iter_mut().zip(self.noise.iter_mut());
        for ((e, n), &v) in sums.zip(&l).take(f) {
            *e += (v + v) * v / d2 * g;
            *n += g / d2;
        }
        // R ← the triangle of [R; lᵀ], by Givens rotations.
        for i in 0..f {
            let (a, b) = (el(&self.r, i, i), at(&l, i));
            if b == T::zero() {
                continue;
            }
            let h = (a * a + b * b).sqrt();
            let (c, s) = (a / h, b / h);
            for jj in i..f {
                let (rij, lj) = (el(&self.r, i, jj), at(&l, jj));
                set_el(&mut self.r, i, jj, c * rij + s * lj);
                if let Some(v) = l.get_mut(jj) {
                    *v = c * lj - s * rij;
                }
            }
        }
    }
}
