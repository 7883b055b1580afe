//! Desktop front end to the core: run-time sizes, `f64`, whole records in memory.
//!
//! The core sizes its buffers by capacities in its types; this module picks a capacity that
//! fits the requested knots and horizons and runs the streaming identifier on a thread with a
//! stack large enough for it, then converts the result into a [`HostModel`] with poles,
//! frequency response and simulation.

use crate::model::Element;
use hsid::{Basis, Direction, Identifier, Knots, MuZero, Order, Settings};
use nalgebra::DMatrix;

use crate::model_file::{FormatTag, ModelFile};
use crate::numerics::direction::directions;
use crate::numerics::poly::eigenvalues;

/// Everything the desktop identification needs besides the data.
#[derive(Clone, Debug, PartialEq)]
pub struct IdentifyOptions {
    /// Ascending-path knots, `u_min` … `u_max`.
    pub knots_asc: Vec<f64>,
    /// Descending-path knots, `u_min` … `u_max`.
    pub knots_desc: Vec<f64>,
    /// Future horizon.
    pub f: usize,
    /// Past horizon.
    pub p: usize,
    /// Fixed order, or `None` for automatic selection.
    pub order: Option<usize>,
    /// Samples of the initial hold at `u_min` (0: μ0 must be given in `mu0`).
    pub hold: usize,
    /// Samples skipped at the start of the hold.
    pub settle: usize,
    /// Known μ0, used when `hold == 0`; with no hold and no μ0 it is estimated
    /// ([`hsid::MuZero::Estimate`]).
    pub mu0: Option<f64>,
    /// Border basis.
    pub basis: Basis,
    /// A static (memoryless) nonlinearity: one border for both directions, on `knots_asc`.
    pub static_nonlinearity: bool,
    /// Subspace weighting.
    pub method: hsid::Method,
    /// What the solve accepts as the linear part: a stable `A` only (the default), or any
    /// (for a caller that refines the poles afterwards; see [`hsid::Identifier::solve_with`]).
    pub poles: hsid::Poles,
}

impl IdentifyOptions {
    /// The channel capacity these options need: the segments of both paths, or for a static
    /// element (one shared knot vector, stored with its n + 1 knots) one more than its
    /// segments. At most [`MAX_CHANNELS`] fit.
    pub fn channels(&self) -> usize {
        match self.static_nonlinearity {
            true => self.knots_asc.len(),
            false => {
                self.knots_asc.len().saturating_sub(1) + self.knots_desc.len().saturating_sub(1)
            }
        }
    }

    /// Uniform knots with `segments` segments per path on `[u_min, u_max]`, `f = p = 10`,
    /// automatic order, a hold of `hold` samples of which the first half settles.
    pub fn uniform(u_min: f64, u_max: f64, segments: usize, hold: usize) -> Self {
        let knots: Vec<f64> = (0..=segments)
            .map(|i| {
                if i == segments {
                    u_max
                } else {
                    u_min + (u_max - u_min) * i as f64 / segments as f64
                }
            })
            .collect();
        Self {
            knots_asc: knots.clone(),
            knots_desc: knots,
            f: 10,
            p: 10,
            order: None,
            hold,
            settle: hold / 2,
            mu0: None,
            basis: Basis::Hat,
            static_nonlinearity: false,
            method: hsid::Method::PiMoesp,
            poles: hsid::Poles::Stable,
        }
    }

    /// `u_min`, the first knot.
    pub fn u_min(&self) -> f64 {
        self.knots_asc.first().copied().unwrap_or(f64::NAN)
    }

    /// `u_max`, the last knot.
    pub fn u_max(&self) -> f64 {
        self.knots_asc.last().copied().unwrap_or(f64::NAN)
    }
}

/// Why a desktop identification failed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum IdentifyError {
    /// The core rejected the settings or the data.
    #[error("{e}{advice}", e = .0, advice = core_advice(.0))]
    Core(#[from] hsid::Error),
    /// `u` and `y` differ in length.
    #[error("u has {u} samples but y has {y}: give one y per u")]
    LengthMismatch {
        /// Samples of `u`.
        u: usize,
        /// Samples of `y`.
        y: usize,
    },
    /// More channels or block rows than the largest capacity compiled in ([`CAPACITIES`]).
    #[error(
        "{channels} channels and f + p = {block_rows} block rows: the desktop front end holds at most {MAX_CHANNELS} channels (segments of both paths, one more for shared knots) and f + p <= {MAX_BLOCK_ROWS}: use fewer knots or shorter horizons"
    )]
    TooLarge {
        /// Channel capacity requested (segments of both paths; one more for shared knots).
        channels: usize,
        /// Block rows `f + p` requested.
        block_rows: usize,
    },
}

/// What to try after the core's error, for the errors whose usual cause is the plant or the
/// order rather than the data.
fn core_advice(e: &hsid::Error) -> &'static str {
    match e {
        hsid::Error::UnstableModel { .. } | hsid::Error::IntegratingModel => {
            "; if the plant integrates (voltage → position, a level loop), identify its stable part on the output's increments y(t) − y(t − 1) with one pole fixed at z = 1 (hsid identify --integrating; the borders are then the output's rate per sample)"
        }
        hsid::Error::ZeroStaticGain => {
            "; an estimate of more states than the record supports (a slowly sampled plant, an output curve) can also put a zero near z = 1: try a lower --order"
        }
        _ => "",
    }
}

/// A capacity the desktop front end compiles the core for: `Identifier<_, channels,
/// block_rows, _, horizon>`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Capacity {
    /// Regressor channels `M`.
    pub channels: usize,
    /// Block rows `K` (`f + p`).
    pub block_rows: usize,
    /// Horizon capacity `H` (largest `f`).
    pub horizon: usize,
}

impl Capacity {
    /// Whether a request of `channels` channels, horizons `f` and `f + p = block_rows` fits.
    pub fn holds(&self, channels: usize, f: usize, block_rows: usize) -> bool {
        channels <= self.channels && block_rows <= self.block_rows && f <= self.horizon
    }
}

/// The paper's class (`f = p = 10`, 7 + 7 segments, and anything like it): small enough for
/// any thread's stack.
const PAPER: Capacity = Capacity {
    channels: 16,
    block_rows: 24,
    horizon: hsid::DEFAULT_HORIZON,
};
/// Up to 16 + 16 segments and `f + p <= 48`.
const MEDIUM: Capacity = Capacity {
    channels: 32,
    block_rows: 48,
    horizon: 47,
};
/// Up to 32 + 32 segments and `f + p <= 96`.
const LARGE: Capacity = Capacity {
    channels: 64,
    block_rows: 96,
    horizon: 95,
};

/// The capacities compiled in, smallest first; a request runs in the first that holds it.
/// All but the paper's hold up to a few MB of sums (`K·M²` scalars) and run on a thread with
/// a large stack. Their horizon capacity is `K − 1`, so within `f + p <= K` any split of the
/// block rows is accepted.
pub const CAPACITIES: [Capacity; 3] = [PAPER, MEDIUM, LARGE];

/// Largest channel capacity (segments of both paths together) the desktop front end accepts.
pub const MAX_CHANNELS: usize = LARGE.channels;

/// The most segments per path that fit [`MAX_CHANNELS`]: half of it for a two-path element,
/// one less than it for a static one ([`IdentifyOptions::channels`]).
pub const fn max_segments(static_nonlinearity: bool) -> usize {
    match static_nonlinearity {
        true => MAX_CHANNELS - 1,
        false => MAX_CHANNELS / 2,
    }
}
/// Largest `f + p` the desktop front end accepts.
pub(crate) const MAX_BLOCK_ROWS: usize = LARGE.block_rows;

/// Stack of the thread that runs the large capacities.
const LARGE_STACK: usize = 256 << 20;

/// Scalars of the column blocks of the Schur complement a solve beyond the paper's capacity
/// may use (64 MB of `f64`).
const WIDE_CACHE: usize = 8 << 20;

/// Scalars of solve workspace for `id`. In the paper's capacity the core's default block
/// width, whose costs the documentation quotes; beyond it as wide as [`WIDE_CACHE`] allows, up
/// to the whole Schur complement: one pass over the lagged sums instead of one per pair of
/// column blocks (the model is the same bit for bit; at `f = p = 30` with 40 channels the
/// solve is about 20 times faster).
fn workspace_len<T: hsid::Real, const M: usize, const K: usize, S, const H: usize>(
    id: &Identifier<T, M, K, S, H>,
) -> usize
where
    S: hsid::Summation<T, M, K>,
{
    if (M, K, H) == (PAPER.channels, PAPER.block_rows, PAPER.horizon) {
        return id.workspace_len();
    }
    let s = id.settings();
    let m = s.knots.channels();
    let fm = s.f * m;
    // Columns of the Schur complement, with past outputs at most `p·(m + 1) + f`.
    let q = s.p * (m + 1) + s.f;
    let width = q.min(WIDE_CACHE / (2 * fm).max(1));
    id.workspace_len() + 2 * fm * width.saturating_sub(hsid::SCHUR_BLOCK)
}

/// Work on an identifier of a capacity chosen at run time ([`with_capacity`]).
trait SizedJob: Sync {
    /// What the work gives.
    type Out: Send;
    /// Runs the work in the capacity `(M, K, H)`.
    fn run<const M: usize, const K: usize, const H: usize>(&self) -> Self::Out;
}

/// Runs `job` in the first of [`CAPACITIES`] that holds `channels`, `f` and `block_rows`; the
/// large ones on a thread with [`LARGE_STACK`]. `None` if none holds them (or the thread
/// could not be started or panicked).
fn with_capacity<J: SizedJob>(
    job: &J,
    channels: usize,
    f: usize,
    block_rows: usize,
) -> Option<J::Out> {
    let class = CAPACITIES
        .iter()
        .position(|c| c.holds(channels, f, block_rows))?;
    if class == 0 {
        return Some(job.run::<{ PAPER.channels }, { PAPER.block_rows }, { PAPER.horizon }>());
    }
    std::thread::scope(|s| {
        std::thread::Builder::new()
            .stack_size(LARGE_STACK)
            .spawn_scoped(s, || match class {
                1 => job.run::<{ MEDIUM.channels }, { MEDIUM.block_rows }, { MEDIUM.horizon }>(),
                _ => job.run::<{ LARGE.channels }, { LARGE.block_rows }, { LARGE.horizon }>(),
            })
            .ok()?
            .join()
            .ok()
    })
}

/// An identified model with `f64` matrices, ready for analysis and JSON.
#[derive(Clone, Debug, PartialEq)]
pub struct HostModel {
    /// Order `n`.
    pub order: usize,
    /// `A` (`n × n`).
    pub a: DMatrix<f64>,
    /// `B` (length `n`).
    pub b: Vec<f64>,
    /// `C` (length `n`).
    pub c: Vec<f64>,
    /// `D`.
    pub d: f64,
    /// μ0.
    pub mu0: f64,
    /// Ascending knots.
    pub knots_asc: Vec<f64>,
    /// Descending knots.
    pub knots_desc: Vec<f64>,
    /// `P_a` at the ascending knots.
    pub border_asc: Vec<f64>,
    /// `P_d` at the descending knots.
    pub border_desc: Vec<f64>,
    /// Singular values of `O_f / √j`.
    pub singular_values: Vec<f64>,
    /// Whitened singular values used for the order.
    pub whitened_singular_values: Vec<f64>,
    /// Future horizon.
    pub f: usize,
    /// Past horizon.
    pub p: usize,
    /// Samples used (hold included).
    pub samples: usize,
}

/// Identifies a model from a whole record (hold first, if any).
pub fn identify(u: &[f64], y: &[f64], opts: &IdentifyOptions) -> Result<HostModel, IdentifyError> {
    if u.len() != y.len() {
        return Err(IdentifyError::LengthMismatch {
            u: u.len(),
            y: y.len(),
        });
    }
    let mut samples = u.iter().copied().zip(y.iter().copied());
    identify_stream(&mut || samples.next(), opts)
}

/// Identifies a model from samples `(u, y)` given one at a time by `next` (hold first, if
/// any) until it gives `None`, without keeping them: memory does not grow with the record.
pub fn identify_stream(
    next: &mut (dyn FnMut() -> Option<(f64, f64)> + Send),
    opts: &IdentifyOptions,
) -> Result<HostModel, IdentifyError> {
    let channels = opts.channels();
    let block_rows = opts.f.saturating_add(opts.p);
    let too_large = IdentifyError::TooLarge {
        channels,
        block_rows,
    };
    let job = Identify {
        next: std::sync::Mutex::new(next),
        opts,
    };
    with_capacity(&job, channels, opts.f, block_rows).unwrap_or(Err(too_large))
}

/// [`identify_stream`] in a capacity.
struct Identify<'a, 'b> {
    next: std::sync::Mutex<&'a mut (dyn FnMut() -> Option<(f64, f64)> + Send + 'b)>,
    opts: &'a IdentifyOptions,
}

impl SizedJob for Identify<'_, '_> {
    type Out = Result<HostModel, IdentifyError>;
    fn run<const M: usize, const K: usize, const H: usize>(&self) -> Self::Out {
        // One job runs once: the lock is never contended, nor poisoned but by a panic.
        let mut next = self.next.lock().unwrap_or_else(|e| e.into_inner());
        run::<M, K, H>(&mut **next, self.opts)
    }
}

fn run<const M: usize, const K: usize, const H: usize>(
    next: &mut (dyn FnMut() -> Option<(f64, f64)> + Send + '_),
    opts: &IdentifyOptions,
) -> Result<HostModel, IdentifyError> {
    let knots = if opts.static_nonlinearity {
        Knots::<f64, M>::shared(&opts.knots_asc)?
    } else {
        Knots::<f64, M>::new(&opts.knots_asc, &opts.knots_desc)?
    };
    let mu0 = match (opts.hold, opts.mu0) {
        (0, Some(v)) => MuZero::Known(v),
        (0, None) => MuZero::Estimate,
        (len, _) => MuZero::Hold {
            len,
            settle: opts.settle,
        },
    };
    let mut settings = Settings::new(knots, opts.f, opts.p, mu0);
    settings.basis = opts.basis;
    settings.order = opts.order.map_or(Order::Auto, Order::Fixed);
    settings.method = opts.method;
    let mut id = Box::new(Identifier::<f64, M, K, hsid::Plain, H>::new(settings)?);
    let mut samples = 0usize;
    while let Some((ui, yi)) = next() {
        id.push(ui, yi);
        samples += 1;
    }
    let mut ws = vec![0.0; workspace_len(&id)];
    let m = id.solve_with(&mut ws, opts.poles)?;
    let n = m.order();
    Ok(HostModel {
        order: n,
        a: DMatrix::from_fn(n, n, |i, j| m.a(i, j)),
        b: m.b().to_vec(),
        c: m.c().to_vec(),
        d: m.d(),
        mu0: m.mu0(),
        knots_asc: m.knots().path(Direction::Ascending).to_vec(),
        knots_desc: m.knots().path(Direction::Descending).to_vec(),
        border_asc: m.border_values(Direction::Ascending).to_vec(),
        border_desc: m.border_values(Direction::Descending).to_vec(),
        singular_values: m.singular_values().to_vec(),
        whitened_singular_values: m.whitened_singular_values().to_vec(),
        f: opts.f,
        p: opts.p,
        samples,
    })
}

/// Linear interpolation of border values `v` on knots `x` (clamped outside).
pub fn interpolate(x: &[f64], v: &[f64], u: f64) -> f64 {
    let n = x.len().min(v.len());
    if n == 0 {
        return f64::NAN;
    }
    if u <= x[0] {
        return v[0];
    }
    for i in 0..n - 1 {
        if u <= x[i + 1] {
            return v[i] + (v[i + 1] - v[i]) * (u - x[i]) / (x[i + 1] - x[i]);
        }
    }
    v[n - 1]
}

impl HostModel {
    /// `u_min`, the first knot.
    pub fn u_min(&self) -> f64 {
        self.knots_asc.first().copied().unwrap_or(f64::NAN)
    }

    /// `u_max`, the last knot.
    pub fn u_max(&self) -> f64 {
        self.knots_asc.last().copied().unwrap_or(f64::NAN)
    }

    /// `P_a(u)`.
    pub fn border_asc_at(&self, u: f64) -> f64 {
        interpolate(&self.knots_asc, &self.border_asc, u)
    }

    /// `P_d(u)`.
    pub fn border_desc_at(&self, u: f64) -> f64 {
        interpolate(&self.knots_desc, &self.border_desc, u)
    }

    /// Spectral radius of `A`: the largest pole modulus (0 for order 0).
    pub fn spectral_radius(&self) -> f64 {
        self.poles()
            .iter()
            .map(|(r, i)| r.hypot(*i))
            .fold(0.0, f64::max)
    }

    /// Eigenvalues of `A` as `(re, im)`.
    pub fn poles(&self) -> Vec<(f64, f64)> {
        if self.order == 0 {
            return Vec::new();
        }
        eigenvalues(self.a.clone()).unwrap_or_default()
    }

    /// `G(e^{jw}) = C (e^{jw} I − A)⁻¹ B + D` as `(re, im)`.
    pub fn freq_response(&self, w: f64) -> (f64, f64) {
        let n = self.order;
        // Solve (zI − A) x = B in complex arithmetic as a real 2n system.
        let (cr, ci) = (w.cos(), w.sin());
        let mut m = DMatrix::<f64>::zeros(2 * n, 2 * n);
        let mut rhs = nalgebra::DVector::<f64>::zeros(2 * n);
        for i in 0..n {
            for j in 0..n {
                let re = if i == j { cr } else { 0.0 } - self.a[(i, j)];
                let im = if i == j { ci } else { 0.0 };
                m[(i, j)] = re;
                m[(i, j + n)] = -im;
                m[(i + n, j)] = im;
                m[(i + n, j + n)] = re;
            }
            rhs[i] = self.b[i];
        }
        let Some(x) = m.lu().solve(&rhs) else {
            return (f64::NAN, f64::NAN);
        };
        let mut re = self.d;
        let mut im = 0.0;
        for i in 0..n {
            re += self.c[i] * x[i];
            im += self.c[i] * x[i + n];
        }
        (re, im)
    }

    /// `|G(e^{jw})|` in dB.
    pub(crate) fn magnitude_db(&self, w: f64) -> f64 {
        let (re, im) = self.freq_response(w);
        10.0 * (re * re + im * im).log10()
    }

    /// Simulates the model for an input record, starting at rest at `u_min` (as after the
    /// identification hold): δ(t) from the input, `H = P_a(u)` or `P_d(u)`, then `G`.
    pub fn simulate(&self, u: &[f64]) -> Vec<f64> {
        self.simulate_from(u, self.knots_asc.first().copied().unwrap_or(0.0))
    }

    /// The element's output `h(t)` for the input `u`: the signal
    /// [`simulate_from`](Self::simulate_from) feeds the linear part with the same `u_start`,
    /// the border of each sample's direction at its input.
    pub fn element_output_from(&self, u: &[f64], u_start: f64) -> Vec<f64> {
        u.iter()
            .zip(directions(u, u_start))
            .map(|(&ui, dir)| match dir {
                Direction::Ascending => self.border_asc_at(ui),
                Direction::Descending => self.border_desc_at(ui),
            })
            .collect()
    }

    /// [`simulate`](Self::simulate) with the input before the record at `u_start` (which
    /// decides the path of a first sample that does not move away from it): a model extended
    /// beyond its interval starts where the model it extends starts.
    pub fn simulate_from(&self, u: &[f64], u_start: f64) -> Vec<f64> {
        let n = self.order;
        // Rest state: x = (I − A)⁻¹ B μ0.
        let ia = DMatrix::<f64>::identity(n, n) - &self.a;
        let bvec = nalgebra::DVector::from_column_slice(&self.b) * self.mu0;
        let mut x = ia
            .lu()
            .solve(&bvec)
            .unwrap_or_else(|| nalgebra::DVector::zeros(n));
        let mut out = Vec::with_capacity(u.len());
        for (&ui, dir) in u.iter().zip(directions(u, u_start)) {
            let h = match dir {
                Direction::Ascending => self.border_asc_at(ui),
                Direction::Descending => self.border_desc_at(ui),
            };
            let y = self.d * h + self.c.iter().zip(x.iter()).map(|(c, x)| c * x).sum::<f64>();
            let mut next = &self.a * &x;
            for (i, b) in self.b.iter().enumerate() {
                next[i] += b * h;
            }
            x = next;
            out.push(y);
        }
        out
    }

    /// The model as a [`ModelFile`] of the given kind, without noise model, standard
    /// deviations, sample time or units (the caller adds what it knows).
    pub fn to_json(&self, nonlinearity: Option<Element>) -> ModelFile {
        ModelFile {
            format: FormatTag,
            nonlinearity,
            order: self.order,
            a: (0..self.order)
                .map(|i| (0..self.order).map(|j| self.a[(i, j)]).collect())
                .collect(),
            b: self.b.clone(),
            c: self.c.clone(),
            d: self.d,
            poles: self.poles().into_iter().map(|(r, i)| [r, i]).collect(),
            mu0: self.mu0,
            u_min: self.knots_asc.first().copied().unwrap_or(f64::NAN),
            u_max: self.knots_asc.last().copied().unwrap_or(f64::NAN),
            knots_asc: self.knots_asc.clone(),
            knots_desc: self.knots_desc.clone(),
            border_asc: self.border_asc.clone(),
            border_desc: self.border_desc.clone(),
            sample_time: None,
            units: None,
            singular_values: self.singular_values.clone(),
            f: self.f,
            p: self.p,
            samples: self.samples,
            noise: None,
            std: None,
            integrating: false,
            element: None,
            friction: None,
        }
    }

    /// A model read back from its JSON form (the whitened singular values are not stored).
    pub fn from_json(j: &ModelFile) -> Self {
        let n = j.order;
        HostModel {
            order: n,
            a: DMatrix::from_fn(n, n, |r, c| j.a[r][c]),
            b: j.b.clone(),
            c: j.c.clone(),
            d: j.d,
            mu0: j.mu0,
            knots_asc: j.knots_asc.clone(),
            knots_desc: j.knots_desc.clone(),
            border_asc: j.border_asc.clone(),
            border_desc: j.border_desc.clone(),
            singular_values: j.singular_values.clone(),
            whitened_singular_values: Vec::new(),
            f: j.f,
            p: j.p,
            samples: j.samples,
        }
    }
}

/// What a checkpoint's header says, read without restoring it ([`checkpoint_header`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CheckpointHeader {
    /// Bytes of the scalar the state was accumulated in: 4 (`f32`) or 8 (`f64`).
    pub scalar_bytes: usize,
    /// Regressor channels `m` in use.
    pub channels: usize,
    /// Channel capacity an identifier needs to restore it (one more than `channels` for a
    /// shared knot vector, which stores `n + 1` knots).
    pub channel_capacity: usize,
    /// Future horizon `f`.
    pub f: usize,
    /// Past horizon `p`.
    pub p: usize,
    /// The accumulation's summation: `true` for [`hsid::Compensated`] output sums.
    pub compensated: bool,
}

impl CheckpointHeader {
    /// `"f32"` or `"f64"`.
    pub fn scalar_name(&self) -> &'static str {
        if self.scalar_bytes == 4 { "f32" } else { "f64" }
    }
}

/// A checkpoint solved on the host ([`solve_checkpoint`]).
#[derive(Clone, Debug, PartialEq)]
pub struct CheckpointSolve {
    /// The header (precision, sizes).
    pub header: CheckpointHeader,
    /// The model, solved in the checkpoint's precision and widened to `f64` (exactly).
    pub model: HostModel,
    /// Whether the knots are shared by both paths (a static nonlinearity).
    pub shared_knots: bool,
}

/// Reads what a checkpoint's header says about its size (layout in `hsid::checkpoint`): magic,
/// format version, scalar size, then from the settings the flags, `f`, `p` and the knot counts
/// of both paths. Everything else, checksums included, is checked when the checkpoint is
/// restored ([`solve_checkpoint`]).
pub fn checkpoint_header(bytes: &[u8]) -> Result<CheckpointHeader, IdentifyError> {
    use hsid::CheckpointError as C;
    let err = |e: C| IdentifyError::Core(hsid::Error::Checkpoint(e));
    let magic = b"HSID";
    let head = bytes.get(..magic.len().min(bytes.len())).unwrap_or(&[]);
    if head != &magic[..head.len()] {
        return Err(err(C::NotACheckpoint));
    }
    let field = |at: usize, n: usize| bytes.get(at..at + n).ok_or(err(C::Truncated));
    let u16_at = |at: usize| field(at, 2).map(|b| usize::from(u16::from_le_bytes([b[0], b[1]])));
    field(0, 4)?;
    if field(4, 2)?
        .iter()
        .all(|b| b.is_ascii_graphic() || *b == b' ')
    {
        // "HSID " and text: the firmware's printed output, not a checkpoint.
        return Err(err(C::NotACheckpoint));
    }
    if u16_at(4)? != usize::from(hsid::CHECKPOINT_VERSION) {
        return Err(err(C::Version));
    }
    let scalar_bytes = usize::from(field(6, 1)?[0]);
    if scalar_bytes != 4 && scalar_bytes != 8 {
        // Neither f32 nor f64: no writer produces that, the byte is damaged.
        return Err(err(C::Invalid));
    }
    // After the settings fingerprint (u32 at 7): flags u8, f u16, p u16, then per path a u16
    // knot count and the knots.
    let settings_at = 11;
    let flags = field(settings_at, 1)?[0];
    let shared = flags & 1 != 0;
    let compensated = flags & 4 != 0;
    let f = u16_at(settings_at + 1)?;
    let p = u16_at(settings_at + 3)?;
    let len_asc = u16_at(settings_at + 5)?;
    let len_desc = u16_at(settings_at + 7 + len_asc * scalar_bytes)?;
    let segments = |len: usize| len.saturating_sub(1);
    let (channels, channel_capacity) = if shared {
        (segments(len_asc), len_asc)
    } else {
        let m = segments(len_asc) + segments(len_desc);
        (m, m.max(len_asc).max(len_desc))
    };
    Ok(CheckpointHeader {
        scalar_bytes,
        channels,
        channel_capacity,
        f,
        p,
        compensated,
    })
}

/// Restores a checkpoint written by [`hsid::Identifier::save`] (on a device or a desktop, in
/// `f32` or `f64`) into an identifier with enough capacity and solves it, in the checkpoint's
/// precision: an `f32` state solved here gives the model the device's solve gives, up to the
/// differences between the two targets' floating-point code (`libm` vs the host's `std`).
pub fn solve_checkpoint(bytes: &[u8]) -> Result<CheckpointSolve, IdentifyError> {
    solve_checkpoint_with(bytes, Solver::Dense)
}

/// Which of the core's solves [`solve_checkpoint_with`] runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Solver {
    /// `Identifier::solve`: the Gram's blocks, any settings.
    #[default]
    Dense,
    /// `Identifier::solve_structured`: the Gram's displacement generator, as the firmware
    /// solves by default (PI-MOESP, μ0 not estimated, no forgetting).
    Structured,
}

impl Solver {
    /// Both solves.
    pub const ALL: [Solver; 2] = [Solver::Dense, Solver::Structured];

    /// Its name on the command line, in Python and on the firmware's config line: `dense`,
    /// `structured`.
    pub const fn name(self) -> &'static str {
        match self {
            Solver::Dense => "dense",
            Solver::Structured => "structured",
        }
    }

    /// The solve called `name` ([`name`](Self::name)), if any.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|s| s.name() == name)
    }
}

/// [`solve_checkpoint`] with the solve of `solver`: the on-target model of a firmware that
/// solved with the same one, to `f32` rounding.
pub fn solve_checkpoint_with(
    bytes: &[u8],
    solver: Solver,
) -> Result<CheckpointSolve, IdentifyError> {
    let header = checkpoint_header(bytes)?;
    let (m, k) = (header.channel_capacity, header.f + header.p);
    let too_large = IdentifyError::TooLarge {
        channels: header.channels,
        block_rows: k,
    };
    let job = RestoreAndSolve {
        kind: (header.scalar_bytes == 4, header.compensated),
        bytes,
        solver,
    };
    let solved = with_capacity(&job, m, header.f, k).unwrap_or(Err(too_large));
    let (model, shared_knots) = solved?;
    Ok(CheckpointSolve {
        header,
        model,
        shared_knots,
    })
}

/// [`restore_and_solve`] in the checkpoint's scalar type (`f32` if the first flag is set) and
/// summation (compensated if the second is).
struct RestoreAndSolve<'a> {
    kind: (bool, bool),
    bytes: &'a [u8],
    solver: Solver,
}

impl SizedJob for RestoreAndSolve<'_> {
    type Out = Result<(HostModel, bool), IdentifyError>;
    fn run<const M: usize, const K: usize, const H: usize>(&self) -> Self::Out {
        use hsid::{Compensated, Plain};
        let (bytes, solver) = (self.bytes, self.solver);
        match self.kind {
            (true, false) => restore_and_solve::<f32, M, K, Plain, H>(bytes, solver),
            (false, false) => restore_and_solve::<f64, M, K, Plain, H>(bytes, solver),
            (true, true) => restore_and_solve::<f32, M, K, Compensated, H>(bytes, solver),
            (false, true) => restore_and_solve::<f64, M, K, Compensated, H>(bytes, solver),
        }
    }
}

fn restore_and_solve<T: hsid::Real, const M: usize, const K: usize, S, const H: usize>(
    bytes: &[u8],
    solver: Solver,
) -> Result<(HostModel, bool), IdentifyError>
where
    S: hsid::Summation<T, M, K>,
{
    let id = Box::new(Identifier::<T, M, K, S, H>::restore(bytes)?);
    let m = match solver {
        Solver::Dense => id.solve(&mut vec![T::zero(); workspace_len(&id)])?,
        Solver::Structured => {
            id.solve_structured(&mut vec![T::zero(); id.structured_workspace_len()])?
        }
    };
    let wide = |v: &[T]| v.iter().map(|x| x.to_f64()).collect::<Vec<f64>>();
    let n = m.order();
    let settings = id.settings();
    let model = HostModel {
        order: n,
        a: DMatrix::from_fn(n, n, |i, j| m.a(i, j).to_f64()),
        b: wide(m.b()),
        c: wide(m.c()),
        d: m.d().to_f64(),
        mu0: m.mu0().to_f64(),
        knots_asc: wide(m.knots().path(Direction::Ascending)),
        knots_desc: wide(m.knots().path(Direction::Descending)),
        border_asc: wide(m.border_values(Direction::Ascending)),
        border_desc: wide(m.border_values(Direction::Descending)),
        singular_values: wide(m.singular_values()),
        whitened_singular_values: wide(m.whitened_singular_values()),
        f: settings.f,
        p: settings.p,
        samples: usize::try_from(id.samples()).unwrap_or(usize::MAX),
    };
    Ok((model, settings.knots.is_shared()))
}

#[cfg(test)]
impl HostModel {
    /// A first-order model for unit tests: `x⁺ = 0.5 x + h`, `y = 0.5 x` (pole 0.5, unit
    /// static gain), a linear element `h(u) = u` on [-1, 1].
    pub(crate) fn first_order_for_tests() -> Self {
        let k = vec![-1.0, 0.0, 1.0];
        HostModel {
            order: 1,
            a: nalgebra::DMatrix::from_element(1, 1, 0.5),
            b: vec![1.0],
            c: vec![0.5],
            d: 0.0,
            mu0: 0.0,
            knots_asc: k.clone(),
            knots_desc: k.clone(),
            border_asc: k.clone(),
            border_desc: k,
            singular_values: vec![],
            whitened_singular_values: vec![],
            f: 1,
            p: 1,
            samples: 0,
        }
    }
}
