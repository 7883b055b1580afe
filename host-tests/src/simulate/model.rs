//! An identified model driven by any input: the two-path element with memory (δ(t)), the
//! linear part and, on request, output noise — white, or coloured by the model's own noise
//! model `C(q)/D(q)` (its innovation form), at the stored `σ_e²` or a given level.

use super::error::SimulateError;
use super::input::InputRecord;
use super::noise::{Level, Noise, white};
use super::output::Output;
use super::plant::transfer;
use crate::identify::HostModel;
use crate::model::{OutsideInterval, Simulate, first_outside, for_input};
use crate::refine::NoiseModel;

/// The colour of the noise added to a model's output.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Colour {
    /// White.
    White,
    /// The model file's noise model `C(q)/D(q)`.
    Model,
}

/// Noise added to a model's output.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ModelNoise {
    /// The colour.
    pub colour: Colour,
    /// The level; `None` uses the noise model's stored `σ_e²` (colour [`Colour::Model`] only).
    pub level: Option<Level>,
    /// Seed of the PCG32 generator.
    pub seed: u64,
}

/// How a model is simulated.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ModelOptions {
    /// Inputs outside `[u_min, u_max]` are an error (the first one is named). Without it
    /// (the default) the borders continue linearly beyond the interval on the end segments'
    /// lines, and the samples outside are counted.
    pub strict_interval: bool,
    /// Output noise; none when `None`.
    pub noise: Option<ModelNoise>,
    /// The model is the stable part of an integrating plant (the model file's
    /// `"integrating": true`): its output, the increments, is summed from 0 before any noise
    /// is added, so the result is the plant's output. Only white noise applies.
    pub integrating: bool,
}

/// The first input outside the model's interval, as an error.
fn check_range(model: &HostModel, input: &InputRecord) -> Result<(), SimulateError> {
    let (lo, hi) = (model.u_min(), model.u_max());
    match first_outside(&input.u, lo, hi) {
        Some(i) => Err(SimulateError::InputOutsideModel {
            file: input.source.clone(),
            line: input.lines[i],
            value: input.u[i],
            lo,
            hi,
        }),
        None => Ok(()),
    }
}

/// Simulates `model` on the input record (see [`HostModel::simulate`]: the model starts at rest
/// at μ0 with the previous input at its lowest knot), sums the output when the model
/// integrates, and adds the requested noise. An input outside the model's interval extends
/// the borders to it (see [`for_input`]), and the samples outside are counted in the
/// [`OutsideInterval`] returned; with [`ModelOptions::strict_interval`] it is an error.
pub fn simulate_model(
    model: &HostModel,
    noise_model: Option<&NoiseModel>,
    input: &InputRecord,
    opts: &ModelOptions,
) -> Result<(Output, Option<OutsideInterval>), SimulateError> {
    if opts.strict_interval {
        check_range(model, input)?;
    }
    let (model, outside) = for_input(model, &input.u);
    let y_clean = model.simulate(&input.u);
    let y_clean = if opts.integrating {
        crate::integrating::integrate(&y_clean, 0.0)
    } else {
        y_clean
    };
    let Some(n) = opts.noise else {
        return Ok((Output::clean(y_clean), outside));
    };
    let (filter, level) = match (n.colour, n.level) {
        (Colour::White, None) => return Err(SimulateError::NoNoiseLevel),
        (Colour::White, Some(l)) => (white(), l),
        (Colour::Model, _) if opts.integrating => return Err(SimulateError::IncrementsNoiseModel),
        (Colour::Model, l) => {
            let nm = noise_model.ok_or(SimulateError::NoNoiseModel)?;
            let filter = transfer(nm.c.clone(), nm.d.clone(), "noise")?;
            (filter, l.unwrap_or(Level::Std(nm.sigma2.sqrt())))
        }
    };
    let noise = Noise {
        filter,
        level,
        seed: n.seed,
    };
    Ok((Output::noisy(y_clean, &noise)?, outside))
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use crate::model::Interval;

    fn first_order() -> HostModel {
        HostModel::first_order_for_tests()
    }

    #[test]
    fn an_integrating_model_sums_its_increments_and_refuses_its_noise_model() {
        let m = first_order();
        let u: Vec<f64> = (0..40)
            .map(|t| if t % 10 < 5 { 1.0 } else { -0.5 })
            .collect();
        let input = InputRecord {
            source: "u.csv".into(),
            lines: (2..u.len() + 2).collect(),
            u,
            t: None,
        };
        let (plain, _) = simulate_model(&m, None, &input, &ModelOptions::default()).unwrap();
        let opts = ModelOptions {
            integrating: true,
            ..ModelOptions::default()
        };
        let (summed, _) = simulate_model(&m, None, &input, &opts).unwrap();
        let mut acc = 0.0;
        for (s, d) in summed.y.iter().zip(&plain.y) {
            acc += d;
            assert!((s - acc).abs() < 1e-12, "{s} against {acc}");
        }
        // Twenty samples of +1 against twenty of -0.5 through a unit gain: the position
        // climbs, it does not settle.
        assert!(summed.y[39] > 5.0, "{}", summed.y[39]);
        let coloured = ModelOptions {
            integrating: true,
            noise: Some(ModelNoise {
                colour: Colour::Model,
                level: None,
                seed: 1,
            }),
            ..ModelOptions::default()
        };
        let nm = NoiseModel {
            c: vec![1.0],
            d: vec![1.0],
            sigma2: 1.0,
        };
        assert!(matches!(
            simulate_model(&m, Some(&nm), &input, &coloured),
            Err(SimulateError::IncrementsNoiseModel)
        ));
    }

    #[test]
    fn extension_continues_the_end_segments() {
        let k = vec![-1.0, 0.0, 1.0];
        let m = HostModel {
            order: 0,
            a: nalgebra::DMatrix::zeros(0, 0),
            b: vec![],
            c: vec![],
            d: 1.0,
            mu0: 0.0,
            knots_asc: k.clone(),
            knots_desc: k,
            border_asc: vec![-1.0, 0.0, 2.0],
            border_desc: vec![0.0, 1.0, 1.5],
            singular_values: vec![],
            whitened_singular_values: vec![],
            f: 1,
            p: 1,
            samples: 0,
        };
        let e = m.extended(-2.0, 3.0);
        assert_eq!(e.border_asc_at(3.0), 6.0);
        assert_eq!(e.border_asc_at(-2.0), -2.0);
        assert_eq!(e.border_desc_at(3.0), 2.5);
        assert_eq!(e.border_desc_at(-2.0), -1.0);
        // Inside the interval nothing changes.
        assert_eq!(e.border_asc_at(0.5), m.border_asc_at(0.5));
    }
}
