//! The keyword settings of `hsid.identify` turned into the library's options and choices, as
//! `hsid identify` turns its flags into them.

use hsid_host::choose::{self, Choices, Estimator, SEGMENT_CANDIDATES, Segments};
use hsid_host::identify::IdentifyOptions;
use hsid_host::model_file::{NonlinearityKind, Units};
use hsid_host::refine::knots::AUTO_CANDIDATES;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyString, PyTuple};

use crate::arrays::vector;
use crate::error::{Class, Failure};

/// Segments per path: a count or `"auto"`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SegmentArg {
    /// This many.
    Fixed(usize),
    /// From 2 to 14 by BIC of the refined model.
    Auto,
}

/// The settings of one identification.
#[derive(Debug)]
pub struct Settings {
    /// Interval, knots, horizons, order, hold.
    pub options: IdentifyOptions,
    /// What is chosen from the data.
    pub choices: Choices,
    /// The input element.
    pub kind: NonlinearityKind,
}

fn settings_err(kind: &'static str, message: String) -> Failure {
    Failure::new(Class::Settings, kind, message)
}

/// `segments=`: None, an int or "auto".
pub fn segments(obj: Option<&Bound<'_, PyAny>>) -> Result<Option<SegmentArg>, Failure> {
    let Some(obj) = obj else { return Ok(None) };
    if obj.is_none() {
        return Ok(None);
    }
    if let Ok(s) = obj.cast::<PyString>() {
        return match s.extract::<String>().as_deref() {
            Ok("auto") => Ok(Some(SegmentArg::Auto)),
            _ => Err(settings_err(
                "segments",
                format!("segments={obj}: give a count of at least 1, \"auto\" or None"),
            )),
        };
    }
    match obj.extract::<usize>() {
        Ok(0) | Err(_) => Err(settings_err(
            "segments",
            format!("segments={obj}: give a count of at least 1, \"auto\" or None"),
        )),
        Ok(n) => Ok(Some(SegmentArg::Fixed(n))),
    }
}

/// Knots of the ascending and the descending path.
pub type KnotPair = (Vec<f64>, Vec<f64>);

/// `knots=`: None, one array for both paths, or a pair `(ascending, descending)`.
pub fn knots(obj: Option<&Bound<'_, PyAny>>) -> Result<Option<KnotPair>, Failure> {
    let Some(obj) = obj.filter(|o| !o.is_none()) else {
        return Ok(None);
    };
    if let Ok(t) = obj.cast::<PyTuple>() {
        if t.len() != 2 {
            return Err(settings_err(
                "knots",
                format!(
                    "knots is a tuple of {} items: give one array for both paths or a pair (ascending, descending)",
                    t.len()
                ),
            ));
        }
        let item = |i| {
            t.get_item(i)
                .map_err(|e| settings_err("knots", e.to_string()))
        };
        return Ok(Some((
            vector("knots[0]", &item(0)?)?,
            vector("knots[1]", &item(1)?)?,
        )));
    }
    let k = vector("knots", obj)?;
    Ok(Some((k.clone(), k)))
}

/// `nonlinearity=`: "backlash", "switch" or "static".
pub fn nonlinearity(name: &str) -> Result<NonlinearityKind, Failure> {
    match name {
        "backlash" => Ok(NonlinearityKind::Backlash),
        "switch" => Ok(NonlinearityKind::Switch),
        "static" => Ok(NonlinearityKind::Static),
        _ => Err(settings_err(
            "nonlinearity",
            format!("nonlinearity={name:?}: give \"backlash\", \"switch\" or \"static\""),
        )),
    }
}

/// `units=`: None or {"input": str, "output": str}.
pub fn units(obj: Option<&Bound<'_, PyAny>>) -> Result<Option<Units>, Failure> {
    let Some(obj) = obj.filter(|o| !o.is_none()) else {
        return Ok(None);
    };
    let bad = || {
        settings_err(
            "units",
            format!("units={obj}: give a dict {{\"input\": \"V\", \"output\": \"rad\"}}"),
        )
    };
    let d = obj.cast::<PyDict>().map_err(|_| bad())?;
    if d.len() != 2 {
        return Err(bad());
    }
    let get = |k: &str| -> Result<String, Failure> {
        d.get_item(k)
            .ok()
            .flatten()
            .and_then(|v| v.extract::<String>().ok())
            .ok_or_else(bad)
    };
    Ok(Some(Units {
        input: get("input")?,
        output: get("output")?,
    }))
}

/// The settings of `hsid identify` for these keywords (`hsid identify`'s `options` and
/// choices, flag for flag).
#[allow(clippy::too_many_arguments)]
pub fn settings(
    umin: f64,
    umax: f64,
    segments: Option<SegmentArg>,
    knots: Option<KnotPair>,
    kind: NonlinearityKind,
    horizons: Option<(usize, usize)>,
    order: Option<usize>,
    hold: usize,
    refine: bool,
) -> Result<Settings, Failure> {
    if !(umin.is_finite() && umax.is_finite() && umin < umax) {
        return Err(settings_err(
            "invalid_interval",
            format!("invalid input interval [{umin}, {umax}]: umin must be finite and below umax"),
        ));
    }
    let fixed = match segments {
        Some(SegmentArg::Fixed(n)) => n,
        _ => 7,
    };
    let mut options = IdentifyOptions::uniform(umin, umax, fixed, hold);
    options.static_nonlinearity = kind == NonlinearityKind::Static;
    let knots_given = knots.is_some();
    if let Some((asc, desc)) = knots {
        for (name, k) in [("knots (ascending)", &asc), ("knots (descending)", &desc)] {
            if k.first() != Some(&umin) || k.last() != Some(&umax) {
                return Err(settings_err(
                    "knot_endpoints",
                    format!("{name} must start at umin {umin} and end at umax {umax}"),
                ));
            }
        }
        (options.knots_asc, options.knots_desc) = (asc, desc);
    }
    (options.f, options.p) = horizons.unwrap_or((10, 10));
    options.order = order;
    let choices = Choices {
        segments: match segments {
            _ if knots_given => Segments::Given,
            Some(SegmentArg::Fixed(_)) => Segments::Given,
            Some(SegmentArg::Auto) => Segments::FromData(AUTO_CANDIDATES.collect()),
            None => Segments::FromData(SEGMENT_CANDIDATES.to_vec()),
        },
        horizons: match horizons {
            Some(_) => choose::Horizons::Given,
            None => choose::Horizons::FromData,
        },
        estimator: if refine {
            Estimator::Refined
        } else {
            Estimator::Subspace
        },
        ..Choices::default()
    };
    Ok(Settings {
        options,
        choices,
        kind,
    })
}

/// `f=` and `p=`: both, one (the other equals it) or neither.
pub fn horizons(f: Option<usize>, p: Option<usize>) -> Option<(usize, usize)> {
    match (f, p) {
        (Some(f), Some(p)) => Some((f, p)),
        (Some(h), None) | (None, Some(h)) => Some((h, h)),
        (None, None) => None,
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    #[test]
    fn one_horizon_given_sets_both() {
        assert_eq!(horizons(Some(12), None), Some((12, 12)));
        assert_eq!(horizons(None, Some(8)), Some((8, 8)));
        assert_eq!(horizons(Some(12), Some(8)), Some((12, 8)));
        assert_eq!(horizons(None, None), None);
    }

    #[test]
    fn paper_keywords_give_the_paper_estimator() {
        let s = settings(
            -3.0,
            3.0,
            Some(SegmentArg::Fixed(7)),
            None,
            NonlinearityKind::Backlash,
            Some((10, 10)),
            None,
            300,
            false,
        )
        .unwrap();
        assert_eq!(s.options, IdentifyOptions::uniform(-3.0, 3.0, 7, 300));
        assert_eq!(s.choices.segments, Segments::Given);
        assert_eq!(s.choices.horizons, choose::Horizons::Given);
        assert_eq!(s.choices.estimator, Estimator::Subspace);
    }

    #[test]
    fn defaults_choose_from_the_data_and_refine() {
        let s = settings(
            -1.0,
            1.0,
            None,
            None,
            NonlinearityKind::Static,
            None,
            Some(3),
            0,
            true,
        )
        .unwrap();
        assert_eq!(
            s.choices.segments,
            Segments::FromData(SEGMENT_CANDIDATES.to_vec())
        );
        assert_eq!(s.choices.horizons, choose::Horizons::FromData);
        assert_eq!(s.choices.estimator, Estimator::Refined);
        assert!(s.options.static_nonlinearity);
        assert_eq!(s.options.order, Some(3));
    }

    #[test]
    fn given_knots_must_span_the_interval() {
        let k = vec![-1.0, 0.0, 0.9];
        let e = settings(
            -1.0,
            1.0,
            None,
            Some((k.clone(), k)),
            NonlinearityKind::Backlash,
            None,
            None,
            300,
            true,
        )
        .err()
        .map(|e| (e.class, e.kind));
        assert_eq!(e, Some((Class::Settings, "knot_endpoints")));
        let e = settings(
            1.0,
            -1.0,
            None,
            None,
            NonlinearityKind::Backlash,
            None,
            None,
            300,
            true,
        )
        .err()
        .map(|e| e.kind);
        assert_eq!(e, Some("invalid_interval"));
    }
}
