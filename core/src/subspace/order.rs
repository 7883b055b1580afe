//! The model order: given, or counted from the whitened singular values against the
//! noise-only edge (see the [module docs](super)).

use super::dense::lower_solve;
use super::{AUTO_ORDER_MARGIN, Layout, Order, Projection};
use crate::error::{Error, Stage};
use crate::linalg::{Small, svd_small};
use crate::scalar::Real;

/// Step 6 of the solve: the whitened singular values of `L₃₂`, `√((j − d)/w) · L₃₃⁻¹ Rᵀ`
/// (`dof = j − d`), with `L₃₃`'s diagonal floored at the rounding level of its row
/// (`white_floor`; a residual below it is rounding, not noise: noise-free data then do not
/// divide by zero, and rounding does not pass for a state).
pub(super) fn whitened<T: Real, const H: usize>(
    l33: &Small<T, H>,
    white_floor: &[T; H],
    rt: &Small<T, H>,
    dof: f64,
    lay: Layout,
) -> Result<[T; H], Error> {
    let (f, w) = (lay.f, lay.w());
    let mut l33f = *l33;
    for (i, &fl) in white_floor.iter().enumerate().take(f) {
        l33f[(i, i)] = l33f[(i, i)].max(fl.sqrt());
    }
    let wh = lower_solve(&l33f, rt, f);
    let scale = T::of(libm::sqrt(dof / w as f64));
    let (_, sw, _) = svd_small(wh, f, Stage::Projection, false)?;
    let mut sv_white = [T::zero(); H];
    for (v, &s) in sv_white.iter_mut().zip(&sw).take(f) {
        *v = s * scale;
    }
    Ok(sv_white)
}

/// The order: fixed, or counted from the whitened singular values.
pub(crate) fn select_order<T: Real, const H: usize>(
    order: Order,
    proj: &Projection<T, H>,
    lay: Layout,
) -> Result<usize, Error> {
    match order {
        Order::Fixed(n) => Ok(n),
        Order::Auto => {
            let edge = 1.0 + libm::sqrt(lay.f as f64 / lay.w() as f64);
            let thr = T::of(AUTO_ORDER_MARGIN * edge);
            let n = proj
                .sv_white
                .iter()
                .take(lay.f)
                .take_while(|&&s| s > thr)
                .count();
            match n {
                0 => Err(Error::NoDynamics),
                n => Ok(n.min(lay.f - 1)),
            }
        }
    }
}
