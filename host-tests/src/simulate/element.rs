//! The input element of a plant specification: named shapes and knot lists turned into the
//! simulator's borders, and the element built on them (the simulator's play operator and
//! relay, or a memoryless border).

use super::error::SimulateError;
use super::spec::{Curve, ElementSpec, Shape};
use crate::model::Element;
use crate::sim::{Backlash, Border, Nonlinearity, Switch, border, paper_backlash, paper_switch};

/// A memoryless element `H(u)`.
#[derive(Clone)]
pub struct Static {
    h: Border,
}

impl Static {
    /// The element with border `h`.
    pub fn new(h: Border) -> Self {
        Self { h }
    }
}

impl Nonlinearity for Static {
    fn reset(&mut self) {}

    fn step(&mut self, u: f64) -> f64 {
        (self.h)(u)
    }
}

/// Piecewise-linear interpolation through `(u, y)`, the end segments extended linearly.
fn piecewise(u: Vec<f64>, y: Vec<f64>) -> Border {
    border(move |x| {
        let last = u.len() - 1;
        let i = u.partition_point(|&k| k <= x).clamp(1, last);
        let (u0, u1, y0, y1) = (u[i - 1], u[i], y[i - 1], y[i]);
        y0 + (y1 - y0) * (x - u0) / (u1 - u0)
    })
}

/// A checked knot list as a border; `field` is its dotted path.
fn curve(c: &Curve, field: &str) -> Result<Border, SimulateError> {
    let bad = |reason: String| SimulateError::Knots {
        field: field.to_string(),
        reason,
    };
    if c.u.len() != c.y.len() {
        return Err(bad(format!(
            "{} knots (u) but {} values (y); give one value per knot",
            c.u.len(),
            c.y.len()
        )));
    }
    if c.u.len() < 2 {
        return Err(bad("at least two knots are needed".into()));
    }
    if let Some(v) = c.u.iter().chain(&c.y).find(|v| !v.is_finite()) {
        return Err(bad(format!("{v} is not a finite number")));
    }
    if let Some(i) = (1..c.u.len()).find(|&i| c.u[i] <= c.u[i - 1]) {
        return Err(bad(format!(
            "knots must increase strictly, but u[{i}] = {} follows u[{}] = {}",
            c.u[i],
            i - 1,
            c.u[i - 1]
        )));
    }
    Ok(piecewise(c.u.clone(), c.y.clone()))
}

fn param(v: Option<f64>, field: &str, default: Option<f64>) -> Result<f64, SimulateError> {
    let v = match (v, default) {
        (Some(v), _) => v,
        (None, Some(d)) => d,
        (None, None) => {
            return Err(SimulateError::Missing {
                field: field.to_string(),
                why: "the shape is defined by it",
            });
        }
    };
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(SimulateError::OutOfRange {
            field: field.to_string(),
            value: v,
            must: "finite and > 0",
        })
    }
}

/// Refuses fields given but not used by the chosen description.
fn unused(e: &ElementSpec, used: &[&str], by: &str) -> Result<(), SimulateError> {
    let given = [
        ("width", e.width.is_some()),
        ("gap", e.gap.is_some()),
        ("slope", e.slope.is_some()),
        ("ascending", e.ascending.is_some()),
        ("descending", e.descending.is_some()),
        ("border", e.border.is_some()),
    ];
    match given.iter().find(|(n, g)| *g && !used.contains(n)) {
        Some((name, _)) => Err(SimulateError::Conflict {
            field: format!("element.{name}"),
            why: format!("it is not used by {by}"),
        }),
        None => Ok(()),
    }
}

/// The borders `(H_a, H_d)` of a named shape; one border is both for `deadband`.
fn shape(e: &ElementSpec, s: Shape) -> Result<(Border, Border), SimulateError> {
    match s {
        Shape::Deadband => {
            unused(e, &["width", "slope"], "the shape deadband")?;
            let half = param(e.width, "element.width", None)? / 2.0;
            let k = param(e.slope, "element.slope", Some(1.0))?;
            let h = border(move |u: f64| k * (u.abs() - half).max(0.0) * u.signum());
            Ok((h.clone(), h))
        }
        Shape::Backlash => {
            unused(e, &["gap", "slope"], "the shape backlash")?;
            let half = param(e.gap, "element.gap", None)? / 2.0;
            let k = param(e.slope, "element.slope", Some(1.0))?;
            Ok((
                border(move |u| k * (u - half)),
                border(move |u| k * (u + half)),
            ))
        }
        Shape::PaperBacklash => {
            unused(e, &[], "the shape paper-backlash")?;
            let p = paper_backlash();
            let (a, d) = (p.clone(), p);
            Ok((border(move |u| a.h_a(u)), border(move |u| d.h_d(u))))
        }
        Shape::PaperSwitch => {
            unused(e, &[], "the shape paper-switch")?;
            let p = paper_switch();
            let (a, d) = (p.clone(), p);
            Ok((border(move |u| a.h_a(u)), border(move |u| d.h_d(u))))
        }
    }
}

/// The two borders of a backlash or switch: a shape, or ascending and descending knots.
fn two_borders(e: &ElementSpec) -> Result<(Border, Border), SimulateError> {
    if let Some(s) = e.shape {
        return shape(e, s);
    }
    unused(
        e,
        &["ascending", "descending"],
        "a backlash or switch given by knots",
    )?;
    let missing = |field: &str| SimulateError::Missing {
        field: field.to_string(),
        why: "a backlash or switch needs a shape, or ascending and descending knots",
    };
    let a = e
        .ascending
        .as_ref()
        .ok_or_else(|| missing("element.ascending"))?;
    let d = e
        .descending
        .as_ref()
        .ok_or_else(|| missing("element.descending"))?;
    Ok((
        curve(a, "element.ascending")?,
        curve(d, "element.descending")?,
    ))
}

/// The one border of a static element: `deadband`, or knots.
fn one_border(e: &ElementSpec) -> Result<Border, SimulateError> {
    match e.shape {
        Some(Shape::Deadband) => Ok(shape(e, Shape::Deadband)?.0),
        Some(s) => Err(SimulateError::Conflict {
            field: "element.shape".into(),
            why: format!(
                "the shape {} has two borders; a static element has one (use deadband or border)",
                s.name()
            ),
        }),
        None => {
            unused(e, &["border"], "a static element given by knots")?;
            let b = e.border.as_ref().ok_or(SimulateError::Missing {
                field: "element.border".into(),
                why: "a static element needs the shape deadband or a border {\"u\": [...], \"y\": [...]}",
            })?;
            curve(b, "element.border")
        }
    }
}

/// Checks `H_a <= H_d` of a backlash at the knots of both borders (the play operator needs it).
fn check_order(e: &ElementSpec, a: &Border, d: &Border) -> Result<(), SimulateError> {
    let knots = e
        .ascending
        .iter()
        .chain(&e.descending)
        .flat_map(|c| c.u.iter());
    match knots.copied().find(|&u| a(u) > d(u)) {
        Some(u) => Err(SimulateError::Knots {
            field: "element.ascending".into(),
            reason: format!(
                "a backlash needs H_a <= H_d, but at u = {u} H_a = {} > H_d = {}",
                a(u),
                d(u)
            ),
        }),
        None => Ok(()),
    }
}

/// The element of a specification, ready to step.
pub fn element(e: &ElementSpec) -> Result<Box<dyn Nonlinearity>, SimulateError> {
    Ok(match e.kind {
        Element::Backlash => {
            let (a, d) = two_borders(e)?;
            check_order(e, &a, &d)?;
            Box::new(Backlash::new(a, d))
        }
        Element::Switch => {
            let (a, d) = two_borders(e)?;
            Box::new(Switch::new(a, d))
        }
        Element::Static => Box::new(Static::new(one_border(e)?)),
    })
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    #[test]
    fn knots_interpolate_and_extend_linearly() {
        let b = curve(
            &Curve {
                u: vec![-1.0, 0.0, 2.0],
                y: vec![-2.0, 0.0, 1.0],
            },
            "b",
        )
        .unwrap();
        assert_eq!(b(-0.5), -1.0);
        assert_eq!(b(1.0), 0.5);
        assert_eq!(b(4.0), 2.0);
        assert_eq!(b(-2.0), -4.0);
    }

    #[test]
    fn non_increasing_knots_are_refused_with_their_index() {
        let c = Curve {
            u: vec![0.0, 1.0, 1.0],
            y: vec![0.0; 3],
        };
        let e = curve(&c, "element.border").err().unwrap().to_string();
        assert!(e.contains("element.border") && e.contains("u[2]"), "{e}");
    }

    #[test]
    fn the_backlash_shape_plays_with_its_gap() {
        let spec: ElementSpec = serde_json::from_str(
            r#"{"kind": "backlash", "shape": "backlash", "gap": 0.4, "slope": 2}"#,
        )
        .unwrap();
        let mut el = element(&spec).unwrap();
        // Up to 1: H_a(1) = 2 (1 − 0.2) = 1.6; back to 0.8: inside the gap, the output stays.
        assert!((el.step(1.0) - 1.6).abs() < 1e-15);
        assert!((el.step(0.8) - 1.6).abs() < 1e-15);
        // Down to 0: H_d(0) = 0.4 < 1.6, the output follows the descending border.
        assert!((el.step(0.0) - 0.4).abs() < 1e-15);
    }

    #[test]
    fn the_deadband_is_zero_inside_and_sloped_outside() {
        let spec: ElementSpec =
            serde_json::from_str(r#"{"kind": "static", "shape": "deadband", "width": 1}"#).unwrap();
        let mut el = element(&spec).unwrap();
        assert_eq!(el.step(0.3), 0.0);
        assert_eq!(el.step(-0.4), 0.0);
        assert!((el.step(1.5) - 1.0).abs() < 1e-15);
        assert!((el.step(-2.0) + 1.5).abs() < 1e-15);
    }
}
