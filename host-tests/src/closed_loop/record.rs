//! The closed-loop estimate on a whole record (hold first), with the desktop identification's
//! options, as a [`HostModel`].

use crate::closed_loop::error::ReferenceError;
use crate::closed_loop::reference_iv::identify_with_reference;
use crate::identify::{HostModel, IdentifyOptions};
use crate::reference::{RefConfig, RefModel, mu0_from_hold};

/// The closed-loop estimate of the record `(u, y)` with its reference `r` (all three with the
/// hold of `opts.hold` samples first), with the knots and horizons of `opts` and the given
/// `order` (the caller picks it, e.g. the order of the open-loop estimate: feedback biases the
/// poles, not the count of states). μ0 is the mean of the hold after `opts.settle` samples,
/// or `opts.mu0` without a hold.
pub fn identify_closed_loop(
    u: &[f64],
    y: &[f64],
    r: &[f64],
    opts: &IdentifyOptions,
    order: usize,
) -> Result<HostModel, ReferenceError> {
    if opts.static_nonlinearity {
        return Err(ReferenceError::StaticElement);
    }
    if u.len() != y.len() || u.len() != r.len() {
        return Err(ReferenceError::LengthMismatch {
            u: u.len(),
            y: y.len(),
            r: r.len(),
        });
    }
    let hold = opts.hold.min(u.len());
    let mu0 = match (hold, opts.mu0) {
        (0, Some(m)) => m,
        (0, None) => return Err(ReferenceError::NoMuZero),
        _ => mu0_from_hold(&y[..hold], opts.settle),
    };
    let cfg = RefConfig {
        u_min: opts.u_min(),
        u_max: opts.u_max(),
        knots_asc: opts.knots_asc.clone(),
        knots_desc: opts.knots_desc.clone(),
        f: opts.f,
        p: opts.p,
        order,
    };
    let model = identify_with_reference(&u[hold..], &y[hold..], &r[hold..], mu0, &cfg)?;
    Ok(host_model(&model, &cfg, u.len()))
}

/// The [`HostModel`] of a reference-form model (no whitened singular values).
fn host_model(m: &RefModel, cfg: &RefConfig, samples: usize) -> HostModel {
    HostModel {
        order: m.order(),
        a: m.a.clone(),
        b: m.b.iter().copied().collect(),
        c: m.c.iter().copied().collect(),
        d: m.d,
        mu0: m.mu0,
        knots_asc: m.knots_asc.clone(),
        knots_desc: m.knots_desc.clone(),
        border_asc: m.border_asc.clone(),
        border_desc: m.border_desc.clone(),
        singular_values: m.singular_values.clone(),
        whitened_singular_values: Vec::new(),
        f: cfg.f,
        p: cfg.p,
        samples,
    }
}
