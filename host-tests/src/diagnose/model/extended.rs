//! The fitted extended model and its simulation.

use crate::diagnose::output_map::OutputMap;
use crate::diagnose::simulate::delay_input;
use crate::diagnose::stores::Stores;
use crate::friction::{FrictionModel, Initial};
use crate::hysteresis::HysteresisModel;
use crate::identify::HostModel;
use crate::sandwich::TwoMassFit;
use crate::validation::noise::ArNoise;

use super::additive::Additive;
use super::outliers::detect_outliers;
use super::structure::Structure;

/// The fitted extended model.
#[derive(Clone, Debug, PartialEq)]
pub struct ExtendedModel {
    /// Its structure.
    pub structure: Structure,
    /// The Hammerstein part (identified on the delayed input).
    pub hammerstein: HostModel,
    /// Initial state of simulations.
    pub x0: Vec<f64>,
    /// Output map `g` (Hammerstein–Wiener), if any.
    pub output_map: Option<OutputMap>,
    /// Additive output terms.
    pub additive: Additive,
    /// Noise model, if any.
    pub noise: Option<ArNoise>,
    /// MAD rule threshold (robust standard deviations) for the outliers.
    pub outlier_k: f64,
    /// Samples of the estimation data flagged as outliers.
    pub flagged: usize,
    /// Level-dependent stores replacing `G`'s simulation ([`Dynamics::Stores`](super::structure::Dynamics::Stores)).
    pub stores: Option<Stores>,
    /// The element with memory and `G` replacing the Hammerstein part's simulation
    /// ([`Structure::element`]); fitted on the delayed input.
    pub hysteresis: Option<HysteresisModel>,
    /// The element and `G` with friction on the velocity replacing the Hammerstein part's
    /// simulation ([`Structure::friction`]); fitted on the delayed input, simulated from rest
    /// at `u_min`.
    pub friction: Option<FrictionModel>,
    /// The two-mass drive with play between motor and load replacing `G`'s simulation (and
    /// the element's) ([`Structure::play_between`]); driven by the Hammerstein part's static
    /// output on the delayed input, from rest.
    pub two_mass: Option<TwoMassFit>,
}

impl ExtendedModel {
    /// The output of `rec` less this model's additive terms (trend, settling, sinusoids): what
    /// its Hammerstein part, element or friction is fitted to and tested on.
    pub(crate) fn less_additive(&self, rec: &crate::model::Record) -> Vec<f64> {
        rec.y
            .iter()
            .zip(&rec.time)
            .map(|(y, &t)| y - self.additive.eval(t))
            .collect()
    }

    /// Refits the additive terms (when the model has any) to the residual of `rec` the model's
    /// simulation leaves through its output map, without the `skip` samples: after the
    /// simulation was replaced (an element with memory, friction), the terms fitted to the
    /// old one's residual no longer belong to it.
    pub(crate) fn refit_additive(&mut self, rec: &crate::model::Record, skip: &[bool]) {
        if self.additive.columns() == 0 {
            return;
        }
        let out = self.hammerstein_output(&rec.u);
        let r: Vec<f64> = rec
            .y
            .iter()
            .zip(&out)
            .map(|(y, o)| y - self.output_map.as_ref().map_or(*o, |g| g.eval(*o)))
            .collect();
        self.additive.fit(&r, &rec.time, skip);
    }

    /// Output of the Hammerstein part (delay included) for an input record.
    pub(crate) fn hammerstein_output(&self, u: &[f64]) -> Vec<f64> {
        let ud = delay_input(u, self.structure.delay);
        if let Some(tm) = &self.two_mass {
            return tm.simulate(&self.hammerstein.nonlinearity_output(&ud));
        }
        if let Some(el) = &self.hysteresis {
            return crate::hysteresis::simulate::simulate(el, &ud);
        }
        if let Some(fm) = &self.friction {
            let u_start = fm.plant.u_min();
            return fm.simulate_from(&ud, Initial::Rest { u_start });
        }
        let h = self.hammerstein.nonlinearity_output(&ud);
        match (&self.stores, self.held_levels()) {
            (Some(st), _) => st.simulate(&h).unwrap_or_else(|| vec![f64::NAN; h.len()]),
            (None, Some((upper, lower))) => self
                .hammerstein
                .linear_response_held(&h, &self.x0, upper, lower),
            (None, None) => self.hammerstein.linear_response(&h, &self.x0),
        }
    }

    /// A mechanical end stop's levels in `G`'s output (before the output map): the map's
    /// preimages of its ceiling and floor.
    fn held_levels(&self) -> Option<(Option<f64>, Option<f64>)> {
        let stop = self.structure.end_stop.filter(|s| s.held)?;
        let g = self.output_map.as_ref()?;
        let pre = |y: Option<f64>| y.and_then(|y| g.preimage(y, 0.0));
        Some((pre(stop.levels.ceiling), pre(stop.levels.floor)))
    }

    /// The largest spectral radius a model fitted on `n` samples can have and still be
    /// validated: a pole at `1 − 1/(2n)` or beyond has a time constant over twice the record
    /// and acts as a drift the data cannot tell from one (see
    /// [`too_slow`](crate::diagnose::effects::too_slow)).
    pub(crate) fn validatable_radius(n: usize) -> f64 {
        1.0 - 0.5 / n.max(4) as f64
    }

    /// The spectral radius of the simulated linear part (`G` of the element model when there
    /// is one).
    pub fn spectral_radius(&self) -> f64 {
        if let Some(tm) = &self.two_mass {
            return tm.model.rigid_body_pole();
        }
        match &self.hysteresis {
            Some(el) => el
                .poles()
                .iter()
                .map(|(re, im)| re.hypot(*im))
                .fold(0.0, f64::max),
            None => match &self.friction {
                Some(fm) => fm.plant.spectral_radius(),
                None => self.hammerstein.spectral_radius(),
            },
        }
    }

    /// The simulated output (deterministic part, no measured output used).
    pub fn simulate(&self, u: &[f64], time: &[f64]) -> Vec<f64> {
        let lin = self.hammerstein_output(u);
        lin.iter()
            .zip(time)
            .map(|(&l, &t)| {
                let g = self.output_map.as_ref().map_or(l, |m| m.eval(l));
                g + self.additive.eval(t)
            })
            .collect()
    }

    /// One-step-ahead prediction: the simulation plus the noise model's prediction of the
    /// residual from the past residuals (the simulation when there is no noise model).
    /// Residuals of samples flagged as outliers are replaced by their own prediction.
    pub fn predict(&self, u: &[f64], y: &[f64], time: &[f64]) -> Vec<f64> {
        let sim = self.simulate(u, time);
        let Some(ar) = &self.noise else { return sim };
        let flags = if self.structure.robust {
            let r: Vec<f64> = y.iter().zip(&sim).map(|(a, b)| a - b).collect();
            detect_outliers(&r, self.outlier_k)
        } else {
            vec![false; y.len()]
        };
        let mut r = vec![0.0; y.len()];
        let mut out = Vec::with_capacity(y.len());
        for t in 0..y.len() {
            let pr: f64 =
                ar.a.iter()
                    .enumerate()
                    .filter(|(k, _)| t > *k)
                    .map(|(k, a)| a * r[t - 1 - k])
                    .sum();
            out.push(sim[t] + pr);
            r[t] = if flags[t] { pr } else { y[t] - sim[t] };
        }
        out
    }
}
