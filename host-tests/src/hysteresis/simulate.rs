//! Simulation of a hysteresis model: the simulator's play operator or relay on the model's
//! piecewise-linear borders, feeding `G(q)` started in the steady state of `w(−1)`.

use super::params::HysteresisModel;
use crate::identify::interpolate;
use crate::model::MemoryElement;
use crate::refine::signal::filter;
use crate::sim::{Backlash, Nonlinearity, Switch, border};

/// The border through `values` at `knots` (constant beyond the ends, as the two-path model's).
fn knot_border(knots: &[f64], values: &[f64]) -> crate::sim::Border {
    let (k, v) = (knots.to_vec(), values.to_vec());
    border(move |u| interpolate(&k, &v, u))
}

/// The element's output `w(t)` for the input `u`.
pub(crate) fn element_output(m: &HysteresisModel, u: &[f64]) -> Vec<f64> {
    let a = knot_border(&m.knots, &m.border_asc);
    let d = knot_border(&m.knots, &m.border_desc);
    let mut el: Box<dyn Nonlinearity> = match m.kind {
        MemoryElement::Play => Box::new(Backlash::new(a, d).with_initial_output(m.w0)),
        MemoryElement::Relay => Box::new(Switch::new(a, d)),
    };
    u.iter().map(|&x| el.step(x)).collect()
}

/// The model's output for the input `u`: `y = w_s + G(q)[w − w_s]` from rest, with
/// `w_s = w(−1)`, so that the plant starts in steady state (`G(1) = 1`). For a backlash it is
/// also the element's initial output; a relay's first output is `H_d(u(0))` whatever it is, so
/// a plant resting elsewhere (at 0 before the element is switched on at `u_min`, say) opens
/// the record with a transient that only this level represents.
pub fn simulate(m: &HysteresisModel, u: &[f64]) -> Vec<f64> {
    let w = element_output(m, u);
    let ws = m.w0;
    let dev: Vec<f64> = w.iter().map(|v| v - ws).collect();
    filter(&m.b, &m.f, &dev)
        .into_iter()
        .map(|v| v + ws)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_backlash_model_holds_its_output_inside_the_gap_and_settles_on_the_border() {
        // G = 0.5 q⁻¹ / (1 − 0.5 q⁻¹); H_a = u − 0.25, H_d = u + 0.25 on [−1, 1].
        let m = HysteresisModel {
            kind: MemoryElement::Play,
            f: vec![1.0, -0.5],
            b: vec![0.0, 0.5],
            feedthrough: false,
            knots: vec![-1.0, 1.0],
            border_asc: vec![-1.25, 0.75],
            border_desc: vec![-0.75, 1.25],
            w0: 0.0,
        };
        // Up to 0.5: w = 0.25; back to 0.3: inside the gap, w stays 0.25.
        let w = element_output(&m, &[0.5, 0.3]);
        assert_eq!(w, vec![0.25, 0.25]);
        // The plant follows with its delay: y(0) = w0 = 0, then 0.5·0.25, then 0.75·0.25 …
        let y = simulate(&m, &[0.5; 40]);
        assert_eq!(y[0], 0.0);
        assert!((y[1] - 0.125).abs() < 1e-15);
        assert!((y[39] - 0.25).abs() < 1e-9);
    }

    #[test]
    fn a_switch_model_takes_the_border_of_the_direction() {
        let m = HysteresisModel {
            kind: MemoryElement::Relay,
            f: vec![1.0],
            b: vec![1.0],
            feedthrough: true,
            knots: vec![0.0, 1.0],
            border_asc: vec![0.0, 1.0],
            border_desc: vec![0.5, 1.5],
            w0: 1.0,
        };
        // First sample on the falling border (the relay's convention), then up, then down.
        assert_eq!(simulate(&m, &[0.5, 0.6, 0.4]), vec![1.0, 0.6, 0.9]);
        // A plant resting at 0 (G = 0.5 q⁻¹/(1 − 0.5 q⁻¹)) starts from there.
        let m = HysteresisModel {
            f: vec![1.0, -0.5],
            b: vec![0.0, 0.5],
            feedthrough: false,
            w0: 0.0,
            ..m
        };
        assert_eq!(simulate(&m, &[0.5, 0.5]), vec![0.0, 0.5]);
    }
}
