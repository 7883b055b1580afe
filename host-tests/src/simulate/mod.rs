//! Simulation for trying the method and for teaching: a true plant from a specification
//! ([`simulate_plant`]) or an identified model ([`simulate_model`]) driven by any input.
//!
//! A plant specification ([`PlantSpec`], JSON, described field by field in
//! `docs/simulate.md`) holds the input element (backlash, switch or static; borders as knots or
//! a named shape), the linear part (a discrete transfer function, or continuous-time sections
//! discretised by a zero-order hold at the sample time), output noise at an SNR or a level,
//! and the sample time and units carried into the output's header. The plant starts at rest
//! with the element's first output, as after a long hold at the first input.

mod element;
mod error;
mod input;
mod model;
mod noise;
mod output;
mod plant;
mod spec;
mod spec_file;
mod true_loop;

pub use element::{Static, element};
pub use error::SimulateError;
pub use input::{InputRecord, read_input};
pub use model::{Colour, ModelNoise, ModelOptions, simulate_model};
pub use noise::{Level, Noise, output_noise};
pub use output::Output;
pub use plant::{StateSpace, linear_part, sample_time};
pub use spec::{
    ColourName, ColourSpec, Curve, ElementSpec, LinearSpec, NoiseSpec, PlantSpec, SectionSpec,
    Shape, TransferSpec, UnitsSpec,
};
pub use spec_file::{MAX_SPEC_BYTES, SpecFileError};
pub use true_loop::{TrueLoop, true_loop};

use crate::sim::Lti;

/// An excitation asked for no more samples than its hold: every sample would be the hold's
/// u_min, a record nothing can be identified from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error(
    "{samples} samples are no more than the hold of {hold}: the excitation would be the hold \
     alone, every sample at u_min; give more samples than the hold (the paper's record is the \
     hold and 4000 more) or a shorter hold"
)]
pub struct ExcitationTooShort {
    /// The samples asked for, hold included.
    pub samples: usize,
    /// The hold at u_min.
    pub hold: usize,
}

/// Checks that an excitation of `samples` samples in all holds more than its `hold`, as
/// `hsid excite` and Python's `hsid.excite` both require before generating it.
pub fn check_excitation_length(samples: usize, hold: usize) -> Result<(), ExcitationTooShort> {
    if samples > hold {
        Ok(())
    } else {
        Err(ExcitationTooShort { samples, hold })
    }
}

/// `G` driven by `h` from rest at `h[0]`: `G(1) h[0] + G (h − h[0])` from zero state (exact by
/// superposition).
fn from_rest(g: &Lti, h: &[f64]) -> Vec<f64> {
    let h0 = h.first().copied().unwrap_or(0.0);
    let dh: Vec<f64> = h.iter().map(|v| v - h0).collect();
    let y0 = g.static_gain() * h0;
    g.filter(&dh).into_iter().map(|y| y + y0).collect()
}

/// Simulates the plant of `spec` on the input `u`; `seed` replaces the specification's noise
/// seed when given.
pub fn simulate_plant(
    spec: &PlantSpec,
    u: &[f64],
    seed: Option<u64>,
) -> Result<Output, SimulateError> {
    let ts = sample_time(spec.ts)?;
    let g = linear_part(&spec.plant, ts)?;
    let mut el = element(&spec.element)?;
    let noise = spec.noise.as_ref().map(noise::from_spec).transpose()?;
    el.reset();
    let h: Vec<f64> = u.iter().map(|&v| el.step(v)).collect();
    let y_clean = from_rest(&g, &h);
    match noise {
        None => Ok(Output::clean(y_clean)),
        Some(mut n) => {
            n.seed = seed.unwrap_or(n.seed);
            Output::noisy(y_clean, &n)
        }
    }
}

/// The header comment lines of a simulated record (without the `# `): the sample time and the
/// units when known, e.g. `ts = 0.01 s`.
pub fn header(ts: Option<f64>, input_unit: Option<&str>, output_unit: Option<&str>) -> Vec<String> {
    let mut lines = Vec::new();
    if let Some(ts) = ts {
        lines.push(format!("ts = {ts} s"));
    }
    if let Some(u) = input_unit {
        lines.push(format!("input unit = {u}"));
    }
    if let Some(y) = output_unit {
        lines.push(format!("output unit = {y}"));
    }
    lines
}
