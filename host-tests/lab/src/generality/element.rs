//! Random input elements unlike the paper's: a backlash (play operator) whose centre line is a
//! cubic, or a switch whose borders open into a lens between `u_min` and `u_max`.

use rand::{Rng, RngExt};

use hsid_host::model::MemoryElement;
use hsid_host::sim::{Backlash, Nonlinearity, Switch};

/// The parameters of a random element on `[u_min, u_max]`.
#[derive(Clone, Copy, Debug)]
pub struct Element {
    /// Backlash or switch.
    pub kind: MemoryElement,
    /// Input interval.
    pub u_min: f64,
    /// Input interval.
    pub u_max: f64,
    /// Centre line `m(u) = s · (u + a u³ / r²)`, `r` the interval's half width.
    pub slope: f64,
    /// Cubic coefficient `a ∈ [0, 0.5]`.
    pub cubic: f64,
    /// Backlash: half the play `h`; switch: the lens' half height `o₀`.
    pub width: f64,
}

impl Element {
    /// The centre line `m(u)`.
    pub fn centre(&self, u: f64) -> f64 {
        let r = 0.5 * (self.u_max - self.u_min);
        let c = 0.5 * (self.u_max + self.u_min);
        let x = u - c;
        self.slope * (x + self.cubic * x * x * x / (r * r))
    }

    /// The element, ready to simulate (a backlash starts at rest on its falling border at
    /// `u_min`, as after the hold).
    pub fn build(&self) -> Box<dyn Nonlinearity> {
        let e = *self;
        match self.kind {
            MemoryElement::Play => {
                let w0 = e.centre(e.u_min + e.width);
                Box::new(
                    Backlash::from_fns(
                        move |u| e.centre(u - e.width),
                        move |u| e.centre(u + e.width),
                    )
                    .with_initial_output(w0),
                )
            }
            MemoryElement::Relay => {
                let lens = move |u: f64| {
                    e.width * (std::f64::consts::PI * (u - e.u_min) / (e.u_max - e.u_min)).sin()
                };
                Box::new(Switch::from_fns(
                    move |u| e.centre(u) - lens(u),
                    move |u| e.centre(u) + lens(u),
                ))
            }
        }
    }

    /// The true gap of a backlash (`2h`), 0 for a switch.
    pub fn gap(&self) -> f64 {
        match self.kind {
            MemoryElement::Play => 2.0 * self.width,
            MemoryElement::Relay => 0.0,
        }
    }
}

/// Draws an element on `[u_min, u_max]`: slope ±[0.5, 2], cubic `[0, 0.5]`, a play of
/// 4–20 % of the interval (backlash) or a lens of 10–40 % of the centre line's range (switch).
pub fn random_element<R: Rng + ?Sized>(
    rng: &mut R,
    kind: MemoryElement,
    u_min: f64,
    u_max: f64,
) -> Element {
    let sign = if rng.random_bool(0.5) { 1.0 } else { -1.0 };
    let slope = sign * rng.random_range(0.5..2.0);
    let cubic = rng.random_range(0.0..0.5);
    let range = u_max - u_min;
    let mut e = Element {
        kind,
        u_min,
        u_max,
        slope,
        cubic,
        width: 0.0,
    };
    e.width = match kind {
        MemoryElement::Play => rng.random_range(0.02..0.10) * range,
        MemoryElement::Relay => {
            let span = (e.centre(u_max) - e.centre(u_min)).abs();
            rng.random_range(0.05..0.20) * span
        }
    };
    e
}
