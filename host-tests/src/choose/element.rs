//! The static element beside a two-path one: when the user names no element, the default
//! backlash is not assumed to be the record's element. A deadzone, a saturation or a sensor
//! curve has no memory, and a two-path model then spends half its border parameters on a
//! play the data do not have: on an input with few reversals (a staircase, quantised levels)
//! the two paths are fitted on different samples and disagree where the element does not.
//!
//! The static model is identified at the structure the two-path model's choices found (its
//! segment count per path and its order), with its own knots where the record has samples and
//! its own horizons (the static element's input Hankel Gram has other channels: horizons the
//! two-path regressor supports can leave it rank deficient), and refined like it; the inner
//! hold-out then decides between them and the linear baseline
//! ([`crate::workflow::baseline`]). One refinement more, not a second search over segments and
//! orders.

use super::{Best, Choices, ChooseError, KnotPlacement, Segments, best_model};
use crate::identify::IdentifyOptions;
use crate::reference::uniform_knots;

/// The static model of `(u, y)` at the structure of the two-path model `two_path` (identified
/// from `base` with `choices`): its segment count per path (the given knots' count when the
/// count was not chosen) and order, knots merged where the record has few samples when
/// `choices` places them so, horizons as `choices` sets them.
pub fn static_beside(
    u: &[f64],
    y: &[f64],
    base: &IdentifyOptions,
    choices: &Choices,
    two_path: &Best,
) -> Result<Best, ChooseError> {
    let segments = two_path.segments.as_ref().map_or_else(
        || base.knots_asc.len().saturating_sub(1).max(1),
        |s| s.segments,
    );
    let mut opts = base.clone();
    opts.static_nonlinearity = true;
    opts.knots_asc = uniform_knots(base.u_min(), base.u_max(), segments);
    opts.knots_desc = opts.knots_asc.clone();
    opts.order = Some(two_path.model.order);
    let choices = Choices {
        segments: Segments::Given,
        knots: match choices.knots {
            KnotPlacement::FromData => KnotPlacement::FromData,
            KnotPlacement::Given => KnotPlacement::Given,
        },
        ..choices.clone()
    };
    best_model(u, y, &opts, &choices)
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    /// A first-order plant behind a deadzone, driven by a staircase: the static model is
    /// identified at the backlash model's order, and its border follows the deadzone.
    #[test]
    fn the_static_model_takes_the_two_path_order_and_reads_a_deadzone() {
        let n = 3000;
        let mut state = 0.37_f64;
        let mut level = 0.0;
        let u: Vec<f64> = (0..n)
            .map(|t| {
                if t % 40 == 0 {
                    state = (state * 3.7 + 0.123).fract();
                    level = 2.0 * state - 1.0;
                }
                level
            })
            .collect();
        let w: Vec<f64> = u
            .iter()
            .map(|&x| x.signum() * (x.abs() - 0.2).max(0.0) / 0.8)
            .collect();
        let mut y = vec![0.0; n];
        for t in 1..n {
            y[t] = 0.8 * y[t - 1] + 0.2 * w[t - 1];
        }
        let base = IdentifyOptions::uniform(-1.0, 1.0, 7, 0);
        let choices = Choices::default();
        let backlash = best_model(&u, &y, &base, &choices).unwrap();
        let s = static_beside(&u, &y, &base, &choices, &backlash).unwrap();
        assert!(s.options.static_nonlinearity);
        assert_eq!(s.model.order, backlash.model.order);
        // The border at 0 (inside the deadzone) and at 0.6 (0.5 out of it).
        let h = |x: f64| s.model.border_asc_at(x);
        assert!(h(0.0).abs() < 0.02, "H(0) = {}", h(0.0));
        assert!((h(0.6) - h(0.0) - 0.5).abs() < 0.03, "H(0.6) = {}", h(0.6));
    }
}
