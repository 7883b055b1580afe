//! The friction model read as a rigid body: `m v̇ = k u − F_v v − F_c sign(v) − F_0`.
//!
//! For an integrating plant whose stable part is of first order (or has one real pole in
//! `(0, 1)` that dominates and others faster than half a sample's decay, `|z| < 0.5`: a motor's
//! electrical lag, the computation delay of the drive) and whose element is a straight line (`H[u] = s u + c`: a static element of one segment, the linear model), the
//! model is that body sampled with a zero-order hold: the increments `Δy` are `T_s v`, `G₀ =
//! (1 − a) q⁻¹ / (1 − a q⁻¹)` with `a = exp(−F_v T_s / m)`, and the steady increment for a
//! force `w` is `w` (`G₀(1) = 1`). Matching the steady velocities, `w/T_s = (k u − …)/F_v`
//! for every `u`: with the input a force (`k = 1`), `F_v = T_s / s`, `m = −F_v T_s / ln a`,
//! `F_c = F_c′ / s` and `F_0 = (F_0′ − c)/s`, where `F_c′` and `F_0′` are the model's friction in
//! the element's units. With any other input (a voltage) the numbers are in input units per
//! output unit (`V s²/m` for a mass): multiply by the force per input unit.

use super::model::FrictionModel;

/// The model in physical terms, per unit of the input (the input a force: newtons, kilograms).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Physical {
    /// `m`: input units × s² per output unit.
    pub mass: f64,
    /// `F_v`: input units × s per output unit.
    pub viscous: f64,
    /// `F_c`: input units.
    pub coulomb: f64,
    /// `F_0`: input units (the force the drive needs to stand still on the offset).
    pub offset: f64,
    /// `v_s`: output units per second.
    pub velocity_scale: f64,
}

impl Physical {
    /// The reading of `m` with sample time `ts` (seconds); `None` unless the plant integrates,
    /// its stable part has one real pole in `(0, 1)` and any others inside `|z| < 0.5`, and
    /// the element is a line.
    pub fn of(m: &FrictionModel, ts: f64) -> Option<Self> {
        let p = &m.plant;
        if !m.integrating || ts.is_nan() || ts <= 0.0 {
            return None;
        }
        let poles = p.poles();
        let slow: Vec<f64> = poles
            .iter()
            .filter(|(re, im)| re.hypot(*im) >= 0.5)
            .map(|(re, im)| if *im == 0.0 { *re } else { f64::NAN })
            .collect();
        let [a] = slow[..] else {
            return None;
        };
        let line =
            p.knots_asc.len() == 2 && p.knots_asc == p.knots_desc && p.border_asc == p.border_desc;
        if !line {
            return None;
        }
        if !(a > 0.0 && a < 1.0) {
            return None;
        }
        let (k, v) = (&p.knots_asc, &p.border_asc);
        let s = (v[1] - v[0]) / (k[1] - k[0]);
        if !(s.abs() > 0.0 && s.is_finite()) {
            return None;
        }
        let c = v[0] - s * k[0];
        let viscous = ts / s;
        Some(Self {
            mass: -viscous * ts / a.ln(),
            viscous,
            coulomb: m.friction.coulomb / s,
            offset: (m.friction.offset - c) / s,
            velocity_scale: m.friction.velocity_scale / ts,
        })
    }
}
