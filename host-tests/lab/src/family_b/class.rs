//! The scenario classes and, in one place, what the diagnosis must do on each to count as
//! "named right".

use hsid_host::diagnose::{Check, Effect};

/// The true class of a scenario: clean, one catalog effect, or one of the classes beyond it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Class {
    /// No effect: the model class fits.
    Clean,
    /// A sensor warm-up drift `D (1 − e^{−t/T})`.
    Drift,
    /// Extra transport delay of 2–4 samples.
    Delay,
    /// An undeclared sensor lag (one real pole more than declared), its time constant
    /// 0.4–0.8 × the plant's slowest.
    ExtraPole,
    /// A smooth monotone sensor curve `c + s tanh((y − c)/s)`.
    OutputCurve,
    /// A sinusoidal disturbance.
    Periodic,
    /// AR(1) or MA(2) noise instead of white.
    ColouredNoise,
    /// 1 % spikes of 6–12 σ_v.
    Outliers,
    /// A backlash or switch behind an ordinary input, diagnosed with a static nonlinearity.
    StaticHysteresis,
    /// The input computed by a PI controller from the measured output.
    ClosedLoop,
    /// An integrator in the plant.
    Integrating,
    /// The measured output clipped at its 85th percentile.
    Saturation,
}

/// What counts as named right.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Expect {
    /// No effect added.
    Nothing,
    /// This effect named first.
    First(Effect),
    /// This data check fires (whatever is named).
    Fires(Check),
}

impl Class {
    /// Every class, clean first.
    pub const ALL: [Class; 12] = [
        Class::Clean,
        Class::Drift,
        Class::Delay,
        Class::ExtraPole,
        Class::OutputCurve,
        Class::Periodic,
        Class::ColouredNoise,
        Class::Outliers,
        Class::StaticHysteresis,
        Class::ClosedLoop,
        Class::Integrating,
        Class::Saturation,
    ];

    /// Lower-case name.
    pub fn name(self) -> &'static str {
        match self {
            Class::Clean => "clean",
            Class::Drift => "drift",
            Class::Delay => "delay",
            Class::ExtraPole => "extra_pole",
            Class::OutputCurve => "output_curve",
            Class::Periodic => "periodic",
            Class::ColouredNoise => "coloured_noise",
            Class::Outliers => "outliers",
            Class::StaticHysteresis => "static_hysteresis",
            Class::ClosedLoop => "closed_loop",
            Class::Integrating => "integrating",
            Class::Saturation => "saturation",
        }
    }

    /// The definition of "named right": nothing added on clean data; the catalog effect
    /// that models the class named first (`hysteresis` for the element behind a static
    /// model, `output_nonlinearity` for the clipped output as for the sensor curve); for a
    /// closed loop and an integrating plant, whose models are outside the catalog, the data
    /// check that says so (`feedback`, `integrating`) fires.
    pub fn expect(self) -> Expect {
        match self {
            Class::Clean => Expect::Nothing,
            Class::Drift => Expect::First(Effect::OffsetDrift),
            Class::Delay => Expect::First(Effect::InputDelay),
            Class::ExtraPole => Expect::First(Effect::UnmodeledDynamics),
            Class::OutputCurve | Class::Saturation => Expect::First(Effect::OutputNonlinearity),
            Class::Periodic => Expect::First(Effect::PeriodicDisturbance),
            Class::ColouredNoise => Expect::First(Effect::ColoredNoise),
            Class::Outliers => Expect::First(Effect::Outliers),
            Class::StaticHysteresis => Expect::First(Effect::Hysteresis),
            Class::ClosedLoop => Expect::Fires(Check::Feedback),
            Class::Integrating => Expect::Fires(Check::Integrating),
        }
    }

    /// Whether a diagnosis that named `first` first, with the data checks `fired`, is right.
    pub fn named_right(self, first: Option<Effect>, fired: &[Check]) -> bool {
        match self.expect() {
            Expect::Nothing => first.is_none(),
            Expect::First(e) => first == Some(e),
            Expect::Fires(c) => fired.contains(&c),
        }
    }
}
