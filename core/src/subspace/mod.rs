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

mod bf;
mod blocks;
mod cross;
mod dense;
mod gram;
mod layout;
mod order;
mod outcome;
mod projection;
mod rounding;
mod schedule;
mod schur;
mod settings;
mod structured;
mod triangular;
mod weighting;
mod workspace;

pub(crate) use layout::Layout;
pub(crate) use order::select_order;
pub(crate) use outcome::Projection;
pub(crate) use projection::pi_moesp;
pub use settings::{AUTO_ORDER_MARGIN, Method, Order, SCHUR_BLOCK};
pub(crate) use structured::{Slots, bf_at, pi_moesp_structured, structured_len};
pub(crate) use workspace::too_small;
pub use workspace::{workspace_len, workspace_len_with_block};

/// Scalars the structured solve ([`Identifier::solve_structured`](crate::Identifier::solve_structured))
/// needs for `m` channels and horizons `f`, `p`: the generator of the Gram's displacement,
/// `((f + p + 1)·m + f) × max(2m + 4, f)`, and a few vectors of `m + 1` (or `B_f` and the model
/// step's scratch, if longer). Size a static array with it, e.g.
/// `[0.0f32; hsid::structured_workspace_len(14, 10, 10)]` (9,983 scalars against
/// [`workspace_len`]'s 33,041).
pub const fn structured_workspace_len(m: usize, f: usize, p: usize) -> usize {
    structured_len(Layout::new(m, f, p))
}
