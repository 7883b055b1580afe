//! The plant behind a small "apply u, read y" interface, and its stand-in.
//!
//! On a real board [`Plant::apply`] writes the actuator command (a PWM duty cycle, a DAC code)
//! and [`Plant::read`] samples the sensor (an encoder count, an ADC conversion), both scaled to
//! engineering units. Here [`SimulatedServo`] stands in for the hardware: the paper's backlash
//! example (Section IV-B) computed on the target. To run on hardware, implement [`Plant`] for
//! the board's peripherals and change [`plant`] (the one place that picks the plant).

use libm::atanf;
use rand_core::{Rng, SeedableRng};
use rand_pcg::Pcg32;

/// An actuator driven by `u` whose response `y` is measured once per sample period.
pub trait Plant {
    /// Applies the input `u(t)` (holds it until the next call).
    fn apply(&mut self, u: f32);
    /// Reads the output `y(t)` for the sample whose input was the last [`Plant::apply`].
    fn read(&mut self) -> f32;
}

/// The plant the firmware identifies. **The one place to change for real hardware**: return
/// the board's implementation of [`Plant`] instead (e.g. a PWM channel and an encoder).
pub fn plant() -> impl Plant {
    SimulatedServo::new(NOISE_SEED)
}

/// Seed of the stand-in's output-noise generator (a `Pcg32::seed_from_u64` seed).
pub const NOISE_SEED: u64 = 0x5EED_0015;

/// Amplitude of the stand-in's output noise: `v(t) = a·(r₁ + r₂ − 1)` with `r₁, r₂` uniform on
/// [0, 1), a triangular density on (−a, a), standard deviation `a/√6 ≈ 0.008`.
pub const NOISE_AMPLITUDE: f32 = 0.02;

/// Descending border `H_d(u) = atan(u + 1)` (paper, Section IV-B).
pub fn border_descending(u: f32) -> f32 {
    atanf(u + 1.0)
}

/// Ascending border `H_a(u) = atan(u − 1)` (paper, Section IV-B).
pub fn border_ascending(u: f32) -> f32 {
    atanf(u - 1.0)
}

/// Stand-in servo: a backlash element with memory followed by the paper's linear part,
///
/// ```text
/// w(t) = min(max(w(t−1), H_a(u(t))), H_d(u(t)))          (play operator, general borders)
/// y(t) = G(q) w(t) + v(t),  G(q) = q⁻¹ (0.1994 − 0.1804 q⁻¹) / (1 − 1.8858 q⁻¹ + 0.9048 q⁻²)
/// ```
///
/// `G` is strictly proper (one sample of delay) with unit static gain, realised in direct form:
/// `x(t) = 1.8858 x(t−1) − 0.9048 x(t−2) + 0.1994 w(t−1) − 0.1804 w(t−2)`, `y(t) = x(t) + v(t)`.
/// `v` is small pseudo-random noise from the servo's own [`Pcg32`].
pub struct SimulatedServo {
    /// Backlash output `w(t−1)`.
    w1: f32,
    /// Backlash output `w(t−2)`.
    w2: f32,
    /// Noise-free output `x(t−1)`.
    x1: f32,
    /// Noise-free output `x(t−2)`.
    x2: f32,
    /// Noise-free output `x(t)` of the current sample.
    x: f32,
    /// Output noise generator.
    rng: Pcg32,
}

impl SimulatedServo {
    const A1: f32 = 1.8858;
    const A2: f32 = -0.9048;
    const B1: f32 = 0.1994;
    const B2: f32 = -0.1804;

    /// A servo at rest (`w = 0`, zero output), noise seeded with `noise_seed`.
    pub fn new(noise_seed: u64) -> Self {
        Self {
            w1: 0.0,
            w2: 0.0,
            x1: 0.0,
            x2: 0.0,
            x: 0.0,
            rng: Pcg32::seed_from_u64(noise_seed),
        }
    }

    /// Uniform on [0, 1) with 24 bits.
    fn uniform(&mut self) -> f32 {
        (self.rng.next_u32() >> 8) as f32 * (1.0 / 16_777_216.0)
    }
}

impl Plant for SimulatedServo {
    fn apply(&mut self, u: f32) {
        // The output of this sample depends on past backlash outputs only (G is strictly proper).
        let x = Self::A1 * self.x1 + Self::A2 * self.x2 + Self::B1 * self.w1 + Self::B2 * self.w2;
        let w = self.w1.max(border_ascending(u)).min(border_descending(u));
        self.x2 = self.x1;
        self.x1 = x;
        self.x = x;
        self.w2 = self.w1;
        self.w1 = w;
    }

    fn read(&mut self) -> f32 {
        let v = NOISE_AMPLITUDE * (self.uniform() + self.uniform() - 1.0);
        self.x + v
    }
}
