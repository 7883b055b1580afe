//! The model order: given, or counted from the whitened singular values against the
//! noise-only edge (see the [module docs](super)).

use super::dense::lower_solve_in_place;
use super::layout::Layout;
use super::outcome::Projection;
use super::settings::{AUTO_ORDER_MARGIN, Order};
use crate::error::{Error, Stage};
use crate::linalg::{Small, el, set_el, svd_in_place};
use crate::scalar::Real;

/// Step 6 of the solve: the whitened singular values of `L₃₂`, `√((j − d)/w) · L₃₃⁻¹ Rᵀ`
/// (`dof = j − d`), with `L₃₃`'s diagonal floored at the rounding level of its row
/// (`white_floor`; a residual below it is rounding, not noise: noise-free data then do not
/// divide by zero, and rounding does not pass for a state). `l33` and `rt` are overwritten
/// (the floored `L₃₃`, the whitened matrix's left singular vectors): no copies on the stack.
pub(super) fn whitened<T: Real, const H: usize>(
    l33: &mut Small<T, H>,
    white_floor: &[T; H],
    rt: &mut Small<T, H>,
    dof: f64,
    lay: Layout,
) -> Result<[T; H], Error> {
    let (f, w) = (lay.f, lay.w());
    for (i, &fl) in white_floor.iter().enumerate().take(f) {
        set_el(l33, i, i, el(l33, i, i).max(fl.sqrt()));
    }
    lower_solve_in_place(l33, rt, f);
    let scale = T::of(libm::sqrt(dof / w as f64));
    let sw = svd_in_place(rt, None, f, Stage::Projection)?;
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
