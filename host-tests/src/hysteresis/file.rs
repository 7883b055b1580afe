//! A hysteresis model in the project's model file: the plant in observer form with `G(1) = 1`,
//! `μ0 = w(−1)`, the borders on one set of knots and the key `"element"` (`"play"` or
//! `"relay"`), which tells a reader to simulate the element itself and which a reader that
//! does not know it refuses rather than simulate the file as a two-path model.

use super::params::HysteresisModel;
use crate::identify::HostModel;
use crate::model_file::ModelFile;
use crate::numerics::poly::tf_from_ss;

impl HysteresisModel {
    /// The model file of this model, fitted on `samples` samples.
    pub(crate) fn to_file(&self, samples: usize) -> ModelFile {
        let mut file = self.to_host(samples).to_json(Some(self.kind.element()));
        file.element = Some(self.kind);
        file
    }

    /// The model a file with an `"element"` holds; `None` for a two-path file. The file is
    /// taken as read by [`ModelFile::load`], which checked that both borders share the knots.
    pub fn from_file(file: &ModelFile) -> Option<Self> {
        let kind = file.element?;
        let h = HostModel::from_json(file);
        let (b, f) = tf_from_ss(&h.a, &h.b, &h.c, h.d);
        Some(Self {
            kind,
            f,
            b,
            feedthrough: h.d != 0.0,
            knots: file.knots_asc.clone(),
            border_asc: file.border_asc.clone(),
            border_desc: file.border_desc.clone(),
            w0: file.mu0,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::super::simulate::simulate;
    use super::*;
    use crate::model::MemoryElement;

    #[test]
    fn a_model_file_round_trips_through_json_and_simulates_the_same() {
        let knots = vec![-3.0, -1.0, 1.0, 3.0];
        let m = HysteresisModel {
            kind: MemoryElement::Play,
            f: vec![1.0, -1.8858, 0.9048],
            b: vec![0.0, 0.1994, -0.1804],
            feedthrough: false,
            border_asc: knots.iter().map(|u| u - 0.3).collect(),
            border_desc: knots.iter().map(|u| u + 0.3).collect(),
            knots,
            w0: 0.0,
        };
        let text = m.to_file(100).to_json_string("m.json");
        let text = text.unwrap_or_else(|e| e.to_string());
        assert!(text.contains("\"element\": \"play\""), "{text}");
        let back = ModelFile::from_json_str("m.json", &text)
            .ok()
            .and_then(|f| HysteresisModel::from_file(&f));
        assert!(back.is_some(), "not read back: {text}");
        let Some(back) = back else { return };
        let u: Vec<f64> = (0..300).map(|t| 2.9 * (0.05 * t as f64).sin()).collect();
        let (a, b) = (simulate(&m, &u), simulate(&back, &u));
        let off = a
            .iter()
            .zip(&b)
            .fold(0.0f64, |s, (x, y)| s.max((x - y).abs()));
        assert!(off < 1e-9, "{off}");
        assert_eq!(back.kind, MemoryElement::Play);
        // A relay element under a backlash is refused.
        let bad = text.replace("\"element\": \"play\"", "\"element\": \"relay\"");
        assert!(ModelFile::from_json_str("m.json", &bad).is_err());
    }
}
