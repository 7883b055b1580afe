//! What each figure of `identify`, `validate` and `diagnose` shows and what to look at in it,
//! by the figure's file name (without the `.svg` and any prefix).

/// `(title, caption)` of the figure written as `stem.svg`; `None` for a name this table does
/// not know (the page then shows the file name as the title and says it has no caption).
pub fn caption(stem: &str) -> Option<(&'static str, &'static str)> {
    Some(match stem {
        "borders" => (
            "The identified loop",
            "The two borders of the input element (rising P_a, falling P_d) times the static \
             gain, with ±2σ bands when the model was refined, the measured points (partial \
             residuals: what the record says the border is at each sample) and, dashed, the \
             true loop when known. The arrow marks the gap at the middle of the input \
             interval: arriving there falling, on P_d, the input must climb by the gap before \
             P_a reaches the same value (± one standard deviation when the model has one). Look for points that leave the bands systematically: a \
             border that misses shape there (more segments, or knots where it bends).",
        ),
        "borders-detail" => (
            "The identified loop around the gap",
            "The borders figure cut to an eighth of the input interval on each side of the \
             gap marker, where the loop is wide: the ±2σ bands, the true loop when known and \
             the gap can be read. A true loop outside the bands is a bias of the borders, \
             not noise.",
        ),
        "bode-magnitude" => (
            "Bode magnitude of the linear part",
            "Gain of the linear dynamics against frequency, ±2σ band. The band widens where \
             the record holds little energy; the resonance peak and the roll-off are what a \
             controller design reads here.",
        ),
        "bode-phase" => (
            "Bode phase of the linear part",
            "Phase against frequency. A phase that keeps falling beyond the poles' count \
             is a sign of dead time the model lacks. Near the Nyquist frequency the phase of a \
             sampled model returns to a multiple of 180°: a zero near z = −1 (which sampling \
             gives a continuous plant of relative degree two or more) lifts it there; that rise is the model's, not a \
             fault.",
        ),
        "poles" => (
            "Poles in the z-plane",
            "Discrete poles with the unit circle and their 2σ ellipses. Poles near the circle \
             are slow or lightly damped; an ellipse that reaches the circle means the record \
             does not pin that mode down.",
        ),
        "output" => (
            "Measured and simulated output",
            "The model simulated from the input alone over the record. The two curves should \
             overlap up to the noise; a lag or an offset that grows over time is a missing \
             dead time or a drift.",
        ),
        "output-detail" => (
            "Measured and simulated output, in detail",
            "A short stretch of the output figure, where the reversals can be seen: after each \
             reversal the simulated output should wait out the gap as the measured one does.",
        ),
        s if s.starts_with("poles-zoom") => (
            "Poles in the z-plane, close up",
            "The neighbourhood of one pole (pair) with its 2σ ellipse: how precisely the \
             record determines it.",
        ),
        "residual" => (
            "Simulation residual",
            "Measured minus simulated output after the hold. It should look like noise \
             without trend, steps at the reversals or spikes.",
        ),
        "residual-acf" | "autocorrelation" => (
            "Residual autocorrelation",
            "Autocorrelation of the residual with the white-noise bounds. Bars outside the \
             bounds at small lags mean unmodelled dynamics or coloured noise.",
        ),
        "input-correlation" => (
            "Input–residual cross-correlation",
            "Correlation of the (prewhitened) input with the residual, before and after the \
             diagnosis. A peak outside the bounds at a positive lag is dynamics or a delay the \
             model misses.",
        ),
        "spectrum" => (
            "Residual spectrum",
            "Periodogram of the residual against the local median spectrum and the 99 % line \
             threshold. A single peak above the threshold is a periodic disturbance.",
        ),
        "residual-vs-input" => (
            "Residual against the input",
            "Validation residual before and after the diagnosis against the input. A pattern \
             that follows u (a slope, a step at a knot) means a border is wrong there.",
        ),
        "residual-vs-output" => (
            "Residual against the simulated output",
            "Residual against the output level. A curve here is a static nonlinearity at the \
             output (a sensor curve).",
        ),
        _ => return None,
    })
}

/// `(title, caption)` of a figure of an element model (the play operator or relay itself,
/// `write_element_figures`): its own `borders` figure, the others as [`caption`] says.
pub(crate) fn element_caption(stem: &str) -> Option<(&'static str, &'static str)> {
    match stem {
        "borders" => Some((
            "The element: borders and its output on the record",
            "The borders H_a (rising) and H_d (falling) of the play operator or relay, with \
             ±2σ bands when the fit gave them (a model file keeps none), the element's output \
             w(t) on the record (inner loops of a play, jumps of a relay), the measured points \
             (partial residuals) and, dashed, the true loop when known. The title gives the \
             play's gap at mid-range (the mean of both directions); the arrow marks the one \
             after a descent there, from H_d to H_a, with its standard deviation. Points that \
             leave the path systematically: a border that misses shape there.",
        )),
        "borders-detail" => Some((
            "The element around the gap",
            "The element's figure cut to an eighth of the input interval on each side of the \
             gap marker, where the loop, its ±2σ bands and the gap can be read.",
        )),
        _ => caption(stem),
    }
}

#[cfg(test)]
mod tests {
    use super::{caption, element_caption};

    #[test]
    fn an_element_figure_has_its_own_borders_caption_and_shares_the_others() {
        assert_ne!(element_caption("borders"), caption("borders"));
        assert!(element_caption("borders").is_some_and(|(_, c)| c.contains("H_a")));
        assert_eq!(element_caption("output"), caption("output"));
        assert!(element_caption("unknown").is_none());
    }

    #[test]
    fn every_figure_of_identify_and_diagnose_has_a_caption() {
        for stem in [
            "borders",
            "borders-detail",
            "bode-magnitude",
            "bode-phase",
            "poles",
            "poles-zoom-1",
            "output-detail",
            "output",
            "residual",
            "residual-acf",
            "autocorrelation",
            "input-correlation",
            "spectrum",
            "residual-vs-input",
            "residual-vs-output",
        ] {
            assert!(caption(stem).is_some(), "{stem}");
        }
        assert!(caption("unknown").is_none());
    }
}
