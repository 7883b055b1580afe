//! A simulated fleet: every device a backlash actuator of its own gap followed by the paper's
//! plant, identified week after week by the core's [`Identifier`] exactly as the firmware runs
//! it (the core's Table I [`Excitation`] in `f32`, one `push` per sample, `save`). Part of the
//! fleet wears (its gap grows week by week), the rest keeps its gap; a few checkpoints are
//! damaged on the way (truncated, corrupted, written with foreign settings, or not a
//! checkpoint at all), as a real fleet's uploads are.

use hsid::{Excitation, Identifier, Knots, MuZero, Settings};
use rand_core::{Rng, SeedableRng};
use rand_distr::{Distribution, StandardNormal};
use rand_pcg::Pcg64;

use crate::sim::{Backlash, Nonlinearity, paper_noise_model, paper_plant};

/// The devices' identifier: `f32`, the paper's capacity (14 channels, 20 block rows), as the
/// firmware builds it.
pub(crate) type DeviceIdentifier = Identifier<f32, 14, 20>;

/// Working interval of every device.
pub const U_MIN: f32 = -3.0;
/// Upper end of the working interval.
pub const U_MAX: f32 = 3.0;

/// What the simulated fleet looks like.
#[derive(Clone, Debug, PartialEq)]
pub struct FleetSpec {
    /// Devices.
    pub devices: usize,
    /// Weeks: one checkpoint per device and week.
    pub weeks: usize,
    /// Every `wear_every`-th device wears (1: all, 2: half).
    pub wear_every: usize,
    /// Range of the gaps of new devices (input units), drawn uniformly per device.
    pub gap: (f64, f64),
    /// Range of the weekly gap growth of a wearing device, drawn uniformly per device.
    pub wear_per_week: (f64, f64),
    /// Samples a device records per week after its hold.
    pub samples: usize,
    /// Samples of the hold at `u_min`; the first half settles.
    pub hold: usize,
    /// Segments per path (uniform knots).
    pub segments: usize,
    /// Standard deviation of the white noise `e` driving the paper's noise model.
    pub noise: f64,
    /// Every `damage_every`-th device has one damaged checkpoint (0: none).
    pub damage_every: usize,
    /// Seed of the whole fleet.
    pub seed: u64,
}

impl FleetSpec {
    /// The fleet the documentation measures: `devices` devices over `weeks` weeks, half of
    /// them wearing by 0.03 to 0.08 per week from gaps of 1.0 to 2.0, 4,000 samples a week
    /// under white noise of standard deviation 0.01 through the paper's noise model.
    pub fn standard(devices: usize, weeks: usize) -> Self {
        Self {
            devices,
            weeks,
            wear_every: 2,
            gap: (1.0, 2.0),
            wear_per_week: (0.03, 0.08),
            samples: 4000,
            hold: 300,
            segments: 7,
            noise: 0.01,
            damage_every: 97,
            seed: 2026,
        }
    }

    /// The settings every device runs (`f = p = 10`).
    pub fn settings(&self) -> Result<Settings<f32, 14>, hsid::Error> {
        let knots = Knots::uniform(U_MIN, U_MAX, self.segments, self.segments)?;
        let mu0 = MuZero::Hold {
            len: self.hold,
            settle: self.hold / 2,
        };
        Ok(Settings::new(knots, 10, 10, mu0))
    }
}

/// How a checkpoint was damaged on its way from the device.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Damage {
    /// Intact.
    None,
    /// Cut to half its length.
    Truncated,
    /// One byte in the middle flipped.
    Corrupted,
    /// Written by a device configured with other knots.
    ForeignSettings,
    /// Not a checkpoint: a text log uploaded in its place.
    NotACheckpoint,
}

impl Damage {
    /// The damage's name in the truth table.
    pub fn name(self) -> &'static str {
        match self {
            Damage::None => "none",
            Damage::Truncated => "truncated",
            Damage::Corrupted => "corrupted",
            Damage::ForeignSettings => "foreign_settings",
            Damage::NotACheckpoint => "not_a_checkpoint",
        }
    }
}

/// One device's truth.
#[derive(Clone, Debug, PartialEq)]
pub struct DeviceTruth {
    /// Device number (0-based).
    pub index: usize,
    /// Whether it wears.
    pub wearing: bool,
    /// True gap per week.
    pub gaps: Vec<f64>,
    /// The week whose checkpoint is damaged, and how.
    pub damaged: Option<(usize, Damage)>,
}

/// The device id of a device's checkpoint of a week: its file name, `d00042-w03.bin`.
pub fn file_name(index: usize, week: usize) -> String {
    format!("d{index:05}-w{week:02}.bin")
}

/// The truth of device `index`: gap, wear and damage drawn from the fleet's seed.
pub fn truth(spec: &FleetSpec, index: usize) -> DeviceTruth {
    let mut rng = Pcg64::seed_from_u64(spec.seed ^ (index as u64).wrapping_mul(0x9E37_79B9));
    let mut uniform =
        |(lo, hi): (f64, f64)| lo + (hi - lo) * (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
    let wearing = spec.wear_every > 0 && index.is_multiple_of(spec.wear_every);
    let g0 = uniform(spec.gap);
    let rate = if wearing {
        uniform(spec.wear_per_week)
    } else {
        0.0
    };
    let gaps = (0..spec.weeks).map(|w| g0 + rate * w as f64).collect();
    let kinds = [
        Damage::Truncated,
        Damage::Corrupted,
        Damage::ForeignSettings,
        Damage::NotACheckpoint,
    ];
    let damaged = (spec.damage_every > 0
        && index % spec.damage_every == spec.damage_every - 1
        && spec.weeks > 0)
        .then(|| {
            (
                (index / spec.damage_every) % spec.weeks,
                kinds[(index / spec.damage_every) % kinds.len()],
            )
        });
    DeviceTruth {
        index,
        wearing,
        gaps,
        damaged,
    }
}

/// One week's record of a device with gap `gap` through the identifier of `settings`, and the
/// checkpoint it saves. `seed` drives the excitation and the noise.
pub(crate) fn record_week(
    spec: &FleetSpec,
    settings: Settings<f32, 14>,
    gap: f64,
    seed: u64,
) -> Result<Vec<u8>, hsid::Error> {
    let mut id = Box::new(DeviceIdentifier::new(settings)?);
    let u_gen = Excitation::new(U_MIN, U_MAX, spec.hold, Pcg64::seed_from_u64(seed))?;
    let mut noise_rng = Pcg64::seed_from_u64(seed ^ 0x5EED);
    let half = gap / 2.0;
    let mut element = Backlash::from_fns(move |u| (u - half).atan(), move |u| (u + half).atan());
    let (mut plant, mut noise) = (paper_plant(), paper_noise_model());
    for u in u_gen.take(spec.hold + spec.samples) {
        let e: f64 = StandardNormal.sample(&mut noise_rng);
        let y = plant.step(element.step(f64::from(u))) + noise.step(spec.noise * e);
        id.push(u, y as f32);
    }
    let mut bytes = vec![0u8; id.checkpoint_len()];
    let len = id.save(&mut bytes)?;
    bytes.truncate(len);
    Ok(bytes)
}

/// The checkpoint of device `t` in `week` as it arrives: recorded, then damaged if the truth
/// says so.
pub(crate) fn device_week(
    spec: &FleetSpec,
    t: &DeviceTruth,
    week: usize,
) -> Result<Vec<u8>, hsid::Error> {
    let damage = match t.damaged {
        Some((w, d)) if w == week => d,
        _ => Damage::None,
    };
    let seed = spec
        .seed
        .wrapping_add((t.index * 1000 + week) as u64 * 0x1_0000_0001);
    let mut settings = spec.settings()?;
    if damage == Damage::ForeignSettings {
        let other = FleetSpec {
            segments: spec.segments.saturating_sub(1),
            ..spec.clone()
        };
        settings = other.settings()?;
    }
    if damage == Damage::NotACheckpoint {
        return Ok(b"HSID fw 1.2 log: motor temperature 41 C, 0 faults\n".to_vec());
    }
    let gap = t.gaps.get(week).copied().unwrap_or(f64::NAN);
    let mut bytes = record_week(spec, settings, gap, seed)?;
    match damage {
        Damage::Truncated => bytes.truncate(bytes.len() / 2),
        Damage::Corrupted => {
            let mid = bytes.len() / 2;
            bytes[mid] ^= 0x40;
        }
        _ => {}
    }
    Ok(bytes)
}
