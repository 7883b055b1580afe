//! An input/output record with the time of each sample, and the controller's reference when
//! the record is closed-loop and the reference was logged.

use std::ops::Range;

/// An input/output record with the time of each sample (sample index in the original file;
/// time-dependent terms are evaluated at it).
#[derive(Clone, Debug, PartialEq)]
pub struct Record {
    /// Input.
    pub u: Vec<f64>,
    /// Output.
    pub y: Vec<f64>,
    /// Time of each sample, in samples.
    pub time: Vec<f64>,
    /// The controller's reference logged with a closed-loop record, one value per sample:
    /// with it the Hammerstein part is the closed-loop consistent estimate
    /// ([`Estimator::Reference`](super::estimator::Estimator::Reference)).
    pub reference: Option<Vec<f64>>,
}

impl Record {
    /// A record whose time is the sample index `0, 1, …`.
    pub fn new(u: Vec<f64>, y: Vec<f64>) -> Self {
        let time = (0..u.len()).map(|t| t as f64).collect();
        Self {
            u,
            y,
            time,
            reference: None,
        }
    }

    /// A closed-loop record with the controller's reference `r` (one value per sample).
    pub fn with_reference(u: Vec<f64>, y: Vec<f64>, r: Vec<f64>) -> Self {
        Self {
            reference: Some(r),
            ..Self::new(u, y)
        }
    }

    /// Samples.
    pub fn len(&self) -> usize {
        self.u.len()
    }

    /// No samples.
    pub fn is_empty(&self) -> bool {
        self.u.is_empty()
    }

    /// A contiguous part (time kept).
    pub fn slice(&self, r: Range<usize>) -> Record {
        Record {
            u: self.u[r.clone()].to_vec(),
            y: self.y[r.clone()].to_vec(),
            time: self.time[r.clone()].to_vec(),
            reference: self.reference.as_ref().map(|v| v[r].to_vec()),
        }
    }

    /// Concatenation of parts of this record (time kept: a junction shows as a jump in time).
    pub fn parts(&self, ranges: &[Range<usize>]) -> Record {
        let mut out = Record {
            u: Vec::new(),
            y: Vec::new(),
            time: Vec::new(),
            reference: self.reference.as_ref().map(|_| Vec::new()),
        };
        for r in ranges {
            out.u.extend_from_slice(&self.u[r.clone()]);
            out.y.extend_from_slice(&self.y[r.clone()]);
            out.time.extend_from_slice(&self.time[r.clone()]);
            if let (Some(o), Some(v)) = (&mut out.reference, &self.reference) {
                o.extend_from_slice(&v[r.clone()]);
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slices_and_parts_cut_the_reference_like_the_input() {
        let n = 10;
        let u: Vec<f64> = (0..n).map(|t| t as f64).collect();
        let r: Vec<f64> = u.iter().map(|v| 100.0 + v).collect();
        let rec = Record::with_reference(u, vec![0.0; n], r);
        let s = rec.slice(2..5);
        assert_eq!(s.reference, Some(vec![102.0, 103.0, 104.0]));
        let p = rec.parts(&[0..2, 8..10]);
        assert_eq!(p.u, vec![0.0, 1.0, 8.0, 9.0]);
        assert_eq!(p.reference, Some(vec![100.0, 101.0, 108.0, 109.0]));
        assert_eq!(
            Record::new(vec![1.0], vec![2.0]).slice(0..1).reference,
            None
        );
    }
}
