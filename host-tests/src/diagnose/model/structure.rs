//! The structure of an extended model: which effects it has and their settings.

use serde::{Serialize, Serializer};

use crate::diagnose::end_stop::EndStop;
use crate::diagnose::stores::StoresClass;
use crate::model::MemoryElement;

/// Which extensions a model has, with their settings.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Structure {
    /// Extra input delay in samples (`input_delay`).
    pub delay: usize,
    /// Model order (`None`: the base option, automatic or fixed); `unmodeled_dynamics`.
    pub order: Option<usize>,
    /// Horizons `f = p` (`None`: the base options); raised with the order.
    pub horizon: Option<usize>,
    /// Degree of the polynomial output trend in time (`offset_drift`).
    pub trend_degree: Option<usize>,
    /// Time constant of an exponential settling term `c · exp(−(t − t₀)/T)` added to the
    /// trend (`offset_drift`), in half-lengths of the estimation record (`t₀` its first
    /// sample): a sensor or plant warming up after it is switched on.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub settling: Option<f64>,
    /// Frequencies of additive sinusoids, radians per sample (`periodic_disturbance`).
    pub frequencies: Vec<f64>,
    /// Segments of the monotone output map (`output_nonlinearity`).
    pub output_map_segments: Option<usize>,
    /// End stops fitted to the data ([`crate::diagnose::end_stop`]), clamping the output map
    /// in place of the levels the data check finds (`output_nonlinearity` on an output held
    /// at a level with noise on it, which the check cannot see).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub end_stop: Option<EndStop>,
    /// Order of the AR noise model (`colored_noise`).
    pub noise_ar_order: Option<usize>,
    /// Outliers flagged by the MAD rule and left out of the error (`outliers`).
    pub robust: bool,
    /// With [`robust`](Self::robust): the model re-estimated with the flagged samples replaced
    /// by its own output. Without it the deterministic model is the one fitted without the
    /// rule; the re-estimation is chosen only when it improves the estimation hold-out
    /// significantly (it can fit the imputed samples' own errors).
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub robust_refit: bool,
    /// The dynamics between the input nonlinearity and the output map
    /// (`state_dependent_dynamics`).
    pub dynamics: Dynamics,
    /// The input element simulated itself — the play operator (backlash) or the relay with
    /// borders (switch) on the knots — with `G` refitted by simulation error in place of the
    /// static or two-path nonlinearity (`hysteresis`).
    /// Written as the element's name, `"backlash"` or `"switch"` (the model file writes the
    /// element itself, `"play"` or `"relay"`).
    #[serde(serialize_with = "element_name")]
    pub element: Option<MemoryElement>,
    /// Coulomb friction and an offset on the output's velocity, fed back into `G`'s input
    /// ([`crate::friction`]), fitted with `G` by simulation error (`friction`).
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub friction: bool,
    /// With [`friction`](Self::friction): the output is a speed, the friction acts on its
    /// sign (not on the sign of its change, as on a position's) ([`crate::friction::Friction::speed`]).
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub friction_on_speed: bool,
    /// Play between two dynamic parts: the two-mass drive whose shaft has a dead zone of the
    /// gear play ([`crate::sandwich`]), driven by the Hammerstein part's static output and
    /// fitted by simulation error from `G`'s poles, in place of `G` and any element
    /// (`play_between`).
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub play_between: bool,
}

/// [`Structure::element`] as the name of the element it simulates.
fn element_name<S: Serializer>(e: &Option<MemoryElement>, s: S) -> Result<S::Ok, S::Error> {
    e.map(MemoryElement::name).serialize(s)
}

/// The dynamics between the input nonlinearity and the output map.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Dynamics {
    /// The identified linear `G` (the paper's model).
    Linear,
    /// Level-dependent stores ([`stores`](crate::diagnose::stores)) started from `G`, the borders refitted with
    /// them.
    Stores,
    /// The same stores with linear outflows and no overflow: the linear cascade refitted as
    /// the stores are (the reference that `Stores` must beat, not an effect of its own).
    LinearStores,
}

impl Dynamics {
    /// The stores class fitted, if any.
    pub fn stores(self) -> Option<StoresClass> {
        match self {
            Dynamics::Linear => None,
            Dynamics::Stores => Some(StoresClass::LevelDependent),
            Dynamics::LinearStores => Some(StoresClass::Linear),
        }
    }
}

impl Structure {
    /// The paper's model: no extension.
    pub fn base() -> Self {
        Self {
            delay: 0,
            order: None,
            horizon: None,
            trend_degree: None,
            settling: None,
            frequencies: Vec::new(),
            output_map_segments: None,
            end_stop: None,
            noise_ar_order: None,
            robust: false,
            robust_refit: false,
            dynamics: Dynamics::Linear,
            element: None,
            friction: false,
            friction_on_speed: false,
            play_between: false,
        }
    }

    /// Backfitting rounds: 3 with an output map or a robust re-estimation (the identification
    /// target is imputed), 2 with additive terms only, 1 otherwise.
    pub(super) fn rounds(&self) -> usize {
        if self.output_map_segments.is_some() || self.robust_refit {
            3
        } else if self.trend_degree.is_some() || !self.frequencies.is_empty() {
            2
        } else {
            1
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_element_is_written_by_the_name_of_the_element_it_simulates() {
        let json = |e: Option<MemoryElement>| {
            let mut out = Vec::new();
            let written = element_name(&e, &mut serde_json::Serializer::new(&mut out));
            written
                .map(|()| String::from_utf8_lossy(&out).into_owned())
                .ok()
        };
        assert_eq!(
            json(Some(MemoryElement::Play)).as_deref(),
            Some("\"backlash\"")
        );
        assert_eq!(
            json(Some(MemoryElement::Relay)).as_deref(),
            Some("\"switch\"")
        );
        assert_eq!(json(None).as_deref(), Some("null"));
    }
}
