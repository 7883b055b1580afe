//! `hsid diagnose --integrating`: an integrating plant (voltage → position, a level loop) is
//! diagnosed through its stable part `G₀`, on the records of its increments
//! `Δy(t) = y(t) − y(t − 1)` with one pole fixed at `z = 1`, as `hsid identify --integrating`
//! identifies it (`hsid_host::integrating`): every error and residual of the report is then of
//! the increments, in output units per sample. A position simulated from the input alone
//! drifts with any error of the rate, so the increments are where a model of such a plant is
//! scored.

use hsid_host::diagnose::Validation;

/// The validation of the increments' records: a separate record's increments
/// ([`Record::increments`](hsid_host::model::Record::increments): the first sample, which has
/// no increment, dropped, the output differenced, each sample keeping its time), its unscored
/// samples and a held-out range one sample earlier (the record lost its first sample).
pub fn validation(v: Validation) -> Validation {
    match v {
        Validation::Separate { record, skip } => Validation::Separate {
            record: record.increments(),
            skip: skip.saturating_sub(1),
        },
        Validation::Holdout(r) => {
            Validation::Holdout(r.start.saturating_sub(1)..r.end.saturating_sub(1))
        }
        split @ Validation::Split(_) => split,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn increments_drop_the_first_sample_and_keep_the_times() -> Result<(), String> {
        let r = hsid_host::model::Record::new(vec![1.0, 2.0, 3.0], vec![0.0, 0.5, 2.0])
            .map_err(|e| e.to_string())?;
        let d = r.increments();
        assert_eq!(d.u, [2.0, 3.0]);
        assert_eq!(d.y, [0.5, 1.5]);
        assert_eq!(d.time, [1.0, 2.0]);
        let shifted = validation(Validation::Holdout(10..20));
        assert!(
            matches!(shifted, Validation::Holdout(ref h) if *h == (9..19)),
            "{shifted:?}"
        );
        Ok(())
    }
}
