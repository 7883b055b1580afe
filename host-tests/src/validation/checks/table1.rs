//! The Table I structure: every monotone input run starts at `u_min` (ascending) or `u_max`
//! (descending).

use super::setup::CheckSetup;
use super::warning::{Check, Warning, warn};
use crate::model::Element;
use crate::table1::{Runs, count_runs};

/// Runs that do not start at an end of the interval (backlash and switch only). `ex` is the
/// record from the last sample of the hold on (the whole record without a hold), so that the
/// first run's start is a sample of the record.
pub(crate) fn table1_structure(ex: &[f64], s: &CheckSetup) -> Vec<Warning> {
    let mut out = Vec::new();
    let (u_min, u_max, tol) = s.interval();
    if s.kind != Element::Static {
        let Runs { runs, inside: bad } = count_runs(ex, u_min, u_max, tol);
        if bad > 0 {
            let msg = match s.kind {
                Element::Backlash => format!(
                    "{bad} of {runs} monotone input runs do not start at u_min (ascending) or u_max (descending), as the Table I excitation does: a backlash is then on inner loops, not on its paths P_a/P_d, and the identified borders are biased there"
                ),
                _ => format!(
                    "{bad} of {runs} monotone input runs do not start at u_min or u_max (not the Table I excitation): a switch only needs the direction, but the paths are then visited unevenly"
                ),
            };
            out.push(warn(Check::Table1Structure, msg));
        }
    }
    out
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;
    use hsid::Excitation;
    use rand_core::SeedableRng;
    use rand_pcg::Pcg32;

    fn setup(knots: &[f64]) -> CheckSetup<'_> {
        CheckSetup {
            kind: Element::Backlash,
            knots_asc: knots,
            knots_desc: knots,
            hold: 300,
            settle: 150,
            mu0_known: false,
            f: 10,
            p: 10,
        }
    }

    #[test]
    fn the_table1_excitation_passes_and_an_inner_reversal_is_counted() {
        let knots = [-1.0, 0.0, 1.0];
        let s = setup(&knots);
        let u: Vec<f64> = Excitation::new(-1.0, 1.0, 300, Pcg32::seed_from_u64(3))
            .unwrap()
            .take(2300)
            .collect();
        assert!(table1_structure(&u[299..], &s).is_empty());
        // Starting after the hold's last sample makes the first run start at a random level.
        assert_eq!(table1_structure(&u[300..], &s).len(), 1);
        // An inner loop: up from u_min to 0.5, down from 0.5 (not u_max), up from 0.2.
        let inner = [-1.0, 0.5, 0.2, 0.8, 1.0];
        let w = table1_structure(&inner, &s);
        assert_eq!(w.len(), 1);
        assert_eq!(w[0].check, Check::Table1Structure);
        assert!(
            w[0].message.starts_with("2 of 3 monotone"),
            "{}",
            w[0].message
        );
    }
}
