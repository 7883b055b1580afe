//! A measured record as it enters the host: input and output, the controller's reference of
//! a closed-loop record, the sample time and units when known, the hold at its start, and
//! where each experiment of a joined record starts, and the time of each sample (kept when a
//! record is cut, so that a junction shows as a jump).

use std::ops::Range;

use crate::model_file::Units;

/// A record: one or several experiments on the same plant, joined in the order given.
#[derive(Clone, Debug, PartialEq)]
pub struct Record {
    /// Input samples.
    pub u: Vec<f64>,
    /// Output samples.
    pub y: Vec<f64>,
    /// Time of each sample, in samples: its index in the record as given (`0, 1, …` from the
    /// constructors), kept by [`Record::slice`] and [`Record::joined`] so that a junction
    /// shows as a jump. Time-dependent terms (trends, settling) are evaluated at it.
    pub time: Vec<f64>,
    /// The controller's reference of a closed-loop record, one value per sample.
    pub reference: Option<Vec<f64>>,
    /// Sample time in seconds, when known.
    pub ts: Option<f64>,
    /// Units of the input and the output, when known.
    pub units: Option<Units>,
    /// Samples of the hold at `u_min` at the start of the first experiment (0: none).
    pub hold: usize,
    /// Index of each experiment's first sample (the first is 0).
    pub starts: Vec<usize>,
}

/// Why samples do not make a record.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum RecordError {
    /// `u` and `y` differ in length.
    #[error("u has {u} samples but y has {y}: give one y per u")]
    LengthMismatch {
        /// Input samples.
        u: usize,
        /// Output samples.
        y: usize,
    },
    /// The reference differs in length from `u`.
    #[error("the reference has {r} samples but u has {u}: give one reference value per u")]
    ReferenceLength {
        /// Input samples.
        u: usize,
        /// Reference samples.
        r: usize,
    },
}

impl Record {
    /// One experiment `(u, y)` without hold, sample time or units.
    pub fn new(u: Vec<f64>, y: Vec<f64>) -> Result<Self, RecordError> {
        if u.len() != y.len() {
            return Err(RecordError::LengthMismatch {
                u: u.len(),
                y: y.len(),
            });
        }
        Ok(Self::checked(u, y))
    }

    /// One experiment from its samples `(u(t), y(t))`, without hold, sample time or units:
    /// one output per input by construction.
    pub fn from_samples(samples: impl IntoIterator<Item = (f64, f64)>) -> Self {
        let (u, y) = samples.into_iter().unzip();
        Self::checked(u, y)
    }

    /// The record of `u` and `y`, whose lengths the caller checked.
    fn checked(u: Vec<f64>, y: Vec<f64>) -> Self {
        let time = (0..u.len()).map(|t| t as f64).collect();
        Self {
            u,
            y,
            time,
            reference: None,
            ts: None,
            units: None,
            hold: 0,
            starts: vec![0],
        }
    }

    /// The record with a hold of `hold` samples at its start.
    pub fn with_hold(mut self, hold: usize) -> Self {
        self.hold = hold;
        self
    }

    /// The record with the controller's reference `r` (one value per sample).
    pub fn with_reference(mut self, r: Vec<f64>) -> Result<Self, RecordError> {
        if r.len() != self.u.len() {
            return Err(RecordError::ReferenceLength {
                u: self.u.len(),
                r: r.len(),
            });
        }
        self.reference = Some(r);
        Ok(self)
    }

    /// Samples.
    pub fn len(&self) -> usize {
        self.u.len()
    }

    /// No samples.
    pub fn is_empty(&self) -> bool {
        self.u.is_empty()
    }

    /// The sample range of each experiment.
    pub(crate) fn ranges(&self) -> Vec<Range<usize>> {
        let ends = self.starts.iter().skip(1).copied().chain([self.u.len()]);
        self.starts.iter().zip(ends).map(|(&a, b)| a..b).collect()
    }

    /// The samples of each experiment, `(u, y)`.
    pub fn parts(&self) -> Vec<(&[f64], &[f64])> {
        self.ranges()
            .into_iter()
            .map(|r| (&self.u[r.clone()], &self.y[r]))
            .collect()
    }

    /// Samples of the first experiment.
    pub(crate) fn first_len(&self) -> usize {
        self.ranges().first().map_or(0, |r| r.len())
    }

    /// The experiment holding sample `index`.
    pub fn experiment_of(&self, index: usize) -> usize {
        self.starts.iter().rposition(|&s| s <= index).unwrap_or(0)
    }

    /// A contiguous part of the samples (time kept). The experiments that start inside `r`
    /// start there too, the hold is what of it lies in `r`; sample time and units are kept.
    ///
    /// # Panics
    ///
    /// If `r` is not within the record.
    pub fn slice(&self, r: Range<usize>) -> Record {
        let starts = std::iter::once(0)
            .chain(
                self.starts
                    .iter()
                    .filter(|&&s| s > r.start && s < r.end)
                    .map(|&s| s - r.start),
            )
            .collect();
        Record {
            u: self.u[r.clone()].to_vec(),
            y: self.y[r.clone()].to_vec(),
            time: self.time[r.clone()].to_vec(),
            reference: self.reference.as_ref().map(|v| v[r.clone()].to_vec()),
            ts: self.ts,
            units: self.units.clone(),
            hold: self.hold.saturating_sub(r.start).min(r.len()),
            starts,
        }
    }

    /// The parts `ranges` of the samples joined in that order (time kept: a junction shows as
    /// a jump in time). Each non-empty part starts an experiment of the result (with those
    /// that start inside it); the hold is that of the first non-empty part.
    ///
    /// # Panics
    ///
    /// If a range is not within the record.
    pub fn joined(&self, ranges: &[Range<usize>]) -> Record {
        let mut out = Record {
            u: Vec::new(),
            y: Vec::new(),
            time: Vec::new(),
            reference: self.reference.as_ref().map(|_| Vec::new()),
            ts: self.ts,
            units: self.units.clone(),
            hold: 0,
            starts: Vec::new(),
        };
        for r in ranges.iter().filter(|r| !r.is_empty()) {
            let part = self.slice(r.clone());
            if out.starts.is_empty() {
                out.hold = part.hold;
            }
            let at = out.u.len();
            out.starts.extend(part.starts.iter().map(|s| s + at));
            out.u.extend(part.u);
            out.y.extend(part.y);
            out.time.extend(part.time);
            if let (Some(o), Some(v)) = (&mut out.reference, part.reference) {
                o.extend(v);
            }
        }
        if out.starts.is_empty() {
            out.starts.push(0);
        }
        out
    }

    /// The record of an integrating plant's stable part: in each experiment the first sample
    /// is dropped (it has no increment) and the output differenced within the experiment; the
    /// hold loses its first sample. Each increment keeps the time of the sample it ends at;
    /// [`Record::increments_source`] maps a sample back.
    pub fn increments(&self) -> Record {
        let mut out = Record {
            u: Vec::with_capacity(self.len()),
            y: Vec::with_capacity(self.len()),
            time: Vec::with_capacity(self.len()),
            reference: self.reference.as_ref().map(|_| Vec::new()),
            ts: self.ts,
            units: self.units.clone(),
            hold: self.hold.saturating_sub(1),
            starts: Vec::with_capacity(self.starts.len()),
        };
        for r in self.ranges() {
            let (u, dy) = crate::integrating::increments(&self.u[r.clone()], &self.y[r.clone()]);
            out.starts.push(out.u.len());
            out.u.extend(u);
            out.y.extend(dy);
            out.time
                .extend_from_slice(self.time[r.clone()].get(1..).unwrap_or_default());
            if let (Some(o), Some(v)) = (&mut out.reference, &self.reference) {
                o.extend_from_slice(v[r].get(1..).unwrap_or_default());
            }
        }
        out
    }

    /// The sample of this record that sample `index` of [`Record::increments`] comes from.
    pub fn increments_source(&self, index: usize) -> usize {
        // Experiment k lost k + 1 samples up to and including its own first.
        let mut start = 0;
        for (k, r) in self.ranges().into_iter().enumerate() {
            let len = r.len().saturating_sub(1);
            if index < start + len || k + 1 == self.starts.len() {
                return index + k + 1;
            }
            start += len;
        }
        index
    }

    /// The record with the mean output subtracted; the mean.
    pub(crate) fn detrended(mut self) -> (Record, f64) {
        let mean = self.y.iter().sum::<f64>() / self.y.len().max(1) as f64;
        self.y.iter_mut().for_each(|v| *v -= mean);
        (self, mean)
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    fn two_experiments() -> Record {
        let mut r = Record::new(
            vec![0.0, 1.0, 2.0, 3.0, 10.0, 11.0, 12.0],
            vec![0.0, 1.0, 3.0, 6.0, 5.0, 7.0, 4.0],
        )
        .unwrap()
        .with_hold(2);
        r.starts = vec![0, 4];
        r
    }

    #[test]
    fn increments_difference_each_experiment_apart() {
        let r = two_experiments();
        let d = r.increments();
        assert_eq!(d.u, vec![1.0, 2.0, 3.0, 11.0, 12.0]);
        assert_eq!(d.y, vec![1.0, 2.0, 3.0, 2.0, -3.0]);
        assert_eq!(d.starts, vec![0, 3]);
        assert_eq!(d.hold, 1);
        assert_eq!(d.time, vec![1.0, 2.0, 3.0, 5.0, 6.0]);
        // Each increment comes from the sample it ends at.
        let sources: Vec<usize> = (0..d.len()).map(|i| r.increments_source(i)).collect();
        assert_eq!(sources, vec![1, 2, 3, 5, 6]);
        for (i, &s) in sources.iter().enumerate() {
            assert_eq!(d.u[i], r.u[s]);
        }
    }

    #[test]
    fn slices_and_joined_parts_keep_the_time_and_cut_the_reference_like_the_input() {
        let n = 10;
        let u: Vec<f64> = (0..n).map(|t| t as f64).collect();
        let r: Vec<f64> = u.iter().map(|v| 100.0 + v).collect();
        let rec = Record::new(u, vec![0.0; n])
            .unwrap()
            .with_reference(r)
            .unwrap();
        assert_eq!(rec.time, rec.u);
        let s = rec.slice(2..5);
        assert_eq!(s.reference, Some(vec![102.0, 103.0, 104.0]));
        assert_eq!(s.time, vec![2.0, 3.0, 4.0]);
        let p = rec.joined(&[0..2, 8..10]);
        assert_eq!(p.u, vec![0.0, 1.0, 8.0, 9.0]);
        assert_eq!(p.time, vec![0.0, 1.0, 8.0, 9.0]);
        assert_eq!(p.reference, Some(vec![100.0, 101.0, 108.0, 109.0]));
        assert_eq!(p.starts, vec![0, 2]);
        let plain = Record::from_samples([(1.0, 2.0)]);
        assert_eq!(
            Some(&plain),
            Record::new(vec![1.0], vec![2.0]).ok().as_ref()
        );
        assert_eq!(plain.slice(0..1).reference, None);
        assert_eq!(plain.joined(&[0..0, 1..1]).starts, vec![0]);
    }

    #[test]
    fn slices_keep_the_experiments_and_the_hold_inside_them() {
        let r = two_experiments();
        let s = r.slice(1..6);
        assert_eq!((s.starts.clone(), s.hold), (vec![0, 3], 1));
        assert_eq!(s.time, vec![1.0, 2.0, 3.0, 4.0, 5.0]);
        let j = r.joined(&[5..7, 0..3]);
        assert_eq!((j.starts, j.hold), (vec![0, 2], 0));
        assert_eq!(j.u, vec![11.0, 12.0, 0.0, 1.0, 2.0]);
    }

    #[test]
    fn lengths_must_agree() {
        assert_eq!(
            Record::new(vec![0.0; 3], vec![0.0; 2]).err(),
            Some(RecordError::LengthMismatch { u: 3, y: 2 })
        );
        let r = Record::new(vec![0.0; 3], vec![0.0; 3]).unwrap();
        assert_eq!(
            r.with_reference(vec![0.0; 4]).err(),
            Some(RecordError::ReferenceLength { u: 3, r: 4 })
        );
    }

    #[test]
    fn detrend_removes_the_mean_output() {
        let (r, mean) = Record::new(vec![0.0; 4], vec![1.0, 2.0, 3.0, 6.0])
            .unwrap()
            .detrended();
        assert_eq!(mean, 3.0);
        assert_eq!(r.y, vec![-2.0, -1.0, 0.0, 3.0]);
        assert_eq!(r.experiment_of(3), 0);
    }
}
