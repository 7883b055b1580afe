//! Checkpoints: the identifier's whole state in a fixed-size byte buffer that can be written to
//! flash (power loss) or sent to a host (solve off the device), and restored from it.
//!
//! Layout, little-endian: magic `HSID`, format version, scalar size, the settings (knots,
//! basis, horizons, μ0 mode, order), their fingerprint (CRC-32), then the accumulated state
//! (counters, μ0, the hold's running mean, the first fault, the sums, the lagged sums `R_τ` for
//! the `m` channels and `k` lags in use, the first and last `k` samples in time order) and a
//! CRC-32 of everything before it. Values are stored bit for bit, so resuming gives exactly the
//! result of an uninterrupted run. The size depends on the run-time `m` and `k`, not on the
//! capacities, so a state saved by `Identifier<f32, 14, 20, Plain, 10>` on a device restores
//! into any `Identifier<f32, M, K, Plain, H>` with `M >= 14`, `K >= 20`, `H >= f` on a host.
//!
//! ```
//! use hsid::{Identifier, Knots, MuZero, Settings};
//! let knots = Knots::<f32, 4>::uniform(-1.0, 1.0, 2, 2)?;
//! let mut id = Identifier::<f32, 4, 6>::new(Settings::new(knots, 3, 3, MuZero::Known(0.0)))?;
//! id.push(0.5, 0.1);
//! let mut flash = [0u8; 1024];
//! let len = id.save(&mut flash)?;
//! let back = Identifier::<f32, 4, 6>::restore(&flash[..len])?;
//! assert_eq!(back.samples(), 1);
//! flash[40] ^= 1; // a flipped bit is caught
//! assert!(Identifier::<f32, 4, 6>::restore(&flash[..len]).is_err());
//! # Ok::<(), hsid::Error>(())
//! ```

use crate::accumulation::{Entry, Lagged, Summation};
use crate::direction::Direction;
use crate::error::{CheckpointError, Error, Signal};
use crate::hold::{HoldMean, MuZero};
use crate::identifier::{Forgetting, Identifier, Settings};
use crate::regressor::{Basis, Knots, Located};
use crate::scalar::Real;
use crate::subspace::{Method, Order};

/// Format version written into every checkpoint (3: the summation kind in the settings flags
/// and the carries of compensated sums in the state).
pub const CHECKPOINT_VERSION: u16 = 3;
const MAGIC: [u8; 4] = *b"HSID";

/// CRC-32 (IEEE 802.3, reflected), bitwise: no table in flash.
pub fn crc32(bytes: &[u8]) -> u32 {
    !crc32_update(0xFFFF_FFFF, bytes)
}

pub(crate) fn crc32_update(mut crc: u32, bytes: &[u8]) -> u32 {
    for &b in bytes {
        crc ^= u32::from(b);
        for _ in 0..8 {
            let mask = (crc & 1).wrapping_neg();
            crc = (crc >> 1) ^ (0xEDB8_8320 & mask);
        }
    }
    crc
}

/// Serialises into a buffer, or only counts and checksums (`buf: None`) to size a checkpoint
/// and fingerprint settings without storage.
struct Writer<'a> {
    buf: Option<&'a mut [u8]>,
    pos: usize,
    ok: bool,
    crc: u32,
}

impl<'a> Writer<'a> {
    fn new(buf: Option<&'a mut [u8]>) -> Self {
        Self {
            buf,
            pos: 0,
            ok: true,
            crc: 0xFFFF_FFFF,
        }
    }

    /// CRC-32 of everything written so far.
    fn crc(&self) -> u32 {
        !self.crc
    }

    fn bytes(&mut self, b: &[u8]) {
        if let Some(buf) = self.buf.as_deref_mut() {
            match buf.get_mut(self.pos..self.pos + b.len()) {
                Some(dst) if self.ok => dst.copy_from_slice(b),
                _ => self.ok = false,
            }
        }
        self.crc = crc32_update(self.crc, b);
        self.pos += b.len();
    }
    fn u8(&mut self, v: u8) {
        self.bytes(&[v]);
    }
    fn u16(&mut self, v: u16) {
        self.bytes(&v.to_le_bytes());
    }
    fn u32(&mut self, v: u32) {
        self.bytes(&v.to_le_bytes());
    }
    fn u64(&mut self, v: u64) {
        self.bytes(&v.to_le_bytes());
    }
    fn real<T: Real>(&mut self, v: T) {
        let mut tmp = [0u8; 8];
        if v.write_le(&mut tmp) {
            self.bytes(&tmp[..T::BYTES]);
        } else {
            self.ok = false;
        }
    }
}

struct Reader<'a> {
    buf: &'a [u8],
    pos: usize,
}

impl Reader<'_> {
    fn bytes(&mut self, n: usize) -> Result<&[u8], CheckpointError> {
        let s = self
            .buf
            .get(self.pos..self.pos + n)
            .ok_or(CheckpointError::Truncated)?;
        self.pos += n;
        Ok(s)
    }
    fn u8(&mut self) -> Result<u8, CheckpointError> {
        Ok(self.bytes(1)?.first().copied().unwrap_or(0))
    }
    fn u16(&mut self) -> Result<u16, CheckpointError> {
        let b = self.bytes(2)?;
        Ok(u16::from_le_bytes([b[0], b[1]]))
    }
    fn u32(&mut self) -> Result<u32, CheckpointError> {
        let mut a = [0u8; 4];
        a.copy_from_slice(self.bytes(4)?);
        Ok(u32::from_le_bytes(a))
    }
    fn u64(&mut self) -> Result<u64, CheckpointError> {
        let mut a = [0u8; 8];
        a.copy_from_slice(self.bytes(8)?);
        Ok(u64::from_le_bytes(a))
    }
    fn real<T: Real>(&mut self) -> Result<T, CheckpointError> {
        T::read_le(self.bytes(T::BYTES)?).ok_or(CheckpointError::Truncated)
    }
}

fn dir_code(d: Direction) -> u8 {
    d.delta()
}

fn dir_of(c: u8) -> Result<Direction, CheckpointError> {
    match c {
        1 => Ok(Direction::Ascending),
        0 => Ok(Direction::Descending),
        _ => Err(CheckpointError::Invalid),
    }
}

/// Bytes of the settings section (after magic, version and scalar size).
/// `summation` is the [`Summation::CODE`] (0 or 1), in bit 2 of the flags.
fn write_settings<T: Real, const M: usize>(w: &mut Writer<'_>, s: &Settings<T, M>, summation: u8) {
    let shared = s.knots.is_shared();
    w.u8(u8::from(shared) | (u8::from(s.basis == Basis::Ramp) << 1) | (summation << 2));
    w.u16(s.f as u16);
    w.u16(s.p as u16);
    for dir in [Direction::Ascending, Direction::Descending] {
        let k = s.knots.path(dir);
        w.u16(k.len() as u16);
        for &v in k {
            w.real(v);
        }
    }
    match s.mu0 {
        MuZero::Hold { len, settle } => {
            w.u8(0);
            w.u32(len as u32);
            w.u32(settle as u32);
            w.real(T::zero());
        }
        MuZero::Known(v) => {
            w.u8(1);
            w.u32(0);
            w.u32(0);
            w.real(v);
        }
        MuZero::Estimate => {
            w.u8(2);
            w.u32(0);
            w.u32(0);
            w.real(T::zero());
        }
    }
    match s.order {
        Order::Auto => w.u16(0),
        Order::Fixed(n) => w.u16(n as u16),
    }
    w.u8(match s.method {
        Method::PiMoesp => 0,
        Method::PoMoesp => 1,
        Method::N4sid => 2,
        Method::Cva => 3,
    });
    w.real(match s.forgetting {
        Forgetting::None => T::one(),
        Forgetting::Exponential { lambda } => lambda,
    });
}

/// The settings and the summation code.
type ReadSettings<T, const M: usize> = (Result<Settings<T, M>, Error>, u8);

fn read_settings<T: Real, const M: usize>(
    r: &mut Reader<'_>,
) -> Result<ReadSettings<T, M>, CheckpointError> {
    let flags = r.u8()?;
    if flags >> 3 != 0 {
        return Err(CheckpointError::Invalid);
    }
    let f = r.u16()? as usize;
    let p = r.u16()? as usize;
    let mut knots: [[T; M]; 2] = [[T::zero(); M]; 2];
    let mut lens = [0usize; 2];
    for (slot, len) in knots.iter_mut().zip(lens.iter_mut()) {
        *len = r.u16()? as usize;
        if *len > M {
            return Err(CheckpointError::Capacity);
        }
        for v in slot.iter_mut().take(*len) {
            *v = r.real()?;
        }
    }
    let mode = r.u8()?;
    let len = r.u32()? as usize;
    let settle = r.u32()? as usize;
    let value: T = r.real()?;
    let mu0 = match mode {
        0 => MuZero::Hold { len, settle },
        1 => MuZero::Known(value),
        2 => MuZero::Estimate,
        _ => return Err(CheckpointError::Invalid),
    };
    let order = match r.u16()? {
        0 => Order::Auto,
        n => Order::Fixed(n as usize),
    };
    let method = match r.u8()? {
        0 => Method::PiMoesp,
        1 => Method::PoMoesp,
        2 => Method::N4sid,
        3 => Method::Cva,
        _ => return Err(CheckpointError::Invalid),
    };
    let lambda: T = r.real()?;
    let forgetting = if lambda == T::one() {
        Forgetting::None
    } else {
        Forgetting::Exponential { lambda }
    };
    // `lens` were checked against `M` above; `get` keeps that visible to the panic proof.
    let path = |i: usize| knots[i].get(..lens[i]).unwrap_or(&[]);
    let (asc, desc) = (path(0), path(1));
    let knots = if flags & 1 != 0 {
        Knots::shared(asc)
    } else {
        Knots::new(asc, desc)
    };
    let settings = knots.map(|knots| Settings {
        knots,
        basis: if flags & 2 != 0 {
            Basis::Ramp
        } else {
            Basis::Hat
        },
        f,
        p,
        mu0,
        order,
        method,
        forgetting,
    });
    Ok((settings, (flags >> 2) & 1))
}

fn fault_code(e: Option<Error>) -> (u8, u64, f64, u8) {
    match e {
        None => (0, 0, 0.0, 0),
        Some(Error::NonFinite { index, signal }) => {
            (1, index, 0.0, u8::from(signal == Signal::Output))
        }
        Some(Error::InputOutOfRange { index, value }) => (2, index, value, 0),
        Some(Error::HoldNotAtMin { index, value }) => (3, index, value, 0),
        Some(_) => (255, 0, 0.0, 0),
    }
}

fn fault_of(
    code: u8,
    index: u64,
    value: f64,
    signal: u8,
) -> Result<Option<Error>, CheckpointError> {
    Ok(match code {
        0 => None,
        1 => Some(Error::NonFinite {
            index,
            signal: if signal == 1 {
                Signal::Output
            } else {
                Signal::Input
            },
        }),
        2 => Some(Error::InputOutOfRange { index, value }),
        3 => Some(Error::HoldNotAtMin { index, value }),
        _ => return Err(CheckpointError::Invalid),
    })
}

impl<T: Real, const M: usize, const K: usize, S: Summation<T, M, K>, const H: usize>
    Identifier<T, M, K, S, H>
{
    /// Largest checkpoint of this identifier type (capacities `M`, `K`, scalar `T`,
    /// summation `S`): size a static buffer with it.
    pub const CHECKPOINT_CAPACITY: usize = if S::CODE == 0 {
        checkpoint_capacity(M, K, T::BYTES)
    } else {
        compensated_checkpoint_capacity(M, K, T::BYTES)
    };

    /// Bytes [`save`](Self::save) writes for this identifier's settings.
    pub fn checkpoint_len(&self) -> usize {
        let mut w = Writer::new(None);
        self.write(&mut w);
        w.pos
    }

    /// Fingerprint (CRC-32) of the settings, as stored in a checkpoint.
    pub fn fingerprint(&self) -> u32 {
        let mut w = Writer::new(None);
        write_settings(&mut w, &self.settings, S::CODE);
        w.crc()
    }

    /// Writes the whole state into `buf`; returns the bytes written
    /// ([`checkpoint_len`](Self::checkpoint_len)).
    pub fn save(&self, buf: &mut [u8]) -> Result<usize, Error> {
        let need = self.checkpoint_len();
        let buf = buf
            .get_mut(..need)
            .ok_or(Error::Checkpoint(CheckpointError::Truncated))?;
        let mut w = Writer::new(Some(buf));
        self.write(&mut w);
        if !w.ok || w.pos != need {
            return Err(Error::Checkpoint(CheckpointError::Truncated));
        }
        Ok(need)
    }

    fn write(&self, w: &mut Writer<'_>) {
        w.bytes(&MAGIC);
        w.u16(CHECKPOINT_VERSION);
        w.u8(T::BYTES as u8);
        w.u32(self.fingerprint());
        write_settings(w, &self.settings, S::CODE);
        let acc = &self.acc;
        let (m, k) = (self.settings.knots.channels(), acc.k);
        w.u64(acc.count);
        w.u64(self.index);
        w.real(self.u_prev);
        w.u8(dir_code(self.dir));
        w.u8(u8::from(self.mu0.is_some()));
        w.real(self.mu0.unwrap_or_default());
        w.real(self.hold.sum);
        w.real(self.hold.comp);
        w.u32(self.hold.count);
        let (code, index, value, signal) = fault_code(self.fault);
        w.u8(code);
        w.u64(index);
        w.u64(value.to_bits());
        w.u8(signal);
        for &v in acc.sum_z.iter().take(m) {
            w.real(v);
        }
        w.real(acc.sum_y);
        w.real(acc.scale);
        for lag in acc.lags.iter().take(k) {
            write_lagged(w, lag, m);
        }
        if let Some(c) = S::carries(&self.carry) {
            for lag in c.lags.iter().take(k) {
                for &v in lag.zy.iter().take(m).chain(lag.yz.iter().take(m)) {
                    w.real(v);
                }
                w.real(lag.yy);
            }
            w.real(c.sum_y);
        }
        let entry = |w: &mut Writer<'_>, e: &Entry<T>| {
            w.u8(dir_code(e.at.dir));
            w.u16(e.at.segment);
            w.real(e.at.theta);
            w.real(e.y);
        };
        for e in acc.head.iter().take(k) {
            entry(w, e);
        }
        // The ring, oldest first.
        for i in 0..k {
            let idx = (acc.pos + i) % k.max(1);
            if let Some(e) = acc.ring.get(idx) {
                entry(w, e);
            }
        }
        let crc = w.crc();
        w.u32(crc);
    }

    /// Restores an identifier from a checkpoint, settings included.
    pub fn restore(bytes: &[u8]) -> Result<Self, Error> {
        Self::restore_inner(bytes, None)
    }

    /// Restores a checkpoint that must have been written with `settings` (e.g. the firmware's
    /// own, after a reset): a checkpoint of another configuration is refused.
    pub fn restore_with(settings: &Settings<T, M>, bytes: &[u8]) -> Result<Self, Error> {
        let probe = Self::new(settings.clone())?;
        Self::restore_inner(bytes, Some(probe.fingerprint()))
    }

    fn restore_inner(bytes: &[u8], expect: Option<u32>) -> Result<Self, Error> {
        let ck = |e: CheckpointError| Error::Checkpoint(e);
        if bytes.len() < 4 + 2 + 1 + 4 {
            return Err(ck(CheckpointError::Truncated));
        }
        let mut r = Reader { buf: bytes, pos: 0 };
        if r.bytes(4).map_err(ck)? != MAGIC {
            return Err(ck(CheckpointError::NotACheckpoint));
        }
        if r.u16().map_err(ck)? != CHECKPOINT_VERSION {
            return Err(ck(CheckpointError::Version));
        }
        if r.u8().map_err(ck)? as usize != T::BYTES {
            return Err(ck(CheckpointError::ScalarType));
        }
        let fp = r.u32().map_err(ck)?;
        let s0 = r.pos;
        let (settings, summation) = read_settings::<T, M>(&mut r).map_err(ck)?;
        let fp_calc = crc32(bytes.get(s0..r.pos).unwrap_or(&[]));
        let settings = match settings {
            Ok(s) => s,
            // Settings that do not validate come from corruption (or a mismatch of
            // capacities); the checksum tells which.
            Err(_) if fp != fp_calc => return Err(ck(CheckpointError::Checksum)),
            Err(e) => return Err(e),
        };
        if fp != fp_calc {
            return Err(ck(CheckpointError::Checksum));
        }
        if summation != S::CODE {
            return Err(ck(CheckpointError::Summation));
        }
        if let Some(e) = expect
            && e != fp
        {
            return Err(ck(CheckpointError::SettingsMismatch));
        }
        let mut id = Self::new(settings).map_err(|e| match e {
            Error::SegmentCount { .. } | Error::InvalidHorizon { .. } => {
                ck(CheckpointError::Capacity)
            }
            other => other,
        })?;
        let need = id.checkpoint_len();
        let body = bytes.get(..need).ok_or(ck(CheckpointError::Truncated))?;
        let crc_at = need - 4;
        let stored = body
            .get(crc_at..need)
            .and_then(|b| b.try_into().ok())
            .map(u32::from_le_bytes)
            .ok_or(ck(CheckpointError::Truncated))?;
        if crc32(body.get(..crc_at).unwrap_or(&[])) != stored {
            return Err(ck(CheckpointError::Checksum));
        }
        let (m, k) = (id.settings.knots.channels(), id.settings.f + id.settings.p);
        let state = (|| -> Result<(), CheckpointError> {
            id.acc.count = r.u64()?;
            id.index = r.u64()?;
            id.u_prev = r.real()?;
            id.dir = dir_of(r.u8()?)?;
            let has_mu0 = r.u8()? != 0;
            let mu0: T = r.real()?;
            id.mu0 = has_mu0.then_some(mu0);
            id.hold = HoldMean {
                sum: r.real()?,
                comp: r.real()?,
                count: r.u32()?,
            };
            let (code, index, value, signal) =
                (r.u8()?, r.u64()?, f64::from_bits(r.u64()?), r.u8()?);
            id.fault = fault_of(code, index, value, signal)?;
            for v in id.acc.sum_z.iter_mut().take(m) {
                *v = r.real()?;
            }
            id.acc.sum_y = r.real()?;
            id.acc.scale = r.real()?;
            for lag in id.acc.lags.iter_mut().take(k) {
                read_lagged(&mut r, lag, m)?;
            }
            if let Some(c) = S::carries_mut(&mut id.carry) {
                for lag in c.lags.iter_mut().take(k) {
                    for v in lag.zy.iter_mut().take(m).chain(lag.yz.iter_mut().take(m)) {
                        *v = r.real()?;
                    }
                    lag.yy = r.real()?;
                }
                c.sum_y = r.real()?;
            }
            let entry = |r: &mut Reader<'_>| -> Result<Entry<T>, CheckpointError> {
                let dir = dir_of(r.u8()?)?;
                let segment = r.u16()?;
                let theta = r.real()?;
                let y = r.real()?;
                Ok(Entry {
                    at: Located {
                        dir,
                        segment,
                        theta,
                    },
                    y,
                })
            };
            for e in id.acc.head.iter_mut().take(k) {
                *e = entry(&mut r)?;
            }
            for e in id.acc.ring.iter_mut().take(k) {
                *e = entry(&mut r)?;
            }
            // Stored oldest first: the next sample goes to slot 0, which now holds the oldest.
            id.acc.pos = 0;
            Ok(())
        })();
        state.map_err(ck)?;
        if !id.consistent() {
            return Err(ck(CheckpointError::Invalid));
        }
        id.acc.rebuild_expanded(&id.settings.knots);
        Ok(id)
    }

    /// Whether a restored state is one that pushing samples into a fresh identifier with its
    /// settings can produce (the checksums only show that it was written as it is read): the
    /// counters agree with each other, the fault and the hold, μ0 is there exactly when it
    /// should be, the last input lies in the interval, the forgetting scale lies in the range
    /// the accumulation keeps it in, and every stored sample is on a segment of its path.
    /// Such a state cannot make `push` or `solve` overflow a counter or loop for long.
    fn consistent(&self) -> bool {
        let s = &self.settings;
        let acc = &self.acc;
        let knots = &s.knots;
        // A saturated sample counter does not count any more (and 2^64 − 1 samples were never
        // pushed).
        if self.index == u64::MAX {
            return false;
        }
        // Samples accepted: up to the fault, which is one of the pushed samples.
        let accepted = match self.fault {
            None => self.index,
            Some(Error::NonFinite { index, .. }) => index,
            Some(
                Error::InputOutOfRange { index, value } | Error::HoldNotAtMin { index, value },
            ) => {
                if !value.is_finite() {
                    return false;
                }
                index
            }
            Some(_) => return false,
        };
        if accepted >= self.index && self.fault.is_some() {
            return false;
        }
        let hold = s.mu0.hold_len() as u64;
        if let Some(Error::HoldNotAtMin { index, .. }) = self.fault
            && index >= hold
        {
            return false;
        }
        // Every accepted sample after the hold is accumulated, the hold's are not.
        if acc.count != accepted.saturating_sub(hold) {
            return false;
        }
        let hold_ok = match s.mu0 {
            MuZero::Hold { len, settle } => {
                let averaged = accepted.min(len as u64).saturating_sub(settle as u64);
                u64::from(self.hold.count) == averaged.min(u64::from(u32::MAX))
            }
            MuZero::Known(_) | MuZero::Estimate => self.hold == HoldMean::ZERO,
        };
        let mu0_ok = match s.mu0 {
            MuZero::Known(v) => {
                self.mu0.map(T::to_f64).map(f64::to_bits) == Some(v.to_f64().to_bits())
            }
            MuZero::Hold { .. } | MuZero::Estimate => self.mu0.is_some() == (acc.count > 0),
        };
        let u_ok = self.u_prev >= knots.u_min() && self.u_prev <= knots.u_max();
        let dir_ok = acc.count > 0 || self.dir == Direction::Descending;
        // The scale starts at 1, grows by 1/λ per sample and is folded back to 1 once above
        // RENORM; without forgetting it stays 1.
        let scale_ok = if acc.lambda == T::one() {
            acc.scale == T::one()
        } else {
            acc.scale >= T::one() && acc.scale <= T::of(crate::accumulation::RENORM)
        };
        let located = |e: &Entry<T>| {
            usize::from(e.at.segment) < knots.segments(e.at.dir)
                && e.at.theta >= T::zero()
                && e.at.theta <= T::one()
        };
        let k = acc.k;
        let entries_ok =
            acc.head.iter().take(k).all(located) && acc.ring.iter().take(k).all(located);
        hold_ok && mu0_ok && u_ok && dir_ok && scale_ok && entries_ok
    }
}

/// Largest checkpoint of an identifier with plain sums ([`Plain`](crate::Plain)), capacities
/// `m` channels and `k` block rows in a scalar of `bytes` bytes (4 or 8): size a static buffer
/// with it (or with [`Identifier::CHECKPOINT_CAPACITY`]).
pub const fn checkpoint_capacity(m: usize, k: usize, bytes: usize) -> usize {
    let knots = m + 2;
    let settings = 1 + 2 + 2 + 2 + 2 + knots * bytes + 1 + 4 + 4 + bytes + 2 + 1 + bytes;
    let header = 4 + 2 + 1 + settings + 4;
    let state = 8 + 8 + bytes + 1 + 1 + bytes + (2 * bytes + 4) + (1 + 8 + 8 + 1);
    header
        + state
        + m * bytes
        + 2 * bytes
        + k * (m * m + 2 * m + 1) * bytes
        + 2 * k * (1 + 2 + 2 * bytes)
        + 4
}

/// Largest checkpoint of an identifier with compensated sums
/// ([`Compensated`](crate::Compensated)): [`checkpoint_capacity`] plus the carries of the
/// output sums.
pub const fn compensated_checkpoint_capacity(m: usize, k: usize, bytes: usize) -> usize {
    checkpoint_capacity(m, k, bytes) + k * (2 * m + 1) * bytes + bytes
}

/// The `m`-channel part of a lagged sum (or of its carries).
fn write_lagged<T: Real, const M: usize>(w: &mut Writer<'_>, lag: &Lagged<T, M>, m: usize) {
    for row in lag.zz.iter().take(m) {
        for &v in row.iter().take(m) {
            w.real(v);
        }
    }
    for &v in lag.zy.iter().take(m) {
        w.real(v);
    }
    for &v in lag.yz.iter().take(m) {
        w.real(v);
    }
    w.real(lag.yy);
}

fn read_lagged<T: Real, const M: usize>(
    r: &mut Reader<'_>,
    lag: &mut Lagged<T, M>,
    m: usize,
) -> Result<(), CheckpointError> {
    for row in lag.zz.iter_mut().take(m) {
        for v in row.iter_mut().take(m) {
            *v = r.real()?;
        }
    }
    for v in lag.zy.iter_mut().take(m) {
        *v = r.real()?;
    }
    for v in lag.yz.iter_mut().take(m) {
        *v = r.real()?;
    }
    lag.yy = r.real()?;
    Ok(())
}
