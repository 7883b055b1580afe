//! One way to simulate every kind of model: [`Simulate`], and the model a model file holds
//! as it simulates ([`FileModel`]).

use crate::diagnose::model::ExtendedModel;
use crate::friction::FrictionModel;
use crate::hysteresis::{HysteresisFit, HysteresisModel};
use crate::identify::HostModel;
use crate::model_file::ModelFile;
use crate::reference::RefModel;
use crate::refine::stochastic::InnovationForm;

/// A model's output for an input record, from rest at `u_min`.
pub trait Simulate {
    /// The simulated output, one sample per input sample.
    fn simulate(&self, u: &[f64]) -> Vec<f64>;
}

impl Simulate for HostModel {
    fn simulate(&self, u: &[f64]) -> Vec<f64> {
        HostModel::simulate(self, u)
    }
}

impl Simulate for HysteresisModel {
    fn simulate(&self, u: &[f64]) -> Vec<f64> {
        crate::hysteresis::simulate::simulate(self, u)
    }
}

/// From rest at `u_min` (an integrating plant at the position 0).
impl Simulate for FrictionModel {
    fn simulate(&self, u: &[f64]) -> Vec<f64> {
        FrictionModel::simulate(self, u)
    }
}

impl Simulate for HysteresisFit {
    fn simulate(&self, u: &[f64]) -> Vec<f64> {
        HysteresisFit::simulate(self, u)
    }
}

/// The diagnosis's extended model on a record whose time is the sample index `0, 1, …` (as
/// [`Record::new`](crate::model::Record::new) gives it): the additive terms are
/// evaluated at those times.
impl Simulate for ExtendedModel {
    fn simulate(&self, u: &[f64]) -> Vec<f64> {
        let time: Vec<f64> = (0..u.len()).map(|t| t as f64).collect();
        ExtendedModel::simulate(self, u, &time)
    }
}

/// The plant and noise model stacked: the deterministic part alone.
impl Simulate for InnovationForm {
    fn simulate(&self, u: &[f64]) -> Vec<f64> {
        InnovationForm::simulate(self, u)
    }
}

/// The reference implementation's model.
impl Simulate for RefModel {
    fn simulate(&self, u: &[f64]) -> Vec<f64> {
        RefModel::simulate(self, u)
    }
}

/// The model of a model file, as it simulates: two paths (or one static border) before the
/// linear part, the play or relay itself (a file with `"element"`), the stable part of an
/// integrating plant (a file with `"integrating": true`, simulated as the plant's output, the
/// increments summed from 0), or a model with friction (a file with `"friction"`).
#[derive(Clone, Debug)]
pub enum FileModel {
    /// A two-path or static element, then the linear part.
    TwoPath(HostModel),
    /// The element with memory itself, then `G`.
    Element(HysteresisModel),
    /// An integrating plant's stable part.
    Integrating(HostModel),
    /// The element and `G` with friction on the velocity (a file with `"friction"`),
    /// integrating or not.
    Friction(FrictionModel),
}

impl FileModel {
    /// The model `file` holds.
    pub fn from_file(file: &ModelFile) -> Self {
        if let Some(f) = FrictionModel::from_file(file) {
            return FileModel::Friction(f);
        }
        if let Some(h) = HysteresisModel::from_file(file) {
            return FileModel::Element(h);
        }
        let m = HostModel::from_json(file);
        match file.integrating {
            true => FileModel::Integrating(m),
            false => FileModel::TwoPath(m),
        }
    }
}

impl FileModel {
    /// The element's output for the input `u`, the signal the linear part is driven by when
    /// the model simulates `u`: the border of each sample's direction (the input before the
    /// record at `u_start`, as [`HostModel::simulate_from`] takes it) for two paths or a static
    /// border, the play's or relay's output for an element with memory (which starts at its
    /// stored output whatever `u_start`). For an integrating model, the element before the
    /// stable part.
    pub fn element_output(&self, u: &[f64], u_start: f64) -> Vec<f64> {
        match self {
            FileModel::TwoPath(m) | FileModel::Integrating(m) => m.element_output_from(u, u_start),
            FileModel::Element(h) => crate::hysteresis::simulate::element_output(h, u),
            FileModel::Friction(f) => f.plant.element_output_from(u, u_start),
        }
    }
}

impl Simulate for FileModel {
    fn simulate(&self, u: &[f64]) -> Vec<f64> {
        match self {
            FileModel::TwoPath(m) => m.simulate(u),
            FileModel::Element(h) => crate::hysteresis::simulate::simulate(h, u),
            FileModel::Integrating(m) => m.simulate_integrating(u, 0.0),
            FileModel::Friction(f) => f.simulate(u),
        }
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use crate::model::MemoryElement;

    #[test]
    fn an_element_file_simulates_the_play_not_two_paths() {
        let knots = vec![-1.0, 0.0, 1.0];
        let play = HysteresisModel {
            kind: MemoryElement::Play,
            f: vec![1.0, -0.5],
            b: vec![0.0, 0.5],
            feedthrough: false,
            border_asc: knots.iter().map(|u| u - 0.2).collect(),
            border_desc: knots.iter().map(|u| u + 0.2).collect(),
            knots,
            w0: -1.2,
        };
        let file = play.to_file(100);
        let model = FileModel::from_file(&file);
        assert!(matches!(model, FileModel::Element(_)));
        // An input that reverses inside the range: the play holds its output through the gap.
        let u: Vec<f64> = (0..200).map(|t| 0.9 * (0.05 * t as f64).sin()).collect();
        let (a, b) = (model.simulate(&u), Simulate::simulate(&play, &u));
        assert_eq!(a, b);
    }
}
