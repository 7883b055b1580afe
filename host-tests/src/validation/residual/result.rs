//! The tests' names, results and inputs.

use serde::Serialize;

use crate::validation::stats::normal_sf;

/// Significance level of every test.
pub const LEVEL: f64 = 0.01;

/// The residual tests (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Test {
    /// Ljung–Box on the autocorrelation.
    Whiteness,
    /// Cross-correlation with the prewhitened input.
    InputCorrelation,
    /// Cross-correlation with the direction δ.
    DirectionCorrelation,
    /// Cross-correlation with the regressor channels.
    RegressorCorrelation,
    /// Binned means per path and knot segment.
    StructureInput,
    /// Binned means in deciles of the simulated output.
    StructureOutput,
    /// Slope and mean over time.
    Trend,
    /// Largest periodogram ordinate against the local median spectrum.
    SpectralLine,
    /// Correlation with the level times the increment of the simulated output.
    StateDependence,
    /// Count of samples beyond 5 robust σ.
    HeavyTails,
}

impl Test {
    /// The test's name, as in the reports.
    pub fn name(self) -> &'static str {
        match self {
            Test::Whiteness => "whiteness",
            Test::InputCorrelation => "input_correlation",
            Test::DirectionCorrelation => "direction_correlation",
            Test::RegressorCorrelation => "regressor_correlation",
            Test::StructureInput => "structure_input",
            Test::StructureOutput => "structure_output",
            Test::Trend => "trend",
            Test::SpectralLine => "spectral_line",
            Test::StateDependence => "state_dependence",
            Test::HeavyTails => "heavy_tails",
        }
    }
}

impl std::fmt::Display for Test {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.pad(self.name())
    }
}

/// One test's outcome.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TestResult {
    /// Which test.
    pub name: Test,
    /// Test statistic.
    pub statistic: f64,
    /// Critical value at the 1 % level.
    pub threshold: f64,
    /// p-value (approximate where stated).
    pub p_value: f64,
    /// `p < 0.01`.
    pub fired: bool,
    /// What the statistic found, in words.
    pub detail: String,
}

/// Series behind the figures.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Curves {
    /// Residual autocorrelation `ρ(k)`, `k = 0…K`.
    pub acf: Vec<f64>,
    /// White-noise 99 % bound `2.58/√N` of the autocorrelation.
    pub acf_bound: f64,
    /// Cross-correlation input–residual, lags `−K…K`.
    pub ccf_input: Vec<f64>,
    /// Its 99 % bounds per lag (Bartlett corrected).
    pub ccf_input_bound: Vec<f64>,
    /// Cross-correlation δ–residual, lags `−K…K`.
    pub ccf_direction: Vec<f64>,
    /// Its 99 % bounds.
    pub ccf_direction_bound: Vec<f64>,
    /// Periodogram frequencies (rad/sample).
    pub omega: Vec<f64>,
    /// Periodogram of the residual.
    pub power: Vec<f64>,
    /// Local median spectrum (the smooth-spectrum estimate of the line test).
    pub power_median: Vec<f64>,
    /// 99 % threshold of the line test per frequency.
    pub power_threshold: Vec<f64>,
}

/// All tests of one residual.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct TestSet {
    /// Samples tested.
    pub samples: usize,
    /// Residual RMS.
    pub rms: f64,
    /// The tests.
    pub tests: Vec<TestResult>,
    /// Lag (samples) of the strongest input–residual correlation; positive: the residual
    /// follows the input.
    pub strongest_input_lag: i64,
    /// Whether that correlation is outside its 99 % bound.
    pub strongest_input_lag_significant: bool,
    /// Lag of the strongest regressor–residual correlation (lags `0…K`).
    pub strongest_regressor_lag: i64,
    /// Lag of the strongest input–residual correlation without prewhitening (lags `0…K`).
    pub strongest_input_lag_raw: i64,
    /// Frequency (rad/sample) of the strongest residual spectral line.
    pub line_frequency: f64,
    /// Figure data.
    #[serde(skip)]
    pub curves: Curves,
}

impl TestSet {
    /// The result of this test.
    pub fn get(&self, test: Test) -> Option<&TestResult> {
        self.tests.iter().find(|t| t.name == test)
    }

    /// Whether this test fired.
    pub fn fired(&self, test: Test) -> bool {
        self.get(test).is_some_and(|t| t.fired)
    }

    /// Names of the tests that fired.
    pub fn fired_names(&self) -> Vec<String> {
        self.tests
            .iter()
            .filter(|t| t.fired)
            .map(|t| t.name.name().to_string())
            .collect()
    }
}

/// What the tests need: the residual and, over the same samples, the input, the direction
/// δ, the regressor channels and the simulated output.
#[derive(Clone, Copy, Debug)]
pub struct ResidualInput<'a> {
    /// Residual.
    pub residual: &'a [f64],
    /// Input.
    pub u: &'a [f64],
    /// Direction δ(t) (1 ascending, 0 descending).
    pub delta: &'a [f64],
    /// Regressor channels (hat basis on the model's knots).
    pub regressor: &'a [Vec<f64>],
    /// Path bins: `(path, segment)` of every sample, for the structure test.
    pub bins: &'a [usize],
    /// Number of distinct bins.
    pub bin_count: usize,
    /// Simulated output.
    pub simulated: &'a [f64],
}

/// The result of test `name`: fired when `p` is below [`LEVEL`] (`p` clamped to `[0, 1]`).
pub fn result(name: Test, statistic: f64, threshold: f64, p: f64, detail: String) -> TestResult {
    TestResult {
        name,
        statistic,
        threshold,
        p_value: p.clamp(0.0, 1.0),
        fired: p < LEVEL,
        detail,
    }
}

/// Bonferroni p-value of the largest of `m` two-sided normal statistics.
pub(crate) fn max_normal_p(stat: f64, m: usize) -> f64 {
    (2.0 * normal_sf(stat) * m as f64).min(1.0)
}
