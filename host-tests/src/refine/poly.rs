//! Polynomials for the refinement: the shared ones from [`crate::numerics::poly`], and the
//! stabilisation of a fitted noise numerator.

pub use crate::numerics::poly::{
    char_poly, eval_w, eval_z, from_roots, is_stable, observer_form, root_sensitivity, roots,
    spectral_radius, tf_from_ss,
};

use super::RefineError;

/// The polynomial with every root of modulus above `r_max` moved inside: `z → 1/z̄`, then
/// clamped to `r_max`. Used to make a fitted noise numerator minimum phase (the spectral
/// factor keeps the spectrum's shape).
pub fn stabilise(p: &[f64], r_max: f64) -> Result<Vec<f64>, RefineError> {
    let r = roots(p).ok_or(RefineError::Singular("roots of a noise polynomial"))?;
    if r.iter().all(|(a, b)| a.hypot(*b) < r_max) {
        return Ok(p.to_vec());
    }
    let moved: Vec<(f64, f64)> = r
        .iter()
        .map(|&(a, b)| {
            let m = a.hypot(b);
            if m >= 1.0 {
                let inv = 1.0 / (m * m);
                (a * inv, b * inv)
            } else {
                (a, b)
            }
        })
        .map(|(a, b)| {
            let m = a.hypot(b);
            if m >= r_max {
                (a * r_max / m, b * r_max / m)
            } else {
                (a, b)
            }
        })
        .collect();
    Ok(from_roots(&moved))
}
