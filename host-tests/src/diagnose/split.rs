//! The data split: the estimation record, the validation record and its scored samples, from
//! the records given and [`Validation`]; the records checked against the knots' interval.

use std::ops::Range;

use super::error::DiagnoseError;
use super::options::Validation;
use crate::closed_loop::ReferenceError;
use crate::identify::IdentifyOptions;
use crate::model::Record;

/// Estimation and validation data.
#[derive(Clone, Debug)]
pub struct DataSplit {
    /// The estimation record.
    pub estimation: Record,
    /// The record the validation simulation runs over.
    pub validation: Record,
    /// Its scored samples.
    pub range: Range<usize>,
    /// How the data were formed, in words.
    pub description: String,
}

/// Fewest samples an estimation record needs with these options.
pub(crate) fn min_len(id: &IdentifyOptions) -> usize {
    // Saturating: a hold or horizons near `usize::MAX` need more samples than any record has.
    id.f.saturating_add(id.p)
        .saturating_mul(4)
        .saturating_add(id.hold)
        .saturating_add(50)
}

/// `u` and `y` of one length, every input inside `[u_min, u_max]`.
pub(crate) fn check_record(
    rec: &Record,
    which: &'static str,
    u_min: f64,
    u_max: f64,
) -> Result<(), DiagnoseError> {
    if rec.u.len() != rec.y.len() {
        return Err(DiagnoseError::LengthMismatch {
            u: rec.u.len(),
            y: rec.y.len(),
        });
    }
    if let Some((index, &value)) = rec
        .u
        .iter()
        .enumerate()
        .find(|(_, v)| !(**v >= u_min && **v <= u_max))
    {
        return Err(DiagnoseError::InputOutOfRange {
            record: which,
            index,
            value,
            u_min,
            u_max,
        });
    }
    Ok(())
}

/// A closed-loop record's reference, if it has one: one finite value per sample, not constant
/// after the hold, and a two-path element (the closed-loop estimate is for backlash or
/// switch).
pub(crate) fn check_reference(rec: &Record, id: &IdentifyOptions) -> Result<(), DiagnoseError> {
    let Some(r) = &rec.reference else {
        return Ok(());
    };
    let err = |e| Err(DiagnoseError::Reference(e));
    if id.static_nonlinearity {
        return err(ReferenceError::StaticElement);
    }
    if r.len() != rec.len() {
        return err(ReferenceError::LengthMismatch {
            u: rec.u.len(),
            y: rec.y.len(),
            r: r.len(),
        });
    }
    if let Some(at) = r.iter().position(|v| !v.is_finite()) {
        return err(ReferenceError::NonFiniteReference { at });
    }
    let moving = &r[id.hold.min(r.len())..];
    if moving.iter().all(|&v| v == moving[0]) {
        return err(ReferenceError::ConstantReference);
    }
    Ok(())
}

/// Splits `record` (the estimation record, or the whole record for [`Validation::Split`] and
/// [`Validation::Holdout`]) as `validation` says.
pub fn split(
    record: &Record,
    validation: &Validation,
    id: &IdentifyOptions,
) -> Result<DataSplit, DiagnoseError> {
    let (u_min, u_max) = (id.u_min(), id.u_max());
    check_record(record, "estimation", u_min, u_max)?;
    let hold = id.hold;
    let n = record.len();
    if hold >= n {
        return Err(DiagnoseError::AllHold { samples: n, hold });
    }
    let min_len = min_len(id);
    if n < min_len {
        return Err(DiagnoseError::TooShort {
            samples: n,
            need: min_len,
        });
    }
    check_reference(record, id)?;
    let split = match validation {
        Validation::Separate { record: v, skip } => {
            check_record(v, "validation", u_min, u_max)?;
            if *skip >= v.len() {
                return Err(DiagnoseError::InvalidHoldout {
                    start: *skip,
                    end: v.len(),
                    len: v.len(),
                });
            }
            DataSplit {
                estimation: record.clone(),
                validation: v.clone(),
                range: *skip..v.len(),
                description: format!(
                    "estimation: all {n} samples of the estimation record; validation: a separate record of {} samples, simulated from its start with the input only, scored from sample {skip}",
                    v.len()
                ),
            }
        }
        Validation::Split(frac) => {
            if !(*frac > 0.0 && *frac < 1.0) {
                return Err(DiagnoseError::InvalidSplit(*frac));
            }
            let at = hold + ((n - hold) as f64 * frac).round() as usize;
            if at + 50 > n || at < min_len {
                return Err(DiagnoseError::TooShort {
                    samples: n,
                    need: min_len.max(at + 50),
                });
            }
            DataSplit {
                estimation: record.slice(0..at),
                validation: record.clone(),
                range: at..n,
                description: format!(
                    "no validation record: samples 0..{at} ({:.0} % of the samples after the hold) estimate, samples {at}..{n} validate; the validation simulation runs from the start of the record with the input only",
                    100.0 * frac
                ),
            }
        }
        Validation::Holdout(r) => {
            if r.start >= r.end || r.start < hold || r.end > n {
                return Err(DiagnoseError::InvalidHoldout {
                    start: r.start,
                    end: r.end,
                    len: n,
                });
            }
            DataSplit {
                estimation: record.joined(&[0..r.start, r.end..n]),
                validation: record.clone(),
                range: r.clone(),
                description: format!(
                    "samples {}..{} are held out for validation; the other {} samples, joined at the gap, estimate; the validation simulation runs from the start of the record with the input only",
                    r.start,
                    r.end,
                    n - (r.end - r.start)
                ),
            }
        }
    };
    // The estimation part alone must still move the reference.
    check_reference(&split.estimation, id)?;
    if split.estimation.len() < min_len {
        return Err(DiagnoseError::TooShort {
            samples: split.estimation.len(),
            need: min_len,
        });
    }
    Ok(split)
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::panic)]
    use super::*;

    #[test]
    fn a_hold_of_every_sample_or_more_is_refused_without_overflow() {
        let record = Record::new(vec![0.0; 500], vec![0.0; 500]).unwrap();
        for hold in [500, usize::MAX] {
            let id = IdentifyOptions::uniform(-1.0, 1.0, 3, hold);
            match split(&record, &Validation::Split(0.7), &id) {
                Err(DiagnoseError::AllHold {
                    samples: 500,
                    hold: h,
                }) => assert_eq!(h, hold),
                other => panic!("{other:?}"),
            }
        }
        let mut id = IdentifyOptions::uniform(-1.0, 1.0, 3, 0);
        id.f = usize::MAX;
        assert_eq!(min_len(&id), usize::MAX);
    }
}
