//! What each residual test means when it fires, and what the user can do about it, in one
//! sentence each (the data checks' own words are in `validation::checks::advice`).

use crate::diagnose::Test;
pub(crate) use crate::validation::checks::advice::{BEFORE_FIT, check_advice};

/// `(what it means, what to do)` for a residual test that fires.
pub(crate) fn test_advice(t: Test) -> (&'static str, &'static str) {
    match t {
        Test::Whiteness => (
            "The residual is correlated with its own past: dynamics the model lacks, or \
             coloured noise.",
            "Run hsid diagnose: it tries further states and a noise model; or identify with a \
             higher --order.",
        ),
        Test::InputCorrelation => (
            "The residual follows the input: the linear part misses dynamics or a dead time.",
            "Look at the lag of the strongest correlation; hsid diagnose tries an input delay \
             and further states.",
        ),
        Test::DirectionCorrelation => (
            "The residual depends on the direction the input moves: the gap or the borders \
             are wrong.",
            "Try more segments per path, or a two-path element if the model is static.",
        ),
        Test::RegressorCorrelation => (
            "The residual is correlated with the border's regressor: a border misses shape.",
            "Try more segments per path, or knots placed where the border bends.",
        ),
        Test::StructureInput => (
            "The residual's mean differs between segments of a path: a border is biased there.",
            "Try more segments, and check that the record covers that segment.",
        ),
        Test::StructureOutput => (
            "The residual's mean depends on the output level: a static nonlinearity at the \
             output (a sensor curve).",
            "hsid diagnose tries an output nonlinearity.",
        ),
        Test::Trend => (
            "The residual drifts over time: an offset that moves (temperature, warm-up).",
            "hsid diagnose adds an offset drift; or let the sensor warm up before recording.",
        ),
        Test::SpectralLine => (
            "A sinusoid in the residual: a periodic disturbance (mains, a rotating part).",
            "hsid diagnose adds a periodic disturbance at that frequency; or remove its source.",
        ),
        Test::StateDependence => (
            "The residual depends on the level times the change of the output: dynamics that \
             change with the state (friction, stores).",
            "hsid diagnose tries state-dependent dynamics.",
        ),
        Test::HeavyTails => (
            "More samples beyond 5 robust standard deviations than Gaussian noise gives: \
             outliers.",
            "Find the spikes in the residual figure; hsid diagnose refits robustly.",
        ),
    }
}
