//! The loop a plant specification's element travels under the Table I sweeps, in the
//! identified model's scale, for drawing beside the identified borders.

use super::element::element;
use super::error::SimulateError;
use super::plant::{linear_part, sample_time};
use super::spec::PlantSpec;

/// The true borders on a grid: `asc` travelled rising from `u_min`, `desc` falling from
/// `u_max`, both times the linear part's static gain (the identified borders carry that gain:
/// the identified linear part has a static gain of 1).
#[derive(Clone, Debug, PartialEq)]
pub struct TrueLoop {
    /// Inputs, increasing from `u_min` to `u_max`.
    pub u: Vec<f64>,
    /// `G(1) H` on the rising sweep at `u`.
    pub asc: Vec<f64>,
    /// `G(1) H` on the falling sweep at `u`.
    pub desc: Vec<f64>,
}

/// Steps the element of `spec` from rest at `u_min` up to `u_max` and back down on `points`
/// equally spaced inputs (at least 2).
pub fn true_loop(
    spec: &PlantSpec,
    u_min: f64,
    u_max: f64,
    points: usize,
) -> Result<TrueLoop, SimulateError> {
    let g = linear_part(&spec.plant, sample_time(spec.ts)?)?.static_gain();
    let mut el = element(&spec.element)?;
    let n = points.max(2);
    let u: Vec<f64> = (0..n)
        .map(|i| u_min + (u_max - u_min) * i as f64 / (n - 1) as f64)
        .collect();
    el.reset();
    el.step(u_min);
    let asc: Vec<f64> = u.iter().map(|&v| g * el.step(v)).collect();
    let mut desc: Vec<f64> = u.iter().rev().map(|&v| g * el.step(v)).collect();
    desc.reverse();
    Ok(TrueLoop { u, asc, desc })
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    #[test]
    fn a_symmetric_backlash_of_gap_g_is_a_parallelogram_of_width_g() {
        // Gap 0.2, slope 1, through the linear part of static gain 2 (num 0.2 q⁻¹, den 1 − 0.9 q⁻¹).
        let spec = PlantSpec::from_json_str(
            r#"{"element": {"kind": "backlash", "shape": "backlash", "gap": 0.2, "slope": 1.0},
                "plant": {"num": [0.0, 0.2], "den": [1.0, -0.9]}}"#,
        )
        .unwrap();
        let t = true_loop(&spec, -1.0, 1.0, 21).unwrap();
        assert_eq!(t.u.len(), 21);
        // Rising from rest at −1: flat until the play of 0.2 is taken up, then slope 1 (×2).
        let at = |v: &[f64], u: f64| v[((u + 1.0) * 10.0).round() as usize];
        assert!((at(&t.asc, -0.8) - at(&t.asc, -1.0)).abs() < 1e-12);
        assert!((at(&t.asc, 0.5) - at(&t.asc, 0.0) - 1.0).abs() < 1e-12);
        // Falling from 1: the loop's height is slope × gap × G(1) = 0.4 inside.
        assert!((at(&t.desc, 0.0) - at(&t.asc, 0.0) - 0.4).abs() < 1e-12);
    }
}
