//! A friction model in the project's model file: the element and `G` (`D = 0`, `G(1) = 1`)
//! as any model's, `"integrating"` for an integrating plant, and the key `"friction"`.

use super::model::FrictionModel;
use crate::identify::HostModel;
use crate::model::Element;
use crate::model_file::ModelFile;

impl FrictionModel {
    /// The model file of this model (its element of kind `element`), fitted on `samples`
    /// samples.
    pub fn to_file(&self, samples: usize, element: Element) -> ModelFile {
        let mut file = self.plant.to_json(Some(element));
        file.samples = samples;
        file.integrating = self.integrating;
        file.friction = Some(self.friction);
        file
    }

    /// The model a file with `"friction"` holds; `None` for any other file.
    pub fn from_file(file: &ModelFile) -> Option<Self> {
        let friction = file.friction?;
        Some(Self {
            plant: HostModel::from_json(file),
            integrating: file.integrating,
            friction,
        })
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use crate::friction::Friction;
    use crate::model_file::ModelFile;

    #[test]
    fn a_friction_file_reads_back_the_model_it_was_written_from() {
        let plant = HostModel {
            order: 1,
            a: nalgebra::DMatrix::from_element(1, 1, 0.9),
            b: vec![0.1],
            c: vec![1.0],
            d: 0.0,
            mu0: -1.0,
            knots_asc: vec![-1.0, 1.0],
            knots_desc: vec![-1.0, 1.0],
            border_asc: vec![-1.0, 1.0],
            border_desc: vec![-1.0, 1.0],
            singular_values: vec![1.0],
            whitened_singular_values: vec![],
            f: 10,
            p: 10,
            samples: 100,
        };
        let m = FrictionModel {
            plant,
            integrating: true,
            friction: Friction {
                coulomb: 0.2,
                velocity_scale: 1e-3,
                offset: -0.05,
                delay: 1,
                speed: false,
            },
        };
        let text = serde_json::to_string(&m.to_file(100, Element::Static)).unwrap();
        assert!(text.contains("\"friction\""), "{text}");
        let file = ModelFile::from_json_str("model.json", &text).unwrap();
        let back = FrictionModel::from_file(&file).unwrap();
        let u: Vec<f64> = (0..300).map(|t| (0.05 * t as f64).sin()).collect();
        assert_eq!(back.simulate(&u), m.simulate(&u));
        assert_eq!(back.friction, m.friction);
    }
}
