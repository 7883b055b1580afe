//! Output nonlinearity: a monotone piecewise-linear output map with 3, 5 or 8 segments; on an
//! output the data checks find pinned at an extreme, first the output saturation alone (a
//! linear map with flat ends at the pinned levels). On a model with an element with memory,
//! only the output saturation: the element's simulation clamped at the pinned levels, `G` and
//! the borders refitted through the clamp (see [`element`](crate::diagnose::model::element)).
//! Where the check finds no pinned sample, an end stop with noise on it: the clamp at levels
//! fitted to the current model's simulation ([`end_stop`](crate::diagnose::end_stop)), tried
//! first, before the maps.

use super::candidate::Candidate;
use super::catalog::{Effect, has_evidence};
use super::proposal::Proposal;
use crate::diagnose::end_stop::{EndStop, fit_levels};
use crate::diagnose::error::DiagnoseError;
use crate::diagnose::model::Metric;
use crate::validation::checks::Saturation;

impl Proposal<'_> {
    /// Output maps of 3, 5 and 8 segments, after the one-segment saturation when the output
    /// sits at a saturation level (the map is clipped there in every setting). On a model with
    /// an element with memory, the saturation alone, and only when the output sits at a level.
    /// Where no sample sits at a level, the end stops fitted to the current model's simulation
    /// come first, if there are any (on a model with an element, alone).
    pub fn output_nonlinearity(&self) -> Result<Option<Candidate>, DiagnoseError> {
        let effect = Effect::OutputNonlinearity;
        let saturated = self.holdout.opts.saturation.any();
        let stops = (!saturated).then(|| self.end_stops()).flatten();
        // The maps answer the residual tests of an output nonlinearity or a pinned output;
        // an end stop's evidence alone asks for the end stop.
        let maps = saturated || self.every || has_evidence(effect, self.tests);
        let segments: &[usize] = match (self.current.element.is_some(), saturated) {
            (true, false) => &[],
            (false, false) if !maps => &[],
            (true, true) => &[1],
            (false, true) => &[1, 3, 5, 8],
            (false, false) => &[3, 5, 8],
        };
        let mut opts = Vec::new();
        if let Some(sat) = stops {
            let at = |l: Option<f64>| l.map_or("-".to_string(), |l| format!("{l:.4}"));
            // The state is held on `G`'s own simulation only (an element, friction or a
            // two-mass drive simulates itself).
            let c = self.current;
            let kinds: &[(bool, &str)] = if c.element.is_none() && !c.friction && !c.play_between {
                &[
                    (false, "a sensor: the output clamped"),
                    (true, "mechanical: the state held at rest there"),
                ]
            } else {
                &[(false, "a sensor: the output clamped")]
            };
            for &(held, kind) in kinds {
                opts.push((
                    format!(
                        "end stop ({kind}; levels fitted to the model's simulation: upper {}, lower {})",
                        at(sat.ceiling),
                        at(sat.floor)
                    ),
                    self.with(|s| {
                        s.output_map_segments = Some(1);
                        s.end_stop = Some(EndStop { levels: sat, held });
                    }),
                ));
            }
        }
        if opts.is_empty() && segments.is_empty() {
            return Ok(None);
        }
        opts.extend(segments.iter().map(|&k| {
            let label = if k == 1 {
                "output saturation (linear, flat ends at the pinned levels)".to_string()
            } else {
                format!("{k} segments")
            };
            (label, self.with(|s| s.output_map_segments = Some(k)))
        }));
        self.best_of(effect, opts, Metric::Simulation)
    }

    /// The end stops the current model's simulation (fitted without the inner hold-out) shows
    /// on the samples it was fitted on ([`fit_levels`]).
    fn end_stops(&self) -> Option<Saturation> {
        let est = self.holdout.est;
        let sim = self.inner_model.simulate(&est.u, &est.time);
        let range = &self.holdout.range;
        let idx: Vec<usize> = (0..est.len()).filter(|t| !range.contains(t)).collect();
        fit_levels(&est.y, &sim, &idx).map(|e| e.levels)
    }
}
