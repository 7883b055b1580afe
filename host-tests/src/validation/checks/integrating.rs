//! An integrating plant (voltage → position, a level loop), seen in the data: the ARX
//! unit-root test of [`unit_root`](crate::validation::unit_root) does not reject `Σ aᵢ = 1`.
//! The method's normalisation `G(1) = 1` then divides by nearly zero, the borders lose their
//! meaning, and no extension can be scored against the model: the diagnosis adds nothing and
//! points at `--integrating`.
//!
//! The test is of the data rather than of the base model's poles: a model fitted under a
//! normalisation the plant breaks puts its poles anywhere (an integrator's base model can keep
//! every pole well inside the unit circle), while a slow stable plant's model can put one at
//! the circle although its data reject the unit root far beyond the 1 % level.

use super::warning::{Check, Warning, warn};
use crate::validation::unit_root::{CRITICAL_1PCT, UnitRoot};

/// A warning when the unit root is not rejected at 1 % (`None`: the test could not be run on
/// a record this short, and nothing is said).
pub fn integrating(test: Option<&UnitRoot>) -> Option<Warning> {
    let t = test.filter(|t| !t.rejected())?;
    Some(warn(
        Check::Integrating,
        format!(
            "the output integrates: an ARX model of it on the input ({} output lags) keeps a unit root (Dickey–Fuller τ = {:.2}, not below the 1 % critical value {CRITICAL_1PCT}; Σaᵢ − 1 = {:+.4}); the plant may integrate (voltage → position, a level loop), so the model's gain normalisation G(1) = 1 and its borders are meaningless and no effect is scored against it; `hsid diagnose --integrating` diagnoses its stable part on the output's increments (a sensor whose offset wanders as a random walk looks the same)",
            t.ar_order, t.tau, t.rho
        ),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fires_only_when_the_unit_root_stands() -> Result<(), String> {
        let kept = UnitRoot {
            ar_order: 3,
            rho: -0.0004,
            tau: -0.4,
        };
        let w = integrating(Some(&kept)).ok_or("no warning")?;
        assert_eq!(w.check, Check::Integrating);
        assert!(w.message.contains("τ = -0.40"), "{}", w.message);
        let rejected = UnitRoot { tau: -9.4, ..kept };
        assert!(integrating(Some(&rejected)).is_none());
        assert!(integrating(None).is_none());
        Ok(())
    }
}
