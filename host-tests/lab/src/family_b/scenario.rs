//! A scenario, `(class, seed)`, and the design its seed draws: plant (order 1–4, real and
//! complex poles), sample time, element and borders, input kind, noise colour and ratio, and
//! the class's own parameters.

use super::class::Class;
use super::element::Borders;
use super::input::InputKind;
use super::noise::Colour;
use super::plant::{Plant, Section};
use super::rng::Rng;
use hsid_host::model;

/// Sample times, s.
pub const SAMPLE_TIMES: [f64; 3] = [0.05, 0.1, 0.2];
/// Samples of the hold at `u_min` opening each record.
pub const HOLD: usize = 300;
/// Samples after the hold in the estimation record.
pub const ESTIMATION: usize = 3000;
/// Samples after the hold in the validation record.
pub const VALIDATION: usize = 1500;
/// Uniform segments of the borders and of the diagnosis's knots.
pub const SEGMENTS: usize = 8;

/// One scenario.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Scenario {
    /// True class.
    pub class: Class,
    /// Seed (≥ 1).
    pub seed: u64,
}

/// What a scenario's seed draws.
#[derive(Clone, Debug, PartialEq)]
pub struct Design {
    /// The plant without the class's additions (its order is declared to the diagnosis).
    pub plant: Plant,
    /// Sample time, s.
    pub ts: f64,
    /// Input range `[u_min, u_max]`.
    pub range: (f64, f64),
    /// The element.
    pub kind: model::Element,
    /// Its borders.
    pub borders: Borders,
    /// The input.
    pub input: InputKind,
    /// Target signal-to-noise ratio, dB: variance of the noise-free output after the hold of
    /// the estimation record over the noise's.
    pub snr_db: f64,
    /// The noise's colour.
    pub colour: Colour,
}

impl Scenario {
    /// A scenario.
    pub fn new(class: Class, seed: u64) -> Self {
        Self { class, seed }
    }

    /// The random stream `stream` of this scenario.
    pub fn rng(&self, stream: u64) -> Rng {
        let c = Class::ALL
            .iter()
            .position(|&c| c == self.class)
            .unwrap_or(0) as u64;
        Rng::new(self.seed.wrapping_mul(1_000_003) ^ (c << 40), stream)
    }

    /// The design. Order, sample time, input and element cycle with the seed (offset by the
    /// class, so that every class meets every order); the rest is drawn.
    pub fn design(&self) -> Design {
        let c = Class::ALL
            .iter()
            .position(|&c| c == self.class)
            .unwrap_or(0) as u64;
        let s = self.seed.saturating_sub(1);
        let mut rng = self.rng(0);
        let order = 1 + ((s + c) % 4) as usize;
        let ts = SAMPLE_TIMES[((s + 2 * c) % 3) as usize];
        let input = self.input_kind();
        let kind = match (self.class, input) {
            (Class::StaticHysteresis, _) | (_, InputKind::Table1) if (s / 2).is_multiple_of(2) => {
                model::Element::Backlash
            }
            (Class::StaticHysteresis, _) | (_, InputKind::Table1) => model::Element::Switch,
            _ => model::Element::Static,
        };
        let range = (rng.between(-3.0, -1.0), rng.between(1.0, 3.0));
        let sign = if kind == model::Element::Backlash {
            -1.0
        } else {
            1.0
        };
        let borders = Borders::random(
            &mut rng,
            range,
            SEGMENTS,
            kind != model::Element::Static,
            sign,
        );
        let plant = random_plant(&mut rng, order);
        let snr_db = rng.between(10.0, 40.0);
        let colour = match self.class {
            Class::ColouredNoise if rng.chance(0.5) => Colour::Ar1(rng.between(0.6, 0.9)),
            Class::ColouredNoise => Colour::Ma2(rng.between(0.6, 1.0), rng.between(0.3, 0.6)),
            _ => Colour::White,
        };
        Design {
            plant,
            ts,
            range,
            kind,
            borders,
            input,
            snr_db,
            colour,
        }
    }

    /// Table I for odd seeds and for the integrating plant; an ordinary input (smoothed or
    /// multisine) for even seeds and for the element behind a static model; the smoothed
    /// input as the closed loop's reference (a multisine reference pushed the clamped input
    /// into a rank-deficient regressor).
    pub fn input_kind(&self) -> InputKind {
        let ordinary = if (self.seed / 2).is_multiple_of(2) {
            InputKind::Smoothed
        } else {
            InputKind::Multisine
        };
        match self.class {
            Class::Integrating => InputKind::Table1,
            Class::StaticHysteresis => ordinary,
            Class::ClosedLoop => InputKind::Smoothed,
            _ if self.seed % 2 == 1 => InputKind::Table1,
            _ => ordinary,
        }
    }
}

/// A plant of `order` states: complex pairs (probability one half per pair of states) and
/// real poles, time constants 0.15–1 s, natural frequencies 1.5–6 rad/s, damping 0.3–0.8.
pub fn random_plant(rng: &mut Rng, order: usize) -> Plant {
    let mut sections = Vec::new();
    let mut left = order;
    while left > 0 {
        if left >= 2 && rng.chance(0.5) {
            sections.push(Section::Complex {
                omega: rng.between(1.5, 6.0),
                zeta: rng.between(0.3, 0.8),
            });
            left -= 2;
        } else {
            sections.push(Section::Real {
                tau: rng.between(0.15, 1.0),
            });
            left -= 1;
        }
    }
    Plant { sections }
}
