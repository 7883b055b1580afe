//! A scenario, `(class, loop, seed)`, and the design its seed draws: the servo and its
//! parameters, the sample time, the command's range and kind, the noise, the controller's
//! kind, and the class's own setting (Coulomb level, play, pinned fraction).

use super::class::{Class, Loop};
use super::input::InputKind;
use super::mass::{Mass, Output};
use super::noise::Colour;
use super::rng::Rng;
use super::servo::{Mechanics, Servo};
use super::two_mass::TwoMass;

/// Samples of the hold at `u_min` opening each record.
pub const HOLD: usize = 250;
/// Samples after the hold in the estimation record.
pub const ESTIMATION: usize = 2000;
/// Samples after the hold in the validation record.
pub const VALIDATION: usize = 1500;
/// Uniform segments of the static element's knots on the command's range (one for a
/// two-level PRBS, whose inner knots it never visits).
pub const SEGMENTS: usize = 4;
/// The subspace horizons `f = p`.
pub const HORIZON: usize = 12;
/// Coulomb force over the largest drive force.
pub const COULOMB_LEVELS: [f64; 4] = [0.05, 0.1, 0.2, 0.3];
/// Gear play's half-width over the shaft's twist under the largest motor torque.
pub const PLAY_BETWEEN_LEVELS: [f64; 4] = [0.5, 1.0, 2.0, 4.0];
/// Input play (the whole gap) over the command's range.
pub const INPUT_PLAY_LEVELS: [f64; 4] = [0.04, 0.08, 0.15, 0.25];

/// One scenario.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Scenario {
    /// True class.
    pub class: Class,
    /// Open or closed loop.
    pub lp: Loop,
    /// Seed (≥ 1).
    pub seed: u64,
}

/// How the end stop pins the output.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Pin {
    /// The sensor saturates: the reading `min(x + v, L)`, exactly at the level.
    Sensor,
    /// A mechanical end stop: the position held at `L` while the force pushes there (the
    /// reading keeps its noise).
    Stop,
}

/// The controller's kind.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ControllerKind {
    /// Proportional.
    P,
    /// Proportional–integral.
    Pi,
}

/// What a scenario's seed draws.
#[derive(Clone, Debug, PartialEq)]
pub struct Design {
    /// The servo (for the end stop without its stop, which is placed from a run).
    pub servo: Servo,
    /// Sample time, s.
    pub ts: f64,
    /// The command's range `[u_min, u_max]` (the knots' range).
    pub range: (f64, f64),
    /// The command (open loop) or the reference's kind (closed loop: levels or multisine; a
    /// two-level reference drives a PI loop's command to its clamps and back, and the static
    /// element's inner knots are then never visited).
    pub input: InputKind,
    /// Samples of each Table I level.
    pub level_hold: usize,
    /// Target ratio, dB, of the noise-free output's variance after the estimation record's
    /// hold over the noise's.
    pub snr_db: f64,
    /// The noise's colour.
    pub colour: Colour,
    /// The controller's kind, closed loop only.
    pub controller: Option<ControllerKind>,
    /// The controller's loop gain (P: `K_p G`; PI: `K_p G`, `T_i` over the dominant time).
    pub loop_gain: (f64, f64),
    /// The end stop's kind and pinned fraction.
    pub pin: Option<(Pin, f64)>,
    /// The class's level: Coulomb over the drive force, play over the twist or the range,
    /// the pinned fraction (0 for clean).
    pub level: f64,
    /// The servo in words.
    pub plant: String,
}

impl Design {
    /// Uniform segments of the diagnosis's knots.
    pub fn segments(&self, lp: Loop) -> usize {
        if lp == Loop::Open && self.input == InputKind::Prbs {
            1
        } else {
            SEGMENTS
        }
    }

    /// The dominant time constant in samples.
    pub fn tau_samples(&self) -> f64 {
        self.servo.dominant_time() / self.ts
    }
}

/// A sample time close to `t`: the nearest of 1, 2, 5 × 10ᵏ s in logarithm.
fn round_ts(t: f64) -> f64 {
    let e = t.log10().floor();
    let base = 10f64.powf(e);
    [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * base)
        .min_by(|a, b| {
            (a / t)
                .ln()
                .abs()
                .partial_cmp(&(b / t).ln().abs())
                .unwrap_or(std::cmp::Ordering::Equal)
        })
        .unwrap_or(t)
}

/// A rigid axis: a motor's speed (`spring = false`) or a spring–mass–damper's position,
/// with or without an actuator lag.
fn axis(rng: &mut Rng, spring: bool, actuator: bool) -> Mass {
    let mass = rng.log_between(0.2, 5.0);
    let static_gain = rng.log_between(0.3, 3.0);
    let (damping, stiffness, mech) = if spring {
        let wn = rng.log_between(3.0, 60.0);
        let zeta = rng.between(0.3, 1.0);
        (2.0 * zeta * mass * wn, mass * wn * wn, 1.0 / wn)
    } else {
        let tau = rng.log_between(0.02, 0.5);
        (mass / tau, 0.0, tau)
    };
    let gain = static_gain * if spring { stiffness } else { damping };
    Mass {
        gain,
        actuator: actuator.then(|| rng.between(0.1, 0.4) * mech),
        mass,
        damping,
        stiffness,
        coulomb: 0.0,
        stop: None,
        output: if spring {
            Output::Position
        } else {
            Output::Velocity
        },
    }
}

/// A two-mass drive: resonance 30–200 rad/s, shaft damping ratio 0.05–0.2, load over motor
/// inertia 0.5–3, the rigid body's time constant 10–40 samples, the play `α = level ×
/// K u_max / k`. Returns the drive and its sample time (0.3–0.7 rad of the resonance per
/// sample).
fn two_mass(rng: &mut Rng, level: f64, u_abs: f64) -> (TwoMass, f64) {
    let jm = 1e-3 * rng.log_between(0.5, 2.0);
    let jl = jm * rng.between(0.5, 3.0);
    let wr = rng.log_between(30.0, 200.0);
    let ts = round_sig(rng.between(0.3, 0.7) / wr);
    let j_eff = jm * jl / (jm + jl);
    let stiffness = wr * wr * j_eff;
    let shaft_damping = 2.0 * rng.between(0.05, 0.2) * wr * j_eff;
    let b = (jm + jl) / (ts * rng.between(10.0, 40.0));
    let q = rng.between(0.3, 0.7);
    let gain = b * rng.log_between(0.3, 3.0);
    let d = TwoMass {
        gain,
        motor_inertia: jm,
        load_inertia: jl,
        motor_damping: q * b,
        load_damping: (1.0 - q) * b,
        stiffness,
        shaft_damping,
        half_play: level * gain * u_abs / stiffness,
    };
    (d, ts)
}

/// `t` to three significant digits.
fn round_sig(t: f64) -> f64 {
    let e = 10f64.powf(t.log10().floor() - 2.0);
    (t / e).round() * e
}

impl Scenario {
    /// A scenario.
    pub fn new(class: Class, lp: Loop, seed: u64) -> Self {
        Self { class, lp, seed }
    }

    fn index(&self) -> u64 {
        Class::ALL
            .iter()
            .position(|&c| c == self.class)
            .unwrap_or(0) as u64
    }

    /// The random stream `stream` of this scenario.
    pub fn rng(&self, stream: u64) -> Rng {
        let lp = u64::from(self.lp == Loop::Closed);
        Rng::new(
            self.seed ^ (self.index() << 40) ^ (lp << 50) ^ 0xC0FF_EE00_0000_0000,
            stream,
        )
    }

    /// The design. The servo's kind, the input's kind and the class's level cycle with the
    /// seed (offset by the class, so that a few seeds meet every combination); the rest is
    /// drawn.
    pub fn design(&self) -> Design {
        let mut rng = self.rng(0);
        let s = self.seed.saturating_sub(1) + self.index();
        let range = (rng.between(-3.0, -1.0), rng.between(1.0, 3.0));
        let u_abs = range.0.abs().max(range.1.abs());
        let cycle = |n: usize| (s % n as u64) as usize;
        let level = match self.class {
            Class::Clean => 0.0,
            Class::Friction => COULOMB_LEVELS[cycle(4)],
            Class::PlayBetween => PLAY_BETWEEN_LEVELS[cycle(4)],
            Class::InputPlay => INPUT_PLAY_LEVELS[cycle(4)],
            Class::EndStop => rng.between(0.03, 0.15),
        };
        // Speed or spring, with or without actuator: (s / 4) so that the level's cycle and
        // the servo's are not locked together.
        let shape = ((s / 4) + s) % 4;
        let (spring, actuator) = match self.class {
            Class::EndStop => (true, shape % 2 == 1),
            _ => (shape >= 2, shape % 2 == 1),
        };
        let (mechanics, ts, plant) = if self.class == Class::PlayBetween {
            let (d, ts) = two_mass(&mut rng, level, u_abs);
            let words = format!(
                "two-mass {:.0} rad/s J_l/J_m {:.1}",
                d.resonance(),
                d.load_inertia / d.motor_inertia
            );
            (Mechanics::TwoMass(d), ts, words)
        } else {
            let mut m = axis(&mut rng, spring, actuator);
            if self.class == Class::Friction {
                m.coulomb = level * m.gain * u_abs;
            }
            let ratio = rng.log_between(3.0, 12.0);
            let ts = round_ts(m.dominant_time() / ratio);
            let words = format!(
                "{}{}",
                if spring { "spring" } else { "speed" },
                if actuator { "+actuator" } else { "" }
            );
            (Mechanics::Mass(m), ts, words)
        };
        let servo = Servo {
            mechanics,
            input_play: (self.class == Class::InputPlay)
                .then_some(0.5 * level * (range.1 - range.0)),
        };
        let input = match self.lp {
            Loop::Open => InputKind::ALL[cycle(4)],
            Loop::Closed => [InputKind::Levels, InputKind::Multisine][cycle(2)],
        };
        let level_hold = 1 + rng.below(3);
        let snr_db = rng.between(20.0, 40.0);
        let colour = if self.class != Class::Clean && rng.chance(1.0 / 3.0) {
            Colour::Ar1(rng.between(0.5, 0.9))
        } else {
            Colour::White
        };
        let controller = match self.lp {
            Loop::Open => None,
            Loop::Closed if rng.chance(1.0 / 3.0) => Some(ControllerKind::P),
            Loop::Closed => Some(ControllerKind::Pi),
        };
        let loop_gain = match controller {
            Some(ControllerKind::P) => (rng.between(1.0, 3.0), 0.0),
            _ => (rng.between(0.3, 1.0), rng.between(0.7, 1.5)),
        };
        let pin = (self.class == Class::EndStop).then(|| {
            let kind = if s.is_multiple_of(2) {
                Pin::Sensor
            } else {
                Pin::Stop
            };
            (kind, level)
        });
        Design {
            servo,
            ts,
            range,
            input,
            level_hold,
            snr_db,
            colour,
            controller,
            loop_gain,
            pin,
            level,
            plant,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sample_times_round_to_one_two_five() {
        assert_eq!(round_ts(0.0031), 0.002);
        assert_eq!(round_ts(0.0037), 0.005);
        assert_eq!(round_ts(0.08), 0.1);
        assert!((round_sig(0.0123456) - 0.0123).abs() < 1e-12);
    }

    #[test]
    fn designs_are_reproducible_and_sampled_near_the_dynamics() {
        for class in Class::ALL {
            for lp in Loop::ALL {
                for seed in 1..=8 {
                    let s = Scenario::new(class, lp, seed);
                    let d = s.design();
                    assert_eq!(d, s.design());
                    let tau = d.tau_samples();
                    assert!((1.5..=60.0).contains(&tau), "{class:?} {seed}: {tau}");
                    assert!(d.range.0 < 0.0 && d.range.1 > 0.0);
                    assert_eq!(d.controller.is_some(), lp == Loop::Closed);
                }
            }
        }
    }
}
