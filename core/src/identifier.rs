//! The streaming front end: the hold, δ(t), z(t) and the accumulation sample by sample, then
//! the final solve.

use crate::accumulation::{Accumulator, Plain, Summation, checked_forgetting};
use crate::direction::Direction;
use crate::error::{Error, ShiftBreak, Signal};
use crate::estimation::{BfSource, Mu0, Outcome, Poles, estimate, estimate_from};
use crate::hold::{HoldMean, MuZero};
use crate::model::{DEFAULT_HORIZON, Model};
use crate::regressor::{Basis, Knots};
use crate::scalar::Real;
use crate::subspace::{
    Layout, Method, Order, Projection, Slots, pi_moesp, pi_moesp_structured, select_order,
    structured_len,
};

/// Identification settings (validated by [`Identifier::new`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Settings<T, const M: usize> {
    /// Knots of both paths; they also define `[u_min, u_max]`.
    pub knots: Knots<T, M>,
    /// Basis of the border expansion ([`Basis::Hat`] by default; same model either way).
    pub basis: Basis,
    /// Future horizon `f` (block rows of `Z_f`, `Ȳ_f`).
    pub f: usize,
    /// Past horizon `p` (block rows of `Z_p`).
    pub p: usize,
    /// Where μ0 comes from.
    pub mu0: MuZero<T>,
    /// Model order selection.
    pub order: Order,
    /// Subspace weighting (PI-MOESP, the paper's, by default).
    pub method: Method,
    /// Memory of the accumulation: all samples alike, or exponential forgetting for
    /// long-running devices that must track a slowly changing actuator.
    pub forgetting: Forgetting<T>,
}

/// How the accumulation weighs old samples.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Forgetting<T> {
    /// Every sample counts the same (the paper's setting).
    #[default]
    None,
    /// Hankel column `c` of `j` weighs `λ^{j−1−c}` (`0 < λ < 1`): the model follows the last
    /// `≈ 1/(1−λ)` samples. The weighted Grams are exact, like the unweighted ones.
    Exponential {
        /// The forgetting factor λ.
        lambda: T,
    },
}

impl<T: Real, const M: usize> Settings<T, M> {
    /// Settings with horizons `f` and `p`, the hat basis and automatic order.
    pub fn new(knots: Knots<T, M>, f: usize, p: usize, mu0: MuZero<T>) -> Self {
        Self {
            knots,
            basis: Basis::Hat,
            f,
            p,
            mu0,
            order: Order::Auto,
            method: Method::PiMoesp,
            forgetting: Forgetting::None,
        }
    }
}

/// Streaming identifier for up to `M` regressor channels (segments of both paths), up to `K`
/// block rows (`f + p`) and a future horizon up to `H`. Memory (and the solve's stack) is
/// fixed by `M`, `K` and `H`, whatever the number of samples: firmware sets them to the exact
/// sizes, a desktop tool to the largest it accepts.
///
/// [`push`](Self::push) never fails: a bad sample (NaN, outside the interval, a hold sample
/// not at `u_min`) is recorded as the first fault and the identifier stops accumulating;
/// [`fault`](Self::fault) reports it at once and [`solve`](Self::solve) returns it.
///
/// `S` chooses how the sums are formed: [`Plain`] (the default) or
/// [`Compensated`](crate::Compensated), which keeps `f32` models accurate over records of 10^6
/// samples for a carry per output sum and more work per sample (see [`Summation`]).
///
/// `H` is the horizon capacity: the largest future horizon `f` (so model order + 1) the
/// final solve handles, on `H × H` matrices of its stack. It comes last and defaults to
/// [`DEFAULT_HORIZON`] (12), so that the common spellings `Identifier<f32, M, K>` and
/// `Identifier<f32, M, K, Compensated>` read as before; firmware that knows its `f` names it
/// (`Identifier<f32, 14, 20, Plain, 10>` for the paper's `f = p = 10`) and saves stack, a
/// desktop tool names the largest `f` it accepts. The model is the same, bit for bit, for
/// every `H >= f`.
#[derive(Clone, Debug)]
pub struct Identifier<
    T: Real,
    const M: usize,
    const K: usize,
    S: Summation<T, M, K> = Plain,
    const H: usize = DEFAULT_HORIZON,
> {
    pub(crate) settings: Settings<T, M>,
    pub(crate) acc: Accumulator<T, M, K>,
    /// The carries of the sums (nothing for plain sums).
    pub(crate) carry: S::Carry,
    pub(crate) hold: HoldMean<T>,
    pub(crate) mu0: Option<T>,
    pub(crate) u_prev: T,
    pub(crate) dir: Direction,
    pub(crate) index: u64,
    pub(crate) fault: Option<Error>,
}

impl<T: Real, const M: usize, const K: usize, S: Summation<T, M, K>, const H: usize>
    Identifier<T, M, K, S, H>
{
    /// An unconfigured identifier, usable in constant expressions so that firmware can place
    /// it in a `static` (no copy through the stack); configure it with
    /// [`reset`](Self::reset). It refuses samples until then (every `push` records a fault).
    pub const EMPTY: Self = Self {
        settings: Settings {
            knots: Knots::EMPTY,
            basis: Basis::Hat,
            f: 0,
            p: 0,
            mu0: MuZero::Known(T::ZERO),
            order: Order::Auto,
            method: Method::PiMoesp,
            forgetting: Forgetting::None,
        },
        acc: Accumulator::EMPTY,
        carry: S::ZERO,
        hold: HoldMean::ZERO,
        mu0: None,
        u_prev: T::ZERO,
        dir: Direction::Descending,
        index: 0,
        fault: Some(Error::Unconfigured),
    };

    /// Validates the settings against the capacities `(M, K, H)`.
    pub fn new(settings: Settings<T, M>) -> Result<Self, Error> {
        let mut id = Self::EMPTY;
        id.reset(settings)?;
        Ok(id)
    }

    /// Validates the settings and starts a new identification in place: all accumulated
    /// statistics are cleared. On error the identifier is left unchanged.
    pub fn reset(&mut self, settings: Settings<T, M>) -> Result<(), Error> {
        let (f, p) = (settings.f, settings.p);
        let k = f.saturating_add(p);
        if f < 2 || p == 0 || f > H || k > K {
            return Err(Error::InvalidHorizon {
                f,
                k,
                max_f: H,
                max_k: K,
            });
        }
        if let Order::Fixed(n) = settings.order
            && (n == 0 || n >= f)
        {
            return Err(Error::InvalidOrder { order: n, f });
        }
        if settings.knots.channels() == 0 {
            return Err(Error::TooFewKnots {
                path: Direction::Ascending,
                count: 0,
            });
        }
        let channels = settings.knots.channels();
        // The instruments' rows as the solve lays them out (`p·m`, `+ p` with past outputs).
        if Layout::for_method(channels, f, p, 1, settings.method).w() < f {
            return Err(Error::TooFewInstruments {
                f,
                p,
                channels,
                past_outputs: settings.method.past_outputs(),
            });
        }
        settings.mu0.validate()?;
        // Validated before anything is reset, so an error leaves the identifier unchanged.
        let lambda = checked_forgetting(match settings.forgetting {
            Forgetting::None => T::one(),
            Forgetting::Exponential { lambda } => lambda,
        })?;
        self.acc.reset(k)?;
        self.acc.set_forgetting(lambda)?;
        self.carry = S::ZERO;
        self.mu0 = match settings.mu0 {
            MuZero::Known(v) => Some(v),
            MuZero::Hold { .. } | MuZero::Estimate => None,
        };
        self.u_prev = settings.knots.u_min();
        self.settings = settings;
        self.hold = HoldMean::ZERO;
        self.dir = Direction::Descending;
        self.index = 0;
        self.fault = None;
        Ok(())
    }

    /// The settings.
    pub fn settings(&self) -> &Settings<T, M> {
        &self.settings
    }

    /// Adds one sample `(u(t), y(t))`. Infallible; see the type's docs for bad samples.
    pub fn push(&mut self, u: T, y: T) {
        let index = self.index;
        // Saturating: 2^64 samples are out of reach, but a restored state must not be able
        // to make the per-sample path overflow.
        self.index = self.index.saturating_add(1);
        if self.fault.is_some() {
            return;
        }
        let knots = &self.settings.knots;
        let fault = if !u.finite() {
            Some(Error::NonFinite {
                index,
                signal: Signal::Input,
            })
        } else if !y.finite() {
            Some(Error::NonFinite {
                index,
                signal: Signal::Output,
            })
        } else if u < knots.u_min() || u > knots.u_max() {
            Some(Error::InputOutOfRange {
                index,
                value: u.to_f64(),
            })
        } else {
            None
        };
        if fault.is_some() {
            self.fault = fault;
            return;
        }
        if let MuZero::Hold { len, settle } = self.settings.mu0
            && index < len as u64
        {
            if u != knots.u_min() {
                self.fault = Some(Error::HoldNotAtMin {
                    index,
                    value: u.to_f64(),
                });
            } else if index >= settle as u64 {
                self.hold.push(y);
            }
            self.u_prev = u;
            return;
        }
        let mu0 = match self.mu0 {
            Some(m) => m,
            None => {
                // After a hold: its settled mean. Without one (MuZero::Estimate): the first
                // output, a provisional offset that keeps ȳ small; the rows are centred anyway.
                let m = match self.settings.mu0 {
                    MuZero::Hold { .. } => self.hold.mean().unwrap_or_default(),
                    _ => y,
                };
                self.mu0 = Some(m);
                m
            }
        };
        self.dir = self.dir.next(self.u_prev, u);
        self.u_prev = u;
        let at = knots.locate(self.dir, u);
        let (knots, basis) = (&self.settings.knots, self.settings.basis);
        match S::carries_mut(&mut self.carry) {
            Some(c) => self.acc.push_compensated(c, knots, basis, at, y - mu0),
            None => self.acc.push(knots, basis, at, y - mu0),
        }
    }

    /// The first bad sample seen, if any.
    pub fn fault(&self) -> Option<Error> {
        self.fault
    }

    /// μ0, once the hold is over (or given).
    pub fn mu0(&self) -> Option<T> {
        self.mu0
    }

    /// Samples pushed in all (hold included).
    pub fn samples(&self) -> u64 {
        self.index
    }

    /// The accumulated statistics.
    pub fn accumulator(&self) -> &Accumulator<T, M, K> {
        &self.acc
    }

    /// Samples after the hold needed before [`solve`](Self::solve) can succeed: the Gram of
    /// `[Z_f; Z_p; Ȳ_f]` needs more Hankel columns than rows.
    pub fn min_samples(&self) -> u64 {
        let lay = self.layout();
        (lay.f + lay.p) as u64 + (lay.d() + lay.py() + lay.f) as u64
    }

    fn layout(&self) -> Layout {
        Layout::for_method(
            self.settings.knots.channels(),
            self.settings.f,
            self.settings.p,
            crate::subspace::SCHUR_BLOCK,
            self.settings.method,
        )
    }

    /// Scalars of workspace for [`solve`](Self::solve) with the default block width
    /// ([`workspace_len`](crate::workspace_len)); the solve accepts less (slower, down to
    /// [`min_workspace_len`](Self::min_workspace_len)) or more (faster).
    pub fn workspace_len(&self) -> usize {
        self.layout().total()
    }

    /// The smallest workspace [`solve`](Self::solve) accepts.
    pub fn min_workspace_len(&self) -> usize {
        Layout::for_method(
            self.settings.knots.channels(),
            self.settings.f,
            self.settings.p,
            1,
            self.settings.method,
        )
        .total()
    }

    /// The final solve: PI-MOESP, order, `A`/`C`, `B`/`D`, rank-1 split and γ. The
    /// accumulated statistics are left untouched, so more samples can follow and the solve
    /// can be repeated. `ws` is caller-owned scratch of at least
    /// [`workspace_len`](Self::workspace_len) scalars. An identified `A` with a pole on or
    /// outside the unit circle is [`Error::UnstableModel`] (the paper's `G` is stable); see
    /// [`solve_with`](Self::solve_with) for a caller that refines the poles afterwards.
    pub fn solve(&self, ws: &mut [T]) -> Result<Model<T, M, H>, Error> {
        self.solve_with(ws, Poles::Stable)
    }

    /// [`solve`](Self::solve) with a choice of what to do with an unstable `A`: on short or
    /// noisy records of a slow plant the subspace estimate of a pole near 1 can land just
    /// outside the unit circle; a caller that refines the model afterwards (on the
    /// simulation error, say) takes it with [`Poles::Any`] and checks stability itself.
    /// `G(1) = 1` still needs `I − A` invertible: a pole at 1 is [`Error::IntegratingModel`].
    pub fn solve_with(&self, ws: &mut [T], poles: Poles) -> Result<Model<T, M, H>, Error> {
        if let Some(e) = self.fault {
            return Err(e);
        }
        let min = Layout::for_method(
            self.settings.knots.channels(),
            self.settings.f,
            self.settings.p,
            1,
            self.settings.method,
        );
        let lay = self
            .layout()
            .fitting(ws.len())
            .ok_or(Error::WorkspaceTooSmall {
                need: min.total(),
                have: ws.len(),
            })?;
        self.ready()?;
        let mu0 = self.model_mu0();
        let centred = matches!(self.settings.mu0, MuZero::Estimate);
        let (knots, basis) = (&self.settings.knots, self.settings.basis);
        let proj = pi_moesp::<T, M, K, H>(
            &self.acc,
            knots,
            basis,
            lay,
            centred,
            S::OUTPUT_ROUNDING,
            ws,
        )?;
        let n = select_order(self.settings.order, &proj, lay)?;
        estimate::<T, M, K, H>(&proj, n, lay, ws, knots, basis, mu0, poles)
    }

    /// Scalars of workspace for [`solve_structured`](Self::solve_structured)
    /// ([`structured_workspace_len`](crate::structured_workspace_len)).
    pub fn structured_workspace_len(&self) -> usize {
        structured_len(self.layout())
    }

    /// The final solve in less memory: the same model as [`solve`](Self::solve) (within the
    /// scalar's rounding), with PI-MOESP's projection from the generalised Schur algorithm on
    /// the Gram's displacement generator, so that neither the Gram nor its Cholesky factor is
    /// stored. `ws` needs [`structured_workspace_len`](Self::structured_workspace_len)
    /// scalars: 9,983 for the paper's configuration (14 channels, `f = p = 10`) against the
    /// dense solve's 33,041. It needs the Gram's rows to be lags of one sequence with equal
    /// weights: μ0 from a hold or given (not estimated), no forgetting, PI-MOESP
    /// ([`Error::NotShiftStructured`] otherwise).
    ///
    /// ```
    /// use hsid::{Excitation, Identifier, Knots, MuZero, Order, Settings, structured_workspace_len};
    /// use rand_core::SeedableRng;
    ///
    /// // The paper's configuration: 7 segments per path, f = p = 10, μ0 from a hold.
    /// let knots = Knots::<f32, 14>::uniform(-3.0, 3.0, 7, 7).unwrap();
    /// let mut settings = Settings::new(knots, 10, 10, MuZero::Hold { len: 300, settle: 150 });
    /// settings.order = Order::Fixed(2);
    /// let mut id = Identifier::<f32, 14, 20>::new(settings).unwrap();
    /// // A backlash of gap 0.4 in front of the paper's G(q).
    /// let rng = rand_pcg::Pcg32::seed_from_u64(1);
    /// let (mut w, mut w1, mut w2, mut y1, mut y2) = (-3.0f32, 0.0, 0.0, 0.0, 0.0);
    /// for u in Excitation::new(-3.0, 3.0, 300, rng).unwrap().take(4319) {
    ///     w = w.clamp(u - 0.2, u + 0.2);
    ///     let y = 1.8858 * y1 - 0.9048 * y2 + 0.1994 * w1 - 0.1804 * w2;
    ///     (w2, w1, y2, y1) = (w1, w, y1, y);
    ///     id.push(u, y);
    /// }
    /// let mut ws = vec![0.0f32; structured_workspace_len(14, 10, 10)]; // 40 KB
    /// let model = id.solve_structured(&mut ws).unwrap();
    /// let mut dense_ws = vec![0.0f32; id.workspace_len()]; // 132 KB
    /// let dense = id.solve(&mut dense_ws).unwrap();
    /// // The same poles: trace and determinant of A (0.9429 ± 0.1255 j: 1.8858, 0.9048).
    /// let tr_det = |m: &hsid::Model<f32, 14>| {
    ///     let a = |i, j| m.a(i, j);
    ///     (a(0, 0) + a(1, 1), a(0, 0) * a(1, 1) - a(0, 1) * a(1, 0))
    /// };
    /// let ((t, d), (t_ref, d_ref)) = (tr_det(&model), tr_det(&dense));
    /// assert!((t - t_ref).abs() < 1e-4 && (d - d_ref).abs() < 1e-4);
    /// assert!((t - 1.8858).abs() < 5e-3 && (d - 0.9048).abs() < 5e-3, "{t} {d}");
    /// ```
    pub fn solve_structured(&self, ws: &mut [T]) -> Result<Model<T, M, H>, Error> {
        self.solve_structured_with(ws, Poles::Stable)
    }

    /// [`solve_structured`](Self::solve_structured) with a choice of what to do with an
    /// unstable `A` (see [`solve_with`](Self::solve_with)).
    pub fn solve_structured_with(
        &self,
        ws: &mut [T],
        poles: Poles,
    ) -> Result<Model<T, M, H>, Error> {
        if let Some(e) = self.fault {
            return Err(e);
        }
        let cause = if matches!(self.settings.mu0, MuZero::Estimate) {
            Some(ShiftBreak::Centred)
        } else if self.acc.forgetting() != T::one() {
            Some(ShiftBreak::Forgetting)
        } else if self.settings.method != Method::PiMoesp {
            Some(ShiftBreak::PastOutputs)
        } else {
            None
        };
        if let Some(cause) = cause {
            return Err(Error::NotShiftStructured { cause });
        }
        let lay = self.layout();
        let need = structured_len(lay);
        if ws.len() < need {
            return Err(Error::WorkspaceTooSmall {
                need,
                have: ws.len(),
            });
        }
        self.ready()?;
        let (knots, basis) = (&self.settings.knots, self.settings.basis);
        let mut proj = Projection::empty();
        pi_moesp_structured::<T, M, K, H>(
            &self.acc,
            knots,
            basis,
            lay,
            S::OUTPUT_ROUNDING,
            ws,
            &mut proj,
        )?;
        let n = select_order(self.settings.order, &proj, lay)?;
        let sl = Slots::of(lay);
        let err = Error::WorkspaceTooSmall {
            need,
            have: ws.len(),
        };
        let (bf, scratch) = ws.split_at_mut_checked(sl.fm * sl.stride).ok_or(err)?;
        let out = Outcome {
            knots,
            basis,
            mu0: self.model_mu0(),
            poles,
        };
        estimate_from::<T, M, K, H>(&proj, n, lay, BfSource::Slots(bf, sl), scratch, err, out)
    }

    /// Whether the statistics can be solved: enough samples, and every regressor channel
    /// excited.
    fn ready(&self) -> Result<(), Error> {
        let have = self.acc.count();
        let need_samples = self.min_samples();
        if have < need_samples {
            return Err(Error::TooFewSamples {
                have,
                need: need_samples,
            });
        }
        let knots = &self.settings.knots;
        if let Some(lag0) = self.acc.lag(0) {
            for dir in [Direction::Ascending, Direction::Descending] {
                let off = knots.offset(dir);
                for i in 0..knots.segments(dir) {
                    let e = lag0.zz.get(off + i).and_then(|r| r.get(off + i));
                    if !matches!(e, Some(&v) if v > T::zero()) {
                        return Err(Error::NoExcitation {
                            path: dir,
                            knot: i + 1,
                        });
                    }
                }
            }
        }
        Ok(())
    }

    /// How the model gets μ0: known (the hold's, or given), or from the means when the rows
    /// were centred.
    fn model_mu0(&self) -> Mu0<T, M> {
        let offset = self.mu0.unwrap_or_default();
        if matches!(self.settings.mu0, MuZero::Estimate) {
            let (mean_z, mean_y) = self.acc.weighted_means();
            Mu0::FromMeans {
                offset,
                mean_y,
                mean_z,
            }
        } else {
            Mu0::Known(offset)
        }
    }
}
