//! Dead time of the data, independent of the model's fit: an ARX model of the output on the
//! hat-basis regressor channels with lags `0…L`, and a sequence of likelihood-ratio tests of
//! "no response at lags `0…j`" for `j = 0, 1, …`. The dead time is the first `j` whose lag
//! is needed (the joint test rejects at the 1 % level).
//!
//! The test does not depend on the simulation error, which on measured data is dominated by
//! whatever else the model lacks: a delay shows in the few samples after every input step,
//! and the ARX regression sees exactly those samples. Autocorrelated ARX errors make the tests
//! reject too often, which shortens the dead time found: the test errs towards *no* extra
//! delay.

use nalgebra::DVector;
use serde::Serialize;

use crate::identify::HostModel;
use crate::numerics::select::{Criterion, best};
use crate::validation::arx::{Column, continuous_rows, rss};
use crate::validation::residual::LEVEL;
use crate::validation::stats::chi2_sf;

/// The dead time found in the data.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct DeadTime {
    /// First lag (samples) at which the output responds to the input, or `None` when no lag up
    /// to the largest tested is significant.
    pub lag: Option<usize>,
    /// p-values of "no response at lags `0…j`", `j = 0…L`.
    pub p_values: Vec<f64>,
    /// Output lags of the ARX model (by BIC).
    pub ar_order: usize,
    /// First lag of the model's own impulse response (`D ≠ 0`: 0).
    pub model_lag: usize,
}

impl DeadTime {
    /// The extra delay the data show beyond the model's own dead time.
    pub fn extra(&self) -> usize {
        self.lag.map_or(0, |l| l.saturating_sub(self.model_lag))
    }
}

/// The dead-time test's finding, in words.
impl std::fmt::Display for DeadTime {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let d = self;
        match d.lag {
            Some(l) => write!(
                f,
                "dead_time: the output first responds to the input at lag {l} (ARX({}) likelihood-ratio tests of no response at lags 0…j: p = {} for j = 0…{l}), the model at lag {}: {} extra samples",
                d.ar_order,
                d.p_values
                    .iter()
                    .take(l + 1)
                    .map(|p| format!("{p:.2e}"))
                    .collect::<Vec<_>>()
                    .join(", "),
                d.model_lag,
                d.extra()
            ),
            None => f.write_str("dead_time: no lag tested is significant"),
        }
    }
}

impl HostModel {
    /// The first lag of the model's impulse response above 1 % of its largest (`D`, `CB`, `CAB`,
    /// …).
    pub fn dead_time(&self, max_lag: usize) -> usize {
        let n = self.order;
        let mut h = vec![self.d];
        let mut x = DVector::from_column_slice(&self.b);
        for _ in 0..max_lag.max(1) + 20 {
            h.push(self.c.iter().zip(x.iter()).map(|(c, v)| c * v).sum());
            if n > 0 {
                x = &self.a * x;
            }
        }
        let top = h.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        h.iter().position(|v| v.abs() >= 0.01 * top).unwrap_or(0)
    }
}

/// The dead time of `y` after the regressor channels `z` (hat basis of the input), lags
/// `0…max_lag` tested. `time` is the time of each sample: rows whose lags reach across a gap
/// (a record joined from parts) are left out. `model_lag` is recorded for [`DeadTime::extra`].
pub fn dead_time(
    z: &[Vec<f64>],
    y: &[f64],
    time: &[f64],
    max_lag: usize,
    model_lag: usize,
) -> DeadTime {
    let span = max_lag + 1;
    let zl: Vec<Vec<Column>> = (0..=span)
        .map(|j| z.iter().map(|c| Column::Lagged(c, j)).collect())
        .collect();
    let yl: Vec<Column> = (1..=6).map(|i| Column::Lagged(y, i)).collect();
    let start = span.max(6);
    let rows = continuous_rows(time, start);
    let n = rows.len() as f64;
    let cols_for = |na: usize, first: usize| -> Vec<Column> {
        let mut c = vec![Column::Constant(1.0)];
        c.extend_from_slice(&yl[..na]);
        for lag in zl.iter().skip(first) {
            c.extend_from_slice(lag);
        }
        c
    };
    // ARX output order by BIC (1…6), with every input lag.
    let scores: Vec<((usize, f64), f64)> = (1..=6)
        .filter_map(|na| {
            let cols = cols_for(na, 0);
            let r = rss(&cols, y, &rows)?;
            Some(((na, r), Criterion::Bic.score(n, r / n, cols.len() as f64)))
        })
        .collect();
    let Some((na, full)) = best(&scores) else {
        return DeadTime {
            lag: None,
            p_values: Vec::new(),
            ar_order: 0,
            model_lag,
        };
    };
    let mut p_values = Vec::new();
    let mut lag = None;
    for j in 0..=max_lag {
        let q = ((j + 1) * z.len()) as f64;
        let p = match rss(&cols_for(na, j + 1), y, &rows) {
            Some(r) if full > 0.0 => chi2_sf(n * (r / full).max(1.0).ln(), q),
            _ => 1.0,
        };
        p_values.push(p);
        if lag.is_none() && p < LEVEL {
            lag = Some(j);
        }
    }
    DeadTime {
        lag,
        p_values,
        ar_order: na,
        model_lag,
    }
}
