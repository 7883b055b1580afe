//! What `hsid identify` checks and reads before it identifies: flags that contradict each
//! other, and the records as identified (increments of an integrating plant, detrended).

use hsid_host::integrating;
use hsid_host::refine::knots::SegmentCount;

use super::IdentifyArgs;
use super::records::Records;
use super::simulation;
use crate::failure::{Failure, outln};

/// Refuses flags that contradict each other or cannot describe a record (`hold`: the hold
/// of the records as identified).
pub fn refuse_bad_flags(a: &IdentifyArgs, hold: usize) -> Result<(), Failure> {
    let (umin, umax) = (a.umin, a.umax);
    if !(umin.is_finite() && umax.is_finite() && umin < umax) {
        return Err(format!(
            "invalid input interval [{umin}, {umax}]: --umin must be finite and below --umax"
        )
        .into());
    }
    if a.segments == Some(SegmentCount::Fixed(0)) {
        return Err("--segments 0: each path needs at least one segment"
            .to_string()
            .into());
    }
    if a.detrend && hold > 0 {
        return Err(format!(
            "--detrend applies to data without a hold (--hold 0); with --hold {hold} μ0 is \
             measured by the hold: drop --detrend or give --hold 0"
        )
        .into());
    }
    if a.fit == simulation::FitArg::Simulation && (a.stream || a.integrating) {
        return Err(
            "--fit simulation needs the whole record (not --stream) and a plant without an \
             integrator (not --integrating): drop those, or give --fit auto or none"
                .to_string()
                .into(),
        );
    }
    super::reference::refuse_bad_flags(a)
}

/// The records as identified: read, their junctions checked, as increments for an
/// integrating plant, their mean removed with `--detrend`; the first must outlast the hold.
pub fn read_records(a: &IdentifyArgs, hold: usize) -> Result<Records, Failure> {
    let reference = a.reference_column.as_deref();
    let mut records = Records::read(&a.data, &a.columns, reference, &a.csv, &a.units)?;
    records.check_junctions(a.umin, a.hold.settle())?;
    if a.integrating {
        to_increments(&mut records);
        outln!(
            "integrating: one pole fixed at z = 1; the stable part G₀ is identified on the output's increments y(t) − y(t − 1) (G₀(1) = 1: μ0, the borders and the fits below are in output units per sample)"
        )?;
    }
    let first = records.parts().first().map_or(0, |p| p.0.len());
    if hold >= first {
        return Err(format!(
            "{}: {first} samples, all inside the hold of {hold} (--hold): nothing left to identify from",
            records.first().display(),
        )
        .into());
    }
    if a.detrend {
        let mean = records.y.iter().sum::<f64>() / records.y.len() as f64;
        records.y.iter_mut().for_each(|v| *v -= mean);
        outln!("detrended: subtracted the mean output {mean:.6} from y")?;
    }
    Ok(records)
}

/// Each record as the record of its increments: its first sample dropped, its output
/// differenced (`y(t) − y(t − 1)`, within the record only).
fn to_increments(r: &mut Records) {
    let parts: Vec<(Vec<f64>, Vec<f64>)> = r
        .parts()
        .into_iter()
        .map(|(u, y)| integrating::increments(u, y))
        .collect();
    (r.u, r.y, r.starts) = (Vec::new(), Vec::new(), Vec::new());
    for (u, y) in parts {
        r.starts.push(r.u.len());
        r.u.extend(u);
        r.y.extend(y);
    }
    for lines in &mut r.lines {
        lines.drain(..lines.len().min(1));
    }
}
