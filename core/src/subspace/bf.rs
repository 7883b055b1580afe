//! `B_f = L₃₁ L₁₁⁻¹`, the regression of `Ȳ_f` on `Z_f` that the `B`, `D` step uses.

use super::cross::cross_block;
use super::gram::Source;
use super::triangular::back_substitution_transposed;
use super::workspace::too_small;
use crate::error::{Error, Stage};
use crate::linalg::{all_finite, at, set};
use crate::scalar::Real;

/// Step 3 of the solve: `B_f = G_{Ȳ_f Z_f} G_{Z_f Z_f}⁻¹ = (L₁₁⁻ᵀ X_Y)ᵀ` at the start of the
/// cache `xs`, `X_Y` the last `f` columns of `X = L₁₁⁻¹ G_{Z_f Q}`: moved from where step 2
/// left them (`y_at`), or computed anew.
///
/// [`Error::Overflow`] if `B_f` or the Schur complement `schur` is not finite,
/// [`Error::WorkspaceTooSmall`] (for a workspace of `ws_len`) if `xs` cannot hold `B_f`.
pub(super) fn regression<T: Real, const M: usize, const K: usize>(
    src: &Source<'_, T, M, K>,
    lff: &[T],
    schur: &[T],
    xs: &mut [T],
    y_at: Option<usize>,
    ws_len: usize,
) -> Result<(), Error> {
    let lay = src.lay;
    let (f, fm) = (lay.f, lay.fm());
    // X_Y moved from the last panel to B_f's place at the start of the cache.
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
            cross_block(src, lff, lay.w(), f, bf);
        }
    }
    let bf = xs.get_mut(..bf_len).ok_or(too_small(lay, ws_len))?;
    for x in bf.chunks_exact_mut(fm.max(1)).take(f) {
        back_substitution_transposed(lff, x);
    }
    if !all_finite(schur) || !all_finite(bf) {
        return Err(Error::Overflow { stage: Stage::Sums });
    }
    Ok(())
}
