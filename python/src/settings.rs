//! The keyword settings of `hsid.identify` turned into the library's options and choices, as
//! `hsid identify` turns its flags into them.

use hsid_host::identify::IdentifyOptions;
use hsid_host::model::Element;
use hsid_host::model_file::Units;
use hsid_host::refine::knots::SegmentCount;
use hsid_host::workflow::{IdentifyRequest, Syntax};
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

/// `ts=`: None, or a sample time in seconds, finite and positive.
pub fn sample_time(ts: Option<f64>) -> Result<Option<f64>, Failure> {
    match ts {
        Some(t) if !(t.is_finite() && t > 0.0) => Err(settings_err(
            "sample_time",
            format!("ts={t}: give the sample time in seconds, finite and positive"),
        )),
        ts => Ok(ts),
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
pub fn nonlinearity(name: &str) -> Result<Element, Failure> {
    match name {
        "backlash" => Ok(Element::Backlash),
        "switch" => Ok(Element::Switch),
        "static" => Ok(Element::Static),
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

/// The request of these keywords in Python's words (`hsid identify`'s flag for flag), the
/// rest at its defaults.
#[allow(clippy::too_many_arguments)]
pub fn request(
    umin: f64,
    umax: f64,
    segments: Option<SegmentArg>,
    knots: Option<KnotPair>,
    kind: Element,
    horizons: Option<(usize, usize)>,
    order: Option<usize>,
    refine: bool,
) -> IdentifyRequest {
    let mut r = IdentifyRequest::new(umin, umax, Syntax::Python);
    r.segments = segments.map(|s| match s {
        SegmentArg::Fixed(n) => SegmentCount::Fixed(n),
        SegmentArg::Auto => SegmentCount::Auto,
    });
    if let Some((asc, desc)) = knots {
        (r.knots_asc, r.knots_desc) = (Some(asc), Some(desc));
    }
    r.element = kind;
    r.horizons = horizons;
    r.order = order;
    r.refine = refine;
    r
}

/// The identification options of `hsid identify` for these keywords (the library's request
/// check, as the command line's).
#[allow(clippy::too_many_arguments)]
pub fn settings(
    umin: f64,
    umax: f64,
    segments: Option<SegmentArg>,
    knots: Option<KnotPair>,
    kind: Element,
    horizons: Option<(usize, usize)>,
    order: Option<usize>,
    hold: usize,
    refine: bool,
) -> Result<IdentifyOptions, Failure> {
    let r = request(umin, umax, segments, knots, kind, horizons, order, refine);
    Ok(r.validate(hold)?.options)
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
    fn keywords_reach_the_request_and_errors_keep_their_kind() {
        let r = request(
            -3.0,
            3.0,
            Some(SegmentArg::Fixed(7)),
            None,
            Element::Static,
            Some((10, 10)),
            Some(3),
            false,
        );
        assert_eq!(r.segments, Some(SegmentCount::Fixed(7)));
        assert!(!r.refine);
        let o = settings(
            -3.0,
            3.0,
            None,
            None,
            Element::Static,
            None,
            Some(3),
            0,
            true,
        )
        .unwrap();
        assert!(o.static_nonlinearity);
        assert_eq!(o.order, Some(3));
        let k = vec![-1.0, 0.0, 0.9];
        let kind = |umin, umax, knots| {
            settings(
                umin,
                umax,
                None,
                knots,
                Element::Backlash,
                None,
                None,
                300,
                true,
            )
            .err()
            .map(|e| (e.class, e.kind))
        };
        assert_eq!(
            kind(-1.0, 1.0, Some((k.clone(), k))),
            Some((Class::Settings, "knot_endpoints"))
        );
        assert_eq!(
            kind(1.0, -1.0, None),
            Some((Class::Settings, "invalid_interval"))
        );
    }
}
