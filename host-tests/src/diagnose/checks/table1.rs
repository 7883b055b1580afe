//! The Table I structure: every monotone input run starts at `u_min` (ascending) or `u_max`
//! (descending).

use super::setup::CheckSetup;
use super::warning::{Check, Warning, warn};
use crate::diagnose::options::Nonlinearity;

/// Runs that do not start at an end of the interval (backlash and switch only).
pub fn table1_structure(ex: &[f64], s: &CheckSetup) -> Vec<Warning> {
    let mut out = Vec::new();
    let (u_min, u_max, tol) = s.interval();
    // Table I: every monotone run starts at u_min (ascending) or u_max (descending).
    if s.kind != Nonlinearity::Static {
        let (mut runs, mut bad) = (0usize, 0usize);
        let mut dir = 0i8;
        for w in ex.windows(2) {
            let d = if w[1] > w[0] {
                1
            } else if w[1] < w[0] {
                -1
            } else {
                0
            };
            if d != 0 && d != dir {
                runs += 1;
                let ok = if d > 0 {
                    (w[0] - u_min).abs() <= tol
                } else {
                    (w[0] - u_max).abs() <= tol
                };
                if !ok {
                    bad += 1;
                }
                dir = d;
            }
        }
        if bad > 0 {
            let msg = match s.kind {
                Nonlinearity::Backlash => format!(
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
