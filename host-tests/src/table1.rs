//! The Table I structure of an input record, counted once for `diagnose` and `identify`: under
//! the paper's excitation every monotone run starts at `u_min` (ascending) or `u_max`
//! (descending), so a backlash travels its paths `P_a`/`P_d`; a run that starts inside the
//! range puts the element on an inner loop, which no pair of paths describes.

/// The monotone runs of an input and how many of them start inside the range.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Runs {
    /// Monotone runs (a change of direction starts a new one; held samples do not).
    pub runs: usize,
    /// Runs that start neither at `u_min` (ascending) nor at `u_max` (descending).
    pub inside: usize,
}

impl Runs {
    /// The runs in words: how many of them start inside `[umin, umax]`, against the Table I
    /// excitation that starts each at an end (why the element's fit is wanted).
    pub fn described(&self, umin: f64, umax: f64) -> String {
        format!(
            "{} of {} monotone input runs start inside [{umin}, {umax}] (the Table I excitation \
             starts each at u_min or u_max)",
            self.inside, self.runs
        )
    }
}

/// Counts the monotone runs of `u` and those that start inside `[u_min, u_max]`; `tol` is the
/// distance within which a sample is "at" an end. Give the record from the last sample of the
/// hold on (the whole record without a hold), so that the first run's start is a sample.
pub fn count_runs(u: &[f64], u_min: f64, u_max: f64, tol: f64) -> Runs {
    let mut c = RunCounter::new(u_min, u_max, tol);
    u.iter().for_each(|&v| c.push(v));
    c.runs()
}

/// [`count_runs`] one sample at a time, for a record read as a stream.
#[derive(Debug, Clone, Copy)]
pub struct RunCounter {
    ends: (f64, f64),
    tol: f64,
    last: Option<f64>,
    dir: i8,
    runs: Runs,
}

impl RunCounter {
    /// A counter for the interval `[u_min, u_max]` with the tolerance `tol` of "at an end".
    pub fn new(u_min: f64, u_max: f64, tol: f64) -> Self {
        Self {
            ends: (u_min, u_max),
            tol,
            last: None,
            dir: 0,
            runs: Runs::default(),
        }
    }

    /// Takes the next sample.
    pub fn push(&mut self, u: f64) {
        if let Some(prev) = self.last.replace(u) {
            let d = match u.partial_cmp(&prev) {
                Some(std::cmp::Ordering::Greater) => 1,
                Some(std::cmp::Ordering::Less) => -1,
                _ => 0,
            };
            if d != 0 && d != self.dir {
                self.runs.runs += 1;
                let end = if d > 0 { self.ends.0 } else { self.ends.1 };
                if (prev - end).abs() > self.tol {
                    self.runs.inside += 1;
                }
                self.dir = d;
            }
        }
    }

    /// The counts so far.
    pub fn runs(&self) -> Runs {
        self.runs
    }
}

/// The tolerance of "at an end" for the interval `[u_min, u_max]`: 10⁻⁹ of its width (the
/// Table I excitation sits exactly on its ends; this absorbs rounding in a CSV round trip).
pub fn end_tolerance(u_min: f64, u_max: f64) -> f64 {
    1e-9 * (u_max - u_min).abs().max(1e-300)
}

impl Runs {
    /// Whether the input breaks the Table I structure enough to fit the element itself rather
    /// than trust the two-path model: more than one run, and more than
    /// [`MAX_INSIDE_FRACTION`] of the runs, start inside the range. The Table I excitation has
    /// none. One comes from a record that opens inside the range (no hold, or a record cut
    /// after it) and costs only the first run, so it never decides alone. An input that
    /// reverses inside the range on more than a tenth of its runs keeps a backlash on inner
    /// loops for a share of the record the two-path model cannot absorb as noise; an
    /// ordinary command (the smoothed random servo input of docs/hysteresis.md) reverses
    /// inside on nearly every run, far above the threshold, so the rule does not hinge on
    /// its exact value.
    pub fn breaks_table1(&self) -> bool {
        self.inside > 1 && self.inside as f64 > MAX_INSIDE_FRACTION * self.runs as f64
    }
}

/// The share of runs starting inside the range above which [`Runs::breaks_table1`] holds.
pub const MAX_INSIDE_FRACTION: f64 = 0.1;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn runs_that_start_inside_are_counted_and_the_rule_needs_more_than_one() {
        // Up from u_min to 0.5, down from 0.5 (inside), up from 0.2 (inside).
        let r = count_runs(&[-1.0, 0.5, 0.2, 0.8, 1.0], -1.0, 1.0, 1e-9);
        assert_eq!(r, Runs { runs: 3, inside: 2 });
        assert!(r.breaks_table1());
        // Held samples do not start a run; a sweep with one opening inside passes.
        let r = count_runs(&[0.3, 1.0, 1.0, -1.0, -1.0, 1.0], -1.0, 1.0, 1e-9);
        assert_eq!(r, Runs { runs: 3, inside: 1 });
        assert!(!r.breaks_table1());
        // Two inside of 30 runs is under a tenth.
        let many = Runs {
            runs: 30,
            inside: 2,
        };
        assert!(!many.breaks_table1());
        assert!(
            Runs {
                runs: 30,
                inside: 4
            }
            .breaks_table1()
        );
    }
}
