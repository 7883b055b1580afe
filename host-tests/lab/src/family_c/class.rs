//! The classes of the family, open or closed loop, and in one place what the diagnosis must
//! do on each to count as named right.

use hsid_host::diagnose::Effect;

/// The true class of a scenario.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Class {
    /// A linear servo (motor speed, or a spring–mass–damper's position; order 1–3).
    Clean,
    /// Coulomb and viscous friction on a stable axis (motor speed, or a mass on a spring).
    Friction,
    /// A two-mass drive with gear play between motor and load, the motor's speed measured.
    PlayBetween,
    /// Play (backlash) at the input of a linear servo, diagnosed with a static element.
    InputPlay,
    /// The position pinned at an upper end stop or by a saturating sensor in 3–15 % of the
    /// samples.
    EndStop,
}

/// Open or closed loop.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Loop {
    /// The command is the designed input.
    Open,
    /// A P or PI controller computes the command from the noisy output and a reference.
    Closed,
}

impl Loop {
    /// Both, open first.
    pub const ALL: [Loop; 2] = [Loop::Open, Loop::Closed];

    /// `open` or `closed`.
    pub fn name(self) -> &'static str {
        match self {
            Loop::Open => "open",
            Loop::Closed => "closed",
        }
    }
}

/// What counts as named right.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Expect {
    /// No effect added (`Diagnosis::steps` empty).
    Nothing,
    /// This catalog name's effect named first; when the library has no effect of that name
    /// ([`Effect::from_name`] gives `None`), nothing is right.
    First(&'static str),
}

impl Class {
    /// Every class, clean first.
    pub const ALL: [Class; 5] = [
        Class::Clean,
        Class::Friction,
        Class::PlayBetween,
        Class::InputPlay,
        Class::EndStop,
    ];

    /// Lower-case name.
    pub fn name(self) -> &'static str {
        match self {
            Class::Clean => "clean",
            Class::Friction => "friction",
            Class::PlayBetween => "play_between",
            Class::InputPlay => "input_play",
            Class::EndStop => "end_stop",
        }
    }

    /// The class of a name.
    pub fn from_name(name: &str) -> Option<Class> {
        Class::ALL.into_iter().find(|c| c.name() == name)
    }

    /// What the diagnosis must do: nothing on a clean servo; `friction` first on friction;
    /// `play_between` first on the two-mass drive with play; `hysteresis` first on the play
    /// at the input behind a static element; `output_nonlinearity` first on the pinned
    /// output. The same in closed loop.
    pub fn expect(self) -> Expect {
        match self {
            Class::Clean => Expect::Nothing,
            Class::Friction => Expect::First("friction"),
            Class::PlayBetween => Expect::First("play_between"),
            Class::InputPlay => Expect::First("hysteresis"),
            Class::EndStop => Expect::First("output_nonlinearity"),
        }
    }

    /// The effect that models the class, when the library has it (`None` for clean, and for
    /// a name the library does not know yet).
    pub fn effect(self) -> Option<Effect> {
        match self.expect() {
            Expect::Nothing => None,
            Expect::First(name) => Effect::from_name(name),
        }
    }

    /// Whether a diagnosis that added `steps` (in order) is right.
    pub fn named_right(self, steps: &[Effect]) -> bool {
        match self.expect() {
            Expect::Nothing => steps.is_empty(),
            Expect::First(_) => self.effect().is_some_and(|e| steps.first() == Some(&e)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn named_right_by_the_first_step() {
        assert!(Class::Clean.named_right(&[]));
        assert!(!Class::Clean.named_right(&[Effect::ColoredNoise]));
        assert!(Class::Friction.named_right(&[Effect::Friction, Effect::Outliers]));
        assert!(!Class::Friction.named_right(&[Effect::Outliers, Effect::Friction]));
        assert!(!Class::InputPlay.named_right(&[]));
        assert!(Class::InputPlay.named_right(&[Effect::Hysteresis]));
        assert!(Class::EndStop.named_right(&[Effect::OutputNonlinearity]));
        // The play between is right only by the library's own effect of that name.
        let e = Effect::from_name("play_between");
        assert_eq!(Class::PlayBetween.effect(), e);
        assert_eq!(
            Class::PlayBetween.named_right(&[Effect::Hysteresis]),
            e == Some(Effect::Hysteresis)
        );
        for c in Class::ALL {
            assert_eq!(Class::from_name(c.name()), Some(c));
        }
    }
}
