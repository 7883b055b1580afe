//! `hsid.regressor`: the data the subspace step sees, `z(t)` and `ȳ(t) = y(t) − μ0` after the
//! hold, for a peer implementation to identify from. Built by the core's own pieces, sample by
//! sample as `Identifier::push` builds them: the direction `δ(t)`, the knot segment, the hat
//! channels and the compensated mean of the settled hold.

use hsid::regressor::for_each_nonzero;
use hsid::{Basis, Direction, Error, HoldMean, Knots};
use hsid_host::identify::{IdentifyOptions, MAX_CHANNELS};
use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::prelude::*;

use crate::arrays::out;
use crate::error::{Class, Failure};
use crate::identify::record;
use crate::settings::{self, SegmentArg};

/// The regressor of a record: `z` row-major (`rows × channels`) and `ȳ`.
#[derive(Clone, Debug, PartialEq)]
pub struct Zy {
    /// Regressor channels `m` (`n_a + n_d`, `n` for a static element).
    pub channels: usize,
    /// `z(t)` for every sample after the hold, one row per sample.
    pub z: Vec<f64>,
    /// `ȳ(t) = y(t) − μ0` for every sample after the hold.
    pub ybar: Vec<f64>,
}

/// The regressor of `(u, y)` under `opts` (hat basis), exactly as the core accumulates it.
/// Without a hold, μ0 is the first output after it, the core's provisional offset.
pub fn zy(u: &[f64], y: &[f64], opts: &IdentifyOptions) -> Result<Zy, Error> {
    let knots = if opts.static_nonlinearity {
        Knots::<f64, MAX_CHANNELS>::shared(&opts.knots_asc)?
    } else {
        Knots::<f64, MAX_CHANNELS>::new(&opts.knots_asc, &opts.knots_desc)?
    };
    let (hold, settle) = (opts.hold, opts.settle);
    if hold > 0 && settle >= hold {
        return Err(Error::HoldTooShort { len: hold, settle });
    }
    let m = knots.channels();
    let rows = u.len().saturating_sub(hold);
    let (mut z, mut ybar) = (vec![0.0; rows * m], Vec::with_capacity(rows));
    let (mut mean, mut mu0) = (HoldMean::ZERO, None);
    let (mut dir, mut prev) = (Direction::Descending, knots.u_min());
    for (index, (&ut, &yt)) in u.iter().zip(y).enumerate() {
        if ut < knots.u_min() || ut > knots.u_max() {
            let index = index as u64;
            return Err(Error::InputOutOfRange { index, value: ut });
        }
        if index < hold {
            if ut != knots.u_min() {
                let index = index as u64;
                return Err(Error::HoldNotAtMin { index, value: ut });
            }
            if index >= settle {
                mean.push(yt);
            }
            prev = ut;
            continue;
        }
        let mu0 = *mu0.get_or_insert_with(|| match hold {
            0 => yt,
            _ => mean.mean().unwrap_or_default(),
        });
        dir = dir.next(prev, ut);
        prev = ut;
        let row = (index - hold) * m;
        for_each_nonzero(&knots, Basis::Hat, &knots.locate(dir, ut), |c, v| {
            if let Some(slot) = z.get_mut(row + c) {
                *slot = v;
            }
        });
        ybar.push(yt - mu0);
    }
    Ok(Zy {
        channels: m,
        z,
        ybar,
    })
}

/// `(z, ybar)` as numpy arrays.
type Arrays<'py> = (Bound<'py, PyArray2<f64>>, Bound<'py, PyArray1<f64>>);

/// The data the subspace identification works on: `(z, ybar)`, numpy arrays of shape
/// `(N − hold, channels)` and `(N − hold,)`. `z(t)` holds the hat-basis regressor channels
/// (ascending path's `n_a` first, then the descending path's `n_d`; `n` channels shared by
/// both directions for `nonlinearity="static"`), `ybar(t) = y(t) − μ0` with μ0 the mean of the
/// settled second half of the hold. These are the values `hsid.identify` accumulates with the
/// same settings, bit for bit; a peer subspace method run on them (inputs `z`, output `ybar`)
/// identifies the same linear part. Without a hold (`hold=0`) `ybar` is `y − y[0]`, and the
/// identification also centres every Hankel row. Bad arrays, settings or samples raise
/// `DataError` or `SettingsError`, as `hsid.identify` does.
#[pyfunction]
#[pyo3(signature = (u, y, umin, umax, *, segments=None, knots=None, nonlinearity="backlash",
    hold=300))]
#[allow(clippy::too_many_arguments)]
pub fn regressor<'py>(
    py: Python<'py>,
    u: &Bound<'py, PyAny>,
    y: &Bound<'py, PyAny>,
    umin: f64,
    umax: f64,
    segments: Option<&Bound<'py, PyAny>>,
    knots: Option<&Bound<'py, PyAny>>,
    nonlinearity: &str,
    hold: usize,
) -> PyResult<Arrays<'py>> {
    let (u, y) = record(u, y, hold)?;
    let segments = match settings::segments(segments)? {
        Some(SegmentArg::Auto) => {
            return Err(Failure::new(
                Class::Settings,
                "segments",
                "segments=\"auto\": the regressor needs fixed knots; give a count or knots",
            )
            .into());
        }
        s => s.or(Some(SegmentArg::Fixed(7))),
    };
    let s = settings::settings(
        umin,
        umax,
        segments,
        settings::knots(knots)?,
        settings::nonlinearity(nonlinearity)?,
        None,
        None,
        hold,
        false,
    )?;
    let Zy { channels, z, ybar } = py.detach(|| zy(&u, &y, &s)).map_err(Failure::from)?;
    let z = out(py, z).reshape([ybar.len(), channels])?;
    Ok((z, out(py, ybar)))
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use hsid_host::refine::signal::HatRegressors;

    fn record() -> (Vec<f64>, Vec<f64>) {
        let mut u = vec![-1.0; 40];
        u.extend((0..200).map(|t| (0.05 * t as f64).sin() * 0.7 + 0.05 * (t % 5) as f64 - 0.1));
        let y = (0..u.len()).map(|t| 0.5 + (0.3 * t as f64).cos()).collect();
        (u, y)
    }

    #[test]
    fn equals_the_hat_regressors_of_the_refinement() {
        let (u, y) = record();
        let mut opts = IdentifyOptions::uniform(-1.0, 1.0, 5, 40);
        opts.knots_desc = vec![-1.0, -0.3, 0.4, 1.0];
        let got = zy(&u, &y, &opts).unwrap();
        let dense = HatRegressors::new(&u, &opts.knots_asc, &opts.knots_desc)
            .unwrap()
            .dense();
        assert_eq!(got.channels, 5 + 3);
        assert_eq!(got.ybar.len(), u.len() - 40);
        for (c, col) in dense[1..].iter().enumerate() {
            for (row, want) in col[40..].iter().enumerate() {
                let at = row * got.channels + c;
                assert_eq!(got.z[at], *want, "channel {c}, row {row}");
            }
        }
        let mu0 = y[20..40].iter().sum::<f64>() / 20.0;
        assert!((got.ybar[0] - (y[40] - mu0)).abs() < 1e-15);
    }

    #[test]
    fn bad_samples_are_named_by_index() {
        let (mut u, y) = record();
        let opts = IdentifyOptions::uniform(-1.0, 1.0, 5, 40);
        u[7] = 0.0;
        assert_eq!(
            zy(&u, &y, &opts),
            Err(Error::HoldNotAtMin {
                index: 7,
                value: 0.0
            })
        );
        u[7] = -1.0;
        u[100] = 1.5;
        assert_eq!(
            zy(&u, &y, &opts),
            Err(Error::InputOutOfRange {
                index: 100,
                value: 1.5
            })
        );
    }
}
