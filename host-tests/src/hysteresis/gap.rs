//! The play of a backlash model in input units, and the model as a [`HostModel`] (observer
//! form, the element's borders in place of the paths) for the shared unit conversions and the
//! model file.

use hsid::Direction;

use super::params::HysteresisModel;
use crate::identify::HostModel;
use crate::numerics::poly::observer_form;

impl HysteresisModel {
    /// The model as a [`HostModel`]: `G` in observer canonical form, `μ0 = w(−1)`, and `H_a`,
    /// `H_d` as the borders on the knots.
    pub fn to_host(&self, samples: usize) -> HostModel {
        let (a, b, c, d) = observer_form(&self.b, &self.f);
        let mu0 = self.w0;
        HostModel {
            order: self.f.len() - 1,
            a,
            b,
            c,
            d,
            mu0,
            knots_asc: self.knots.clone(),
            knots_desc: self.knots.clone(),
            border_asc: self.border_asc.clone(),
            border_desc: self.border_desc.clone(),
            singular_values: Vec::new(),
            whitened_singular_values: Vec::new(),
            f: 0,
            p: 0,
            samples,
        }
    }

    /// The play at the middle of the input range: the input travel after a reversal before
    /// the output moves again, averaged over a reversal from rising and one from falling
    /// (equal for a play of constant width). `None` when a border never reaches the other's
    /// value there.
    pub fn gap(&self) -> Option<f64> {
        let m = self.to_host(0);
        let mid = 0.5 * (m.u_min() + m.u_max());
        let up = m.gap_at(Direction::Ascending, mid)?;
        let down = m.gap_at(Direction::Descending, mid)?;
        Some(0.5 * (up + down))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::MemoryElement;

    #[test]
    fn the_gap_of_a_play_of_constant_width_is_its_width() {
        // H_a = 2(u − 0.15), H_d = 2(u + 0.15): the play is 0.3.
        let k = vec![-1.0, 0.0, 1.0];
        let m = HysteresisModel {
            kind: MemoryElement::Play,
            f: vec![1.0, -0.5],
            b: vec![0.0, 0.5],
            feedthrough: false,
            border_asc: k.iter().map(|u| 2.0 * (u - 0.15)).collect(),
            border_desc: k.iter().map(|u| 2.0 * (u + 0.15)).collect(),
            knots: k,
            w0: 0.0,
        };
        let g = m.gap().unwrap_or(f64::NAN);
        assert!((g - 0.3).abs() < 1e-12, "{g}");
        // The host form has the same static gain (1) and pole.
        let h = m.to_host(0);
        assert!((h.a[(0, 0)] - 0.5).abs() < 1e-15);
        assert!((h.freq_response(0.0).0 - 1.0).abs() < 1e-12);
    }
}
