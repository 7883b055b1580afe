//! Shape and value checks of a model file, each failure naming the offending key.

use std::path::Path;

use super::{ModelFile, ModelFileError};
use crate::units::check_unit_text;

type Checked = Result<(), ModelFileError>;

/// All checks of [`ModelFile::validate`], in the order of the keys.
pub(super) fn validate(m: &ModelFile, path: &Path) -> Checked {
    let bad = |field: &'static str, reason: String| ModelFileError::Invalid {
        path: path.to_path_buf(),
        field,
        reason,
    };
    sizes(m, &bad)?;
    plant(m, &bad)?;
    finite_all(m, &bad)?;
    knots(m, &bad)?;
    if let Some(t) = m.sample_time
        && !(in_range(t) && t > 0.0)
    {
        return Err(bad(
            "sample_time",
            format!("{t} is not a positive number (at most {MAX_MAGNITUDE:e})"),
        ));
    }
    if let Some(u) = &m.units {
        if u.input.trim().is_empty() || u.output.trim().is_empty() {
            return Err(bad(
                "units",
                "an empty unit name; give both (e.g. \"V\") or null".to_string(),
            ));
        }
        for (signal, unit) in [("input", &u.input), ("output", &u.output)] {
            check_unit_text(unit)
                .map_err(|e| bad("units", format!("the {signal} unit {unit:?}: {e}")))?;
        }
    }
    noise(m, &bad)?;
    element(m, &bad)?;
    friction(m, &bad)?;
    std(m, &bad)
}

/// The largest model order a model file may state: the desktop identifies orders below its
/// largest horizon (95), and the work of reading and simulating a model grows with the cube of
/// its order (order 200 took 14 s to validate, 1000 more than ten minutes).
pub const MAX_MODEL_ORDER: usize = 128;

/// The most knots a border of a model file may have: the desktop's largest capacity holds 64
/// channels (at most 64 knots on a border); a file with more is no model hsid wrote.
pub const MAX_MODEL_KNOTS: usize = 1024;

/// The order and the knot counts within [`MAX_MODEL_ORDER`] and [`MAX_MODEL_KNOTS`], checked
/// before anything is computed from them.
fn sizes(m: &ModelFile, bad: &Bad) -> Checked {
    if m.order > MAX_MODEL_ORDER {
        return Err(bad(
            "order",
            format!(
                "{} is above the largest order a model file holds ({MAX_MODEL_ORDER})",
                m.order
            ),
        ));
    }
    for (field, k) in [
        ("knots_asc", &m.knots_asc),
        ("knots_desc", &m.knots_desc),
        ("border_asc", &m.border_asc),
        ("border_desc", &m.border_desc),
    ] {
        if k.len() > MAX_MODEL_KNOTS {
            return Err(bad(
                field,
                format!(
                    "has {} values, more than the {MAX_MODEL_KNOTS} a border of a model file \
                     holds",
                    k.len()
                ),
            ));
        }
    }
    Ok(())
}

/// Relative tolerance of a stored pole against the eigenvalue of `A` it stands for: `poles`
/// must match A's eigenvalues within `POLE_TOLERANCE · max(1, |λ|)` each. hsid writes the
/// eigenvalues it computes from `A` itself (they read back within rounding); the tolerance
/// also admits poles rounded to about four decimals in a file written by hand.
pub const POLE_TOLERANCE: f64 = 1e-3;

/// The checks of a model file as it is read, beyond [`validate`]'s (which run on writing
/// too): `A` is stable (its eigenvalues strictly inside the unit circle; for an integrating
/// model too, whose `A` is the stable part `G₀` and whose pole at `z = 1` is not stored), and
/// `poles` are A's eigenvalues ([`POLE_TOLERANCE`]). Run after [`validate`], which checked the
/// shapes and that every number is finite and bounded.
pub(super) fn on_read(m: &ModelFile, path: &Path) -> Checked {
    let bad = |field: &'static str, reason: String| ModelFileError::Invalid {
        path: path.to_path_buf(),
        field,
        reason,
    };
    let n = m.order;
    if n == 0 {
        return Ok(());
    }
    let a = nalgebra::DMatrix::from_fn(n, n, |i, j| m.a[i][j]);
    let Some(eig) = crate::numerics::poly::eigenvalues(a) else {
        return Err(bad(
            "A",
            "its eigenvalues cannot be computed (the Schur decomposition does not converge)"
                .to_string(),
        ));
    };
    let modulus = |&(re, im): &(f64, f64)| re.hypot(im);
    if let Some(&(re, im)) = eig
        .iter()
        .find(|l| modulus(l) >= 1.0 || modulus(l).is_nan())
    {
        let what = match m.integrating {
            true => "the stable part G0 of an integrating model (its pole at z = 1 is not stored)",
            false => "the plant",
        };
        return Err(bad(
            "A",
            format!(
                "has a pole at {} of modulus {:.6} >= 1: {what} must be stable, every pole \
                 strictly inside the unit circle; identify the model again",
                complex_text(re, im),
                re.hypot(im)
            ),
        ));
    }
    let mut unmatched: Vec<(f64, f64)> = eig;
    for (i, &[re, im]) in m.poles.iter().enumerate() {
        let distance = |&(r, j): &(f64, f64)| (r - re).hypot(j - im);
        let nearest = unmatched
            .iter()
            .enumerate()
            .min_by(|x, y| distance(x.1).total_cmp(&distance(y.1)));
        let Some((k, &l)) = nearest else {
            break;
        };
        if distance(&l) > POLE_TOLERANCE * modulus(&l).max(1.0) {
            return Err(bad(
                "poles",
                format!(
                    "entry {i} is {}, but the nearest eigenvalue of A left is {}: the poles must \
                     be A's eigenvalues (within {POLE_TOLERANCE:e} relative); write them as A \
                     gives them",
                    complex_text(re, im),
                    complex_text(l.0, l.1)
                ),
            ));
        }
        unmatched.swap_remove(k);
    }
    Ok(())
}

/// `0.5`, `0.5+0.1i` or `0.5-0.1i`.
fn complex_text(re: f64, im: f64) -> String {
    if im == 0.0 {
        format!("{re}")
    } else {
        format!("{re}{im:+}i")
    }
}

/// A play or relay element: the kind it belongs to, one set of knots for both borders.
fn element(m: &ModelFile, bad: &Bad) -> Checked {
    use crate::model::Element;
    let Some(e) = m.element else {
        return Ok(());
    };
    let kind = e.element();
    if m.nonlinearity != Some(kind) {
        return Err(bad(
            "element",
            format!(
                "{e:?} belongs to nonlinearity \"{}\", the file says {:?}",
                kind.name(),
                m.nonlinearity.map(Element::name)
            ),
        ));
    }
    if m.knots_asc != m.knots_desc {
        return Err(bad(
            "element",
            "the borders of a play or relay share their knots: knots_asc and knots_desc differ"
                .to_string(),
        ));
    }
    Ok(())
}

/// Friction on the velocity: finite forces, a positive velocity scale, a bounded delay, no
/// feed-through and no element with memory beside it.
fn friction(m: &ModelFile, bad: &Bad) -> Checked {
    let Some(f) = m.friction else {
        return Ok(());
    };
    finite(
        bad,
        "friction",
        &mut [f.coulomb, f.velocity_scale, f.offset].into_iter(),
    )?;
    if f.velocity_scale <= 0.0 {
        return Err(bad(
            "friction",
            format!(
                "velocity_scale is {}: the Coulomb force changes sign over a positive velocity",
                f.velocity_scale
            ),
        ));
    }
    if f.delay > MAX_FRICTION_DELAY {
        return Err(bad(
            "friction",
            format!("delay is {} samples, at most {MAX_FRICTION_DELAY}", f.delay),
        ));
    }
    if m.d != 0.0 {
        return Err(bad(
            "D",
            format!("{}: a model with friction has no feed-through (D = 0)", m.d),
        ));
    }
    if m.element.is_some() {
        return Err(bad(
            "friction",
            "friction is fitted on a two-path or static element, not beside \"element\""
                .to_string(),
        ));
    }
    Ok(())
}

/// The largest delay of a model with friction's element output a file may state (the fit
/// tries up to 2; a file may be written by hand).
pub const MAX_FRICTION_DELAY: usize = 1000;

type Bad<'a> = dyn Fn(&'static str, String) -> ModelFileError + 'a;

fn plant(m: &ModelFile, bad: &Bad) -> Checked {
    let n = m.order;
    if m.a.len() != n {
        return Err(bad(
            "A",
            format!("has {} rows, expected order = {n}", m.a.len()),
        ));
    }
    if let Some((i, row)) = m.a.iter().enumerate().find(|(_, r)| r.len() != n) {
        return Err(bad(
            "A",
            format!("row {i} has {} values, expected order = {n}", row.len()),
        ));
    }
    for (field, len) in [("B", m.b.len()), ("C", m.c.len()), ("poles", m.poles.len())] {
        if len != n {
            return Err(bad(
                field,
                format!("has {len} entries, expected order = {n}"),
            ));
        }
    }
    for (kf, bf, k, b) in [
        ("knots_asc", "border_asc", &m.knots_asc, &m.border_asc),
        ("knots_desc", "border_desc", &m.knots_desc, &m.border_desc),
    ] {
        if k.len() != b.len() {
            return Err(bad(
                bf,
                format!("has {} values but {kf} has {}", b.len(), k.len()),
            ));
        }
    }
    Ok(())
}

/// The largest magnitude of a number in a model file: products of two such numbers (the
/// simulation's `A x`, `C x`) stay far from overflow, and no model of a physical plant comes
/// near it.
pub const MAX_MAGNITUDE: f64 = 1e150;

/// Each value finite and at most [`MAX_MAGNITUDE`] in magnitude.
fn finite(bad: &Bad, field: &'static str, values: &mut dyn Iterator<Item = f64>) -> Checked {
    match values.enumerate().find(|(_, v)| !in_range(*v)) {
        Some((i, v)) if v.is_finite() => Err(bad(
            field,
            format!(
                "entry {i} is {v:e}, beyond the largest magnitude a model file holds \
                 ({MAX_MAGNITUDE:e}); rescale the signals or write the model again"
            ),
        )),
        Some((i, v)) => Err(bad(field, format!("entry {i} is {v}, not a finite number"))),
        None => Ok(()),
    }
}

/// Finite and at most [`MAX_MAGNITUDE`] in magnitude.
fn in_range(v: f64) -> bool {
    v.is_finite() && v.abs() <= MAX_MAGNITUDE
}

fn finite_all(m: &ModelFile, bad: &Bad) -> Checked {
    let one = |v: f64| std::iter::once(v);
    finite(bad, "A", &mut m.a.iter().flatten().copied())?;
    finite(bad, "B", &mut m.b.iter().copied())?;
    finite(bad, "C", &mut m.c.iter().copied())?;
    finite(bad, "D", &mut one(m.d))?;
    finite(bad, "poles", &mut m.poles.iter().flatten().copied())?;
    finite(bad, "mu0", &mut one(m.mu0))?;
    finite(bad, "u_min", &mut one(m.u_min))?;
    finite(bad, "u_max", &mut one(m.u_max))?;
    finite(bad, "knots_asc", &mut m.knots_asc.iter().copied())?;
    finite(bad, "knots_desc", &mut m.knots_desc.iter().copied())?;
    finite(bad, "border_asc", &mut m.border_asc.iter().copied())?;
    finite(bad, "border_desc", &mut m.border_desc.iter().copied())?;
    finite(
        bad,
        "singular_values",
        &mut m.singular_values.iter().copied(),
    )
}

fn knots(m: &ModelFile, bad: &Bad) -> Checked {
    if m.u_min >= m.u_max {
        return Err(bad(
            "u_max",
            format!("{} is not above u_min = {}", m.u_max, m.u_min),
        ));
    }
    for (field, k) in [("knots_asc", &m.knots_asc), ("knots_desc", &m.knots_desc)] {
        if k.len() < 2 {
            return Err(bad(
                field,
                format!(
                    "has {} knots: at least two (u_min and u_max) are needed",
                    k.len()
                ),
            ));
        }
        if let Some(i) = k.windows(2).position(|w| w[1] <= w[0]) {
            return Err(bad(
                field,
                format!(
                    "knot {} is not above knot {i}: knots must increase strictly",
                    i + 1
                ),
            ));
        }
        let (first, last) = (k[0], k[k.len() - 1]);
        if first != m.u_min || last != m.u_max {
            return Err(bad(
                field,
                format!(
                    "runs from {first} to {last}, but the interval is [u_min, u_max] = [{}, {}]",
                    m.u_min, m.u_max
                ),
            ));
        }
    }
    Ok(())
}

fn noise(m: &ModelFile, bad: &Bad) -> Checked {
    let Some(nm) = &m.noise else {
        return Ok(());
    };
    for (field, poly) in [("noise.c", &nm.c), ("noise.d", &nm.d)] {
        if poly.first() != Some(&1.0) {
            return Err(bad(field, "must start with 1 (a monic polynomial)".into()));
        }
        finite(bad, field, &mut poly.iter().copied())?;
    }
    if !(in_range(nm.sigma2) && nm.sigma2 >= 0.0) {
        return Err(bad(
            "noise.sigma2",
            format!("{} is not a finite variance >= 0", nm.sigma2),
        ));
    }
    Ok(())
}

fn std(m: &ModelFile, bad: &Bad) -> Checked {
    let Some(s) = &m.std else {
        return Ok(());
    };
    for (field, len, want) in [
        ("std.poles", s.poles.len(), m.poles.len()),
        ("std.border_asc", s.border_asc.len(), m.border_asc.len()),
        ("std.border_desc", s.border_desc.len(), m.border_desc.len()),
    ] {
        if len != want {
            return Err(bad(
                field,
                format!("has {len} entries, the estimates it describes {want}"),
            ));
        }
    }
    let all = s
        .poles
        .iter()
        .flatten()
        .chain(&s.border_asc)
        .chain(&s.border_desc)
        .chain(std::iter::once(&s.mu0))
        .chain(&s.mean_gap);
    if let Some(v) = all.copied().find(|v| !(in_range(*v) && *v >= 0.0)) {
        return Err(bad(
            "std",
            format!("{v} is not a standard deviation (finite, >= 0)"),
        ));
    }
    Ok(())
}
