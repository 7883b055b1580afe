//! Tests of the level-dependent stores against plants of their class.

use super::fixtures::{levels, model};
use super::*;
use crate::numerics::rms_error;

type Outcome = Result<(), Box<dyn std::error::Error>>;

/// Two tanks: square-root outflows, the upper one overflowing at 1.2 with half the excess
/// reaching the lower one; the output is the lower level.
fn tanks() -> Stores {
    Stores {
        k: [0.08, 0.06],
        alpha: [0.5, 0.5],
        c: [0.0, 1.0],
        d: 0.0,
        offset: 0.0,
        inflow_offset: 0.0,
        level: 1.2,
        spill: 0.5,
        x0: [0.5, 0.5],
    }
}

/// Inflow levels in [0.02, 0.12], 20 samples each (the upper tank overflows above 0.088).
fn inflow(n: usize, seed: u64) -> Vec<f64> {
    levels(n, seed).iter().map(|v| 0.02 + 0.1 * v).collect()
}

#[test]
fn steady_output_is_where_the_simulation_settles() -> Outcome {
    let t = tanks();
    // Below the overflow (0.05 < 0.08 · √1.2 = 0.0876) and above it.
    for h in [0.05, 0.11] {
        let y = t.simulate(&vec![h; 4000]).ok_or("not simulated")?;
        let last = y.last().copied().ok_or("empty")?;
        assert!(
            (last - t.steady_output(h)).abs() < 1e-6,
            "h = {h}: settles at {last}, steady_output {}",
            t.steady_output(h)
        );
    }
    Ok(())
}

#[test]
fn linear_start_simulates_like_the_linear_model() -> Outcome {
    // The cascade x1⁺ = 0.95 x1 + h, x2⁺ = 0.9 x2 + x1, y = 0.1 x1 + 0.05 x2 as a model.
    let lin = model([[0.95, 0.0], [1.0, 0.9]], [1.0, 0.0], [0.1, 0.05], 0.0);
    let h = levels(2000, 3);
    let y = lin.linear_response(&h, &[0.0, 0.0]);
    let [cascade, _] = lin.start_cascades()?;
    let start = linear_start(&cascade, 0.0, 0.0, 0.0, 1.0).ok_or("no start")?;
    let ys = start.simulate(&h).ok_or("not simulated")?;
    // Sub-steps discretise the cascade's coupling differently: a small mismatch only.
    let spread = rms_error(&y, &vec![y.iter().sum::<f64>() / y.len() as f64; y.len()]);
    let e = rms_error(&y, &ys);
    assert!(e < 0.05 * spread, "start error {e}, output spread {spread}");
    Ok(())
}

#[test]
fn fit_recovers_two_tanks() -> Outcome {
    recovers_two_tanks(START_WINDOW)
}

/// The starts tried on the first 1,000 of the 3,000 samples (with at most 25 iterations),
/// the best continued on all of them: the same tanks recovered.
#[test]
fn fit_recovers_two_tanks_from_starts_on_a_window() -> Outcome {
    recovers_two_tanks(1000)
}

fn recovers_two_tanks(window: usize) -> Outcome {
    let truth = tanks();
    let h = inflow(3000, 11);
    let y = truth.simulate(&h).ok_or("not simulated")?;
    // The start: the cascade form of the tanks linearised at a mid level, the static
    // gain matched there (dq/dx = k α x^(α−1), dy/dh = 2 h / k2²).
    let (h_mid, x1, x2): (f64, f64, f64) =
        (0.07, (0.07f64 / 0.08).powi(2), (0.07f64 / 0.06).powi(2));
    let p1 = 1.0 - 0.08 * 0.5 / x1.sqrt();
    let p2 = 1.0 - 0.06 * 0.5 / x2.sqrt();
    let c2 = 2.0 * h_mid / (0.06 * 0.06) * (1.0 - p1) * (1.0 - p2);
    let lin = model([[p1, 0.0], [1.0, p2]], [1.0, 0.0], [0.0, c2], 0.0);
    let skip = vec![false; h.len()];
    let data = DynamicsFit {
        h: &h,
        y: &y,
        skip: &skip,
        map: None,
        fit_x0: true,
        radius_limit: 1.0,
        iterations: ITERATIONS,
        borders: None,
    };
    let x0 = [x1 / (1.0 - p2), 0.0];
    let before = rms_error(&lin.linear_response(&h, &x0), &y);
    let (fit, _) = fit_with_window(&lin, &x0, &data, StoresClass::LevelDependent, window)?;
    let after = rms_error(&fit.simulate(&h).ok_or("not simulated")?, &y);
    assert!(
        after < 0.01 * before,
        "before {before}, after {after}: {fit:?}"
    );
    // On a new input too, and with the tanks' own steady states.
    let h2 = inflow(3000, 12);
    let y2 = truth.simulate(&h2).ok_or("not simulated")?;
    let new = rms_error(&fit.simulate(&h2).ok_or("not simulated")?, &y2);
    assert!(new < 0.02 * before, "new input: {new} (before {before})");
    for h in [0.03, 0.06, 0.11] {
        let (a, b) = (fit.steady_output(h), truth.steady_output(h));
        assert!(
            (a - b).abs() < 0.02 * b,
            "steady output at h = {h}: {a} vs {b}"
        );
    }
    Ok(())
}
