//! The family's servos: a rigid axis ([`Mass`]) or a two-mass drive ([`TwoMass`]), with an
//! optional play operator at the command's input, simulated one sample at a time so that a
//! controller can close the loop around them.

use super::mass::{Mass, MassState};
use super::two_mass::{TwoMass, TwoMassState};

/// The mechanics.
#[derive(Clone, Debug, PartialEq)]
pub enum Mechanics {
    /// A rigid axis.
    Mass(Mass),
    /// A two-mass drive.
    TwoMass(TwoMass),
}

/// The play operator (backlash) on the sampled command, half-width `h`:
/// `w(t) = min(max(w(t − 1), u(t) − h), u(t) + h)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Play {
    /// Half the play, command units.
    pub half: f64,
    /// The output held.
    pub w: f64,
}

impl Play {
    /// A play of half-width `half` at rest after the command came down to `u` (on its
    /// descending flank, `w = u + h`).
    pub fn at_rest(half: f64, u: f64) -> Self {
        Self { half, w: u + half }
    }

    /// The output for the next command.
    pub fn next(&mut self, u: f64) -> f64 {
        self.w = self.w.max(u - self.half).min(u + self.half);
        self.w
    }
}

/// A servo: mechanics behind an optional play at its input.
#[derive(Clone, Debug, PartialEq)]
pub struct Servo {
    /// The mechanics.
    pub mechanics: Mechanics,
    /// Half the play at the input, when there is one.
    pub input_play: Option<f64>,
}

/// The state of a running servo.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Running {
    mech: State,
    play: Option<Play>,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum State {
    Mass(MassState),
    TwoMass(TwoMassState),
}

impl Servo {
    /// At rest under the constant command `u`.
    pub fn rest(&self, u: f64) -> Running {
        let play = self.input_play.map(|h| Play::at_rest(h, u));
        let w = play.map_or(u, |p| p.w);
        let mech = match &self.mechanics {
            Mechanics::Mass(m) => State::Mass(m.rest(w)),
            Mechanics::TwoMass(d) => State::TwoMass(d.rest(w)),
        };
        Running { mech, play }
    }

    /// The measured quantity (without noise) now.
    pub fn output(&self, r: &Running) -> f64 {
        match (&self.mechanics, &r.mech) {
            (Mechanics::Mass(m), State::Mass(s)) => m.output(s),
            (Mechanics::TwoMass(d), State::TwoMass(s)) => d.output(s),
            _ => f64::NAN,
        }
    }

    /// One sample of the command `u`, held `ts` seconds.
    pub fn advance(&self, r: &mut Running, u: f64, ts: f64) {
        let w = match &mut r.play {
            Some(p) => p.next(u),
            None => u,
        };
        match (&self.mechanics, &mut r.mech) {
            (Mechanics::Mass(m), State::Mass(s)) => m.advance(s, w, ts),
            (Mechanics::TwoMass(d), State::TwoMass(s)) => d.advance(s, w, ts),
            _ => {}
        }
    }

    /// The noise-free open-loop response to `u`, at rest under `u[0]` before it.
    pub fn simulate(&self, u: &[f64], ts: f64) -> Vec<f64> {
        let mut r = self.rest(u.first().copied().unwrap_or(0.0));
        u.iter()
            .map(|&v| {
                let y = self.output(&r);
                self.advance(&mut r, v, ts);
                y
            })
            .collect()
    }

    /// The plant's order (the play adds none).
    pub fn order(&self) -> usize {
        match &self.mechanics {
            Mechanics::Mass(m) => m.order(),
            Mechanics::TwoMass(d) => d.order(),
        }
    }

    /// The same servo without play, friction and end stop.
    pub fn linear(&self) -> Servo {
        Servo {
            mechanics: match &self.mechanics {
                Mechanics::Mass(m) => Mechanics::Mass(m.linear()),
                Mechanics::TwoMass(d) => Mechanics::TwoMass(d.linear()),
            },
            input_play: None,
        }
    }

    /// The dominant time constant, s.
    pub fn dominant_time(&self) -> f64 {
        match &self.mechanics {
            Mechanics::Mass(m) => m.dominant_time(),
            Mechanics::TwoMass(d) => d.dominant_time(),
        }
    }

    /// The static gain of the linear servo.
    pub fn static_gain(&self) -> f64 {
        match &self.mechanics {
            Mechanics::Mass(m) => m.static_gain(),
            Mechanics::TwoMass(d) => d.static_gain(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn play_holds_inside_the_gap_and_follows_outside() {
        let mut p = Play::at_rest(0.5, -1.0);
        assert_eq!(p.w, -0.5);
        // Up within the gap: held.
        assert_eq!(p.next(-0.2), -0.5);
        // Beyond it: the ascending flank u − h.
        assert_eq!(p.next(1.0), 0.5);
        // Back down by less than the gap: held; further: the descending flank u + h.
        assert_eq!(p.next(0.2), 0.5);
        assert!((p.next(-0.8) + 0.3).abs() < 1e-12);
    }
}
