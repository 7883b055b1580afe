//! What the checks need to know about the identification: the nonlinearity kind, the knots,
//! the hold and the horizons.

use crate::identify::IdentifyOptions;
use crate::model::Element;

/// What the checks need to know about the identification.
#[derive(Clone, Debug)]
pub struct CheckSetup<'a> {
    /// Element kind.
    pub kind: Element,
    /// Ascending knots.
    pub knots_asc: &'a [f64],
    /// Descending knots.
    pub knots_desc: &'a [f64],
    /// Hold samples at `u_min` (0: none).
    pub hold: usize,
    /// Samples of the hold skipped.
    pub settle: usize,
    /// A known μ0 was given.
    pub mu0_known: bool,
    /// Future horizon.
    pub f: usize,
    /// Past horizon.
    pub p: usize,
}

impl<'a> CheckSetup<'a> {
    /// The setup of an identification with `opts` (knots chosen) as `kind`.
    pub fn new(opts: &'a IdentifyOptions, kind: Element) -> Self {
        CheckSetup {
            kind,
            knots_asc: &opts.knots_asc,
            knots_desc: &opts.knots_desc,
            hold: opts.hold,
            settle: opts.settle,
            mu0_known: opts.mu0.is_some(),
            f: opts.f,
            p: opts.p,
        }
    }

    /// The knots' interval `(u_min, u_max)` and the tolerance of "at an end" of it.
    pub fn interval(&self) -> (f64, f64, f64) {
        let u_min = self.knots_asc.first().copied().unwrap_or(f64::NAN);
        let u_max = self.knots_asc.last().copied().unwrap_or(f64::NAN);
        (u_min, u_max, crate::table1::end_tolerance(u_min, u_max))
    }

    /// One border for both directions (a static nonlinearity).
    pub fn shared(&self) -> bool {
        self.kind == Element::Static
    }
}
