//! `--fit auto` (the default): whether `identify` fits the element itself after the
//! identification. The two-path model describes a backlash or switch under the Table I
//! excitation; when the record's input breaks it (`hsid_host::table1::Runs::breaks_table1`:
//! more than one, and more than a tenth, of the monotone runs start inside the range) the
//! element runs on inner loops and the simulation fit of the play or relay is run, with a
//! note that says why and how to turn it off. Where that fit cannot run (several records,
//! `--integrating`, `--stream`) the note says it was not run and why, and the run goes on.

use hsid_host::table1::{Runs, count_runs, end_tolerance};

use super::IdentifyArgs;
use super::simulation::FitArg;
use crate::args::NonlinearityArg;
use crate::failure::{Failure, outln};

/// Why the fit is wanted: the count of runs that start inside the range, in words.
pub fn why(runs: Runs, umin: f64, umax: f64) -> String {
    format!(
        "{} of {} monotone input runs start inside [{umin}, {umax}] (the Table I excitation \
         starts each at u_min or u_max)",
        runs.inside, runs.runs
    )
}

/// Whether `--fit auto` looks at the input at all: backlash and switch only (a static element
/// takes any input).
pub fn applies(a: &IdentifyArgs) -> bool {
    a.fit == FitArg::Auto && a.nonlinearity != NonlinearityArg::Static
}

/// Whether to run the simulation fit on the record `u` (all records joined, `parts` of
/// them, the hold's last sample at `hold - 1`). `--fit simulation` always (one record);
/// `--fit auto` when the input breaks the Table I structure and the fit can run, with a note
/// either way.
pub fn decide(a: &IdentifyArgs, u: &[f64], parts: usize, hold: usize) -> Result<bool, Failure> {
    match a.fit {
        FitArg::None => return Ok(false),
        FitArg::Simulation if parts > 1 => {
            return Err(
                "--fit simulation takes one record (one --data): the element's state \
                        does not carry across experiments"
                    .to_string()
                    .into(),
            );
        }
        FitArg::Simulation => return Ok(true),
        FitArg::Auto if !applies(a) => return Ok(false),
        FitArg::Auto => {}
    }
    let from = &u[hold.saturating_sub(1).min(u.len())..];
    let runs = count_runs(from, a.umin, a.umax, end_tolerance(a.umin, a.umax));
    if !runs.breaks_table1() {
        return Ok(false);
    }
    let why = why(runs, a.umin, a.umax);
    let blocked = if parts > 1 {
        Some("the element's fit takes one record (one --data)")
    } else if a.integrating {
        Some("the element's fit is not available with --integrating")
    } else {
        None
    };
    match blocked {
        Some(reason) => {
            outln!("--fit auto: {why}; {reason}: not run, the model is the two-path one")?;
            Ok(false)
        }
        None => {
            outln!(
                "--fit auto: {why}: fitting the element itself by simulation error (--fit none keeps the two-path model)"
            )?;
            Ok(true)
        }
    }
}
