//! The model order: given, or counted from the whitened singular values against the
//! noise-only edge (see the [module docs](super)).

use super::{AUTO_ORDER_MARGIN, Layout, Order, Projection};
use crate::error::Error;
use crate::scalar::Real;

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
