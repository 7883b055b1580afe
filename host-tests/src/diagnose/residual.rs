//! Statistical tests of a residual against the model's assumptions, each at the 1 % level
//! (99 % bounds):
//!
//! | test | statistic | reference distribution under "nothing missing" |
//! |---|---|---|
//! | `whiteness` | Ljung–Box `Q = N(N+2) Σ_{k≤K} ρ̂(k)²/(N−k)` | χ²(K) |
//! | `input_correlation` | max over lags `−K…K` of `|r̂_uε(k)| / σ_k`, input prewhitened | normal, Bonferroni over the lags |
//! | `direction_correlation` | the same with δ(t) | idem |
//! | `regressor_correlation` | max over channels `z_i` and lags `0…K` | idem |
//! | `structure_input` | binned means of ε per path and knot segment | χ²(bins − 1) |
//! | `structure_output` | binned means of ε in deciles of the simulated output | χ²(9) |
//! | `trend` | slope and mean of ε over time, Newey–West standard errors | normal, two tests |
//! | `spectral_line` | largest Hann periodogram ordinate / local median spectrum | exponential, max of M |
//! | `state_dependence` | max over lags `0…K` of the correlation of ε with `(ŷ − ȳ)·Δŷ` (ŷ the simulated output, the product's part not explained by `1, ŷ, Δŷ`), prewhitened | normal, Bonferroni over the lags |
//! | `heavy_tails` | count of |ε − median| beyond 5 robust σ (1.4826 MAD) | Poisson(N · 5.7e-7) |
//!
//! The cross-correlations are computed after prewhitening (an AR model of the input filters
//! both signals), and `σ_k² = (1 + 2 Σ_j ρ_ε(j) ρ_x(j)) / N` (Bartlett) corrects their bounds
//! for what colour remains; the plain white-noise bound is `2.58/√N`. Binned means use
//! the residual's autocorrelation for their variances. Spectral lines shared with the input
//! (the Table I excitation has lines at π/2 and π) are not counted: they are input effects.

use serde::Serialize;

use super::stats::{
    acf, ccf, ccf_sigma, chi2_quantile, chi2_sf, excess_kurtosis, mad_sigma, mean,
    newey_west_var_of_mean, normal_quantile, normal_sf, periodogram, poisson_sf, running_median,
};

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

/// Hat-basis regressor channels, δ and the (path, segment) bin of every sample.
pub fn regressor(
    u: &[f64],
    knots_asc: &[f64],
    knots_desc: &[f64],
    shared: bool,
) -> (Vec<f64>, Vec<Vec<f64>>, Vec<usize>, usize) {
    let na = knots_asc.len().saturating_sub(1).max(1);
    let nd = knots_desc.len().saturating_sub(1).max(1);
    let channels = if shared { na } else { na + nd };
    let mut z = vec![vec![0.0; u.len()]; channels];
    let mut delta = Vec::with_capacity(u.len());
    let mut bins = Vec::with_capacity(u.len());
    let mut up = false;
    let mut prev = knots_asc.first().copied().unwrap_or(0.0);
    for (t, &ui) in u.iter().enumerate() {
        if ui > prev {
            up = true;
        } else if ui < prev {
            up = false;
        }
        prev = ui;
        let (k, off) = if up || shared {
            (knots_asc, 0)
        } else {
            (knots_desc, na)
        };
        let segs = k.len().saturating_sub(1).max(1);
        let s = k
            .iter()
            .rposition(|&x| x <= ui)
            .unwrap_or(0)
            .min(segs.saturating_sub(1));
        let th = if k.len() >= 2 {
            ((ui - k[s]) / (k[s + 1] - k[s])).clamp(0.0, 1.0)
        } else {
            0.0
        };
        if s >= 1 {
            z[off + s - 1][t] = 1.0 - th;
        }
        z[off + s][t] = th;
        delta.push(if up { 1.0 } else { 0.0 });
        bins.push(off + s);
    }
    (delta, z, bins, channels)
}

fn max_lag(n: usize) -> usize {
    (n / 10).clamp(2, 25)
}

/// Prewhitening (Box–Jenkins): an AR model of the input (order by BIC, at most 10) filters
/// both the input and the residual, so that the cross-correlation of the filtered pair is
/// that of a white input, with bounds near `±2.58/√N` and its peak at the input's delay.
fn prewhiten(x: &[f64], r: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let m = mean(x);
    let xc: Vec<f64> = x.iter().map(|v| v - m).collect();
    let Some(p) = super::noise::ar_order_bic(&xc, 10) else {
        return (x.to_vec(), r.to_vec());
    };
    let Some(ar) = super::noise::fit_ar(&xc, p) else {
        return (x.to_vec(), r.to_vec());
    };
    let filt = |v: &[f64]| -> Vec<f64> {
        (p..v.len())
            .map(|t| {
                v[t] - ar
                    .a
                    .iter()
                    .enumerate()
                    .map(|(k, a)| a * v[t - 1 - k])
                    .sum::<f64>()
            })
            .collect()
    };
    (filt(&xc), filt(r))
}

/// Largest normalised cross-correlation over lags, after prewhitening the input;
/// `(stat, lag, values, bounds)`.
fn xcorr_test(
    x: &[f64],
    r: &[f64],
    _rho_r: &[f64],
    k: usize,
    causal: bool,
) -> (f64, i64, Vec<f64>, Vec<f64>) {
    let (x, r) = prewhiten(x, r);
    let (x, r) = (&x[..], &r[..]);
    let n = r.len();
    let c = ccf(x, r, k);
    let rho_x = acf(x, k);
    let rho_r = acf(r, k);
    let rho_r = &rho_r[..];
    let sigma = ccf_sigma(rho_r, &rho_x, n);
    let z99 = normal_quantile(1.0 - LEVEL / 2.0);
    let bounds = vec![z99 * sigma; c.len()];
    let mut best = (0.0, 0i64);
    for (i, v) in c.iter().enumerate() {
        let lag = i as i64 - k as i64;
        if causal && lag < 0 {
            continue;
        }
        let s = v.abs() / sigma;
        if s > best.0 {
            best = (s, lag);
        }
    }
    (best.0, best.1, c, bounds)
}

/// Variance-corrected binned means test: `(chi2, df)` or `None` with fewer than two bins.
fn binned_test(r: &[f64], bins: &[usize], count: usize, rho: &[f64]) -> Option<(f64, usize)> {
    let n = r.len();
    let var = super::stats::variance(r);
    let m = mean(r);
    let mut chi2 = 0.0;
    let mut used = 0;
    for b in 0..count {
        let idx: Vec<usize> = (0..n).filter(|&t| bins[t] == b).collect();
        let nb = idx.len();
        if nb < 10 {
            continue;
        }
        let mb = idx.iter().map(|&t| r[t]).sum::<f64>() / nb as f64;
        // Σ_{s,t ∈ b} ρ(s − t) = n_b + 2 Σ_k ρ(k) #{t ∈ b : t + k ∈ b}.
        let mut pairs = nb as f64;
        for (k, rk) in rho.iter().enumerate().skip(1) {
            let c = idx
                .iter()
                .filter(|&&t| t + k < n && bins[t + k] == b)
                .count();
            pairs += 2.0 * rk * c as f64;
        }
        let vb = var * pairs.max(0.2 * nb as f64) / (nb as f64 * nb as f64);
        if vb > 0.0 {
            chi2 += (mb - m) * (mb - m) / vb;
            used += 1;
        }
    }
    (used >= 2).then_some((chi2, used - 1))
}

fn result(name: Test, statistic: f64, threshold: f64, p: f64, detail: String) -> TestResult {
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
fn max_normal_p(stat: f64, m: usize) -> f64 {
    (2.0 * normal_sf(stat) * m as f64).min(1.0)
}

/// Local-median spectral line test on the periodogram: `(ratio, index, median curve)`.
fn line_scan(power: &[f64], exclude: &[bool]) -> (f64, usize, Vec<f64>) {
    let m = power.len();
    let w = (m / 20).clamp(16, 128);
    let med: Vec<f64> = running_median(power, 2 * w + 1);
    let mut best = (0.0, 0usize);
    for i in 0..m {
        if exclude[i] {
            continue;
        }
        let s = med[i] / std::f64::consts::LN_2;
        if s > 0.0 {
            let q = power[i] / s;
            if q > best.0 {
                best = (q, i);
            }
        }
    }
    (best.0, best.1, med)
}

/// `(ŷ − ȳ)·Δŷ` with its least-squares fit on `1, ŷ, Δŷ` removed; `None` for a constant
/// simulated output.
fn level_times_increment(sim: &[f64]) -> Option<Vec<f64>> {
    let n = sim.len();
    if n < 10 {
        return None;
    }
    let m = mean(sim);
    let d: Vec<f64> = (0..n)
        .map(|t| if t == 0 { 0.0 } else { sim[t] - sim[t - 1] })
        .collect();
    let w: Vec<f64> = (0..n).map(|t| (sim[t] - m) * d[t]).collect();
    let x = nalgebra::DMatrix::from_fn(n, 3, |t, c| match c {
        0 => 1.0,
        1 => sim[t] - m,
        _ => d[t],
    });
    let y = nalgebra::DVector::from_column_slice(&w);
    let beta = super::stats::lstsq(&x, &y)?;
    let e = &y - &x * beta;
    let out: Vec<f64> = e.iter().copied().collect();
    (super::stats::variance(&out) > 0.0 && out.iter().all(|v| v.is_finite())).then_some(out)
}

/// Runs every test on a residual.
pub fn run_tests(inp: &ResidualInput) -> TestSet {
    let r = inp.residual;
    let n = r.len();
    let mut set = TestSet {
        samples: n,
        rms: super::stats::rms(r),
        ..TestSet::default()
    };
    if n < 40 {
        return set;
    }
    let k = max_lag(n);
    let rho = acf(r, k);
    let z99 = normal_quantile(1.0 - LEVEL / 2.0);

    // Whiteness: Ljung–Box.
    let q: f64 = n as f64
        * (n as f64 + 2.0)
        * (1..=k)
            .map(|j| rho[j] * rho[j] / (n - j) as f64)
            .sum::<f64>();
    let outside = (1..=k)
        .filter(|&j| rho[j].abs() > z99 / (n as f64).sqrt())
        .count();
    set.tests.push(result(
        Test::Whiteness,
        q,
        chi2_quantile(1.0 - LEVEL, k as f64),
        chi2_sf(q, k as f64),
        format!(
            "Ljung–Box over {k} lags; {outside} of {k} autocorrelations outside ±2.58/√N; ρ(1) = {:.3}",
            rho[1]
        ),
    ));
    set.curves.acf = rho.clone();
    set.curves.acf_bound = z99 / (n as f64).sqrt();

    // Cross-correlations.
    let m_lags = 2 * k + 1;
    let crit = normal_quantile(1.0 - LEVEL / (2.0 * m_lags as f64));
    let (s_u, lag_u, c_u, b_u) = xcorr_test(inp.u, r, &rho, k, false);
    let p_u = max_normal_p(s_u, m_lags);
    set.strongest_input_lag = lag_u;
    set.strongest_input_lag_significant = s_u > z99;
    set.tests.push(result(
        Test::InputCorrelation,
        s_u,
        crit,
        p_u,
        format!(
            "strongest input–residual correlation at lag {lag_u} ({s_u:.2} σ; positive lag: the residual follows the input)"
        ),
    ));
    let raw = ccf(inp.u, r, k);
    set.strongest_input_lag_raw = raw
        .iter()
        .enumerate()
        .skip(k)
        .max_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))
        .map_or(0, |(i, _)| i as i64 - k as i64);
    set.curves.ccf_input = c_u;
    set.curves.ccf_input_bound = b_u;
    let (s_d, lag_d, c_d, b_d) = xcorr_test(inp.delta, r, &rho, k, false);
    set.tests.push(result(
        Test::DirectionCorrelation,
        s_d,
        crit,
        max_normal_p(s_d, m_lags),
        format!("strongest δ–residual correlation at lag {lag_d} ({s_d:.2} σ)"),
    ));
    set.curves.ccf_direction = c_d;
    set.curves.ccf_direction_bound = b_d;
    let mut best = (0.0, 0usize, 0i64);
    let mut tried = 0usize;
    for (i, z) in inp.regressor.iter().enumerate() {
        if z.iter().all(|&v| v == 0.0) {
            continue;
        }
        tried += k + 1;
        let (s, lag, _, _) = xcorr_test(z, r, &rho, k, true);
        if s > best.0 {
            best = (s, i, lag);
        }
    }
    let tried = tried.max(1);
    set.strongest_regressor_lag = best.2;
    set.tests.push(result(
        Test::RegressorCorrelation,
        best.0,
        normal_quantile(1.0 - LEVEL / (2.0 * tried as f64)),
        max_normal_p(best.0, tried),
        format!(
            "strongest correlation with regressor channel z{} at lag {} ({:.2} σ)",
            best.1 + 1,
            best.2,
            best.0
        ),
    ));

    // Structure against the input per path, and against the simulated output.
    match binned_test(r, inp.bins, inp.bin_count, &rho) {
        Some((c, df)) => set.tests.push(result(
            Test::StructureInput,
            c,
            chi2_quantile(1.0 - LEVEL, df as f64),
            chi2_sf(c, df as f64),
            format!(
                "mean residual in {} (path, knot segment) bins, autocorrelation-corrected",
                df + 1
            ),
        )),
        None => set.tests.push(result(
            Test::StructureInput,
            0.0,
            f64::NAN,
            1.0,
            "fewer than two bins with 10 samples".into(),
        )),
    }
    let mut sorted = inp.simulated.to_vec();
    sorted.sort_by(f64::total_cmp);
    let edges: Vec<f64> = (1..10).map(|i| sorted[(n - 1) * i / 10]).collect();
    let out_bins: Vec<usize> = inp
        .simulated
        .iter()
        .map(|&v| edges.iter().filter(|&&e| v > e).count())
        .collect();
    match binned_test(r, &out_bins, 10, &rho) {
        Some((c, df)) => set.tests.push(result(
            Test::StructureOutput,
            c,
            chi2_quantile(1.0 - LEVEL, df as f64),
            chi2_sf(c, df as f64),
            "mean residual in deciles of the simulated output, autocorrelation-corrected".into(),
        )),
        None => set.tests.push(result(
            Test::StructureOutput,
            0.0,
            f64::NAN,
            1.0,
            "simulated output is constant".into(),
        )),
    }

    // Trend and offset, Newey–West.
    let lags = ((n as f64).powf(1.0 / 3.0) * 1.5).ceil() as usize;
    let tc = (n as f64 - 1.0) / 2.0;
    let tau: Vec<f64> = (0..n).map(|t| (t as f64 - tc) / tc.max(1.0)).collect();
    let stt: f64 = tau.iter().map(|v| v * v).sum();
    let m = mean(r);
    let slope = tau.iter().zip(r).map(|(a, b)| a * (b - m)).sum::<f64>() / stt;
    let e: Vec<f64> = r.iter().zip(&tau).map(|(v, t)| v - m - slope * t).collect();
    // Var(Σ τ ε) = N² Var(mean of τ ε), long-run (Newey–West).
    let w: Vec<f64> = tau.iter().zip(&e).map(|(t, e)| t * e).collect();
    let var_slope = newey_west_var_of_mean(&w, lags) * (n as f64) * (n as f64) / (stt * stt);
    let t_slope = slope / var_slope.sqrt().max(1e-300);
    let t_mean = m / newey_west_var_of_mean(r, lags).sqrt().max(1e-300);
    let stat = t_slope.abs().max(t_mean.abs());
    set.tests.push(result(
        Test::Trend,
        stat,
        normal_quantile(1.0 - LEVEL / 4.0),
        (4.0 * normal_sf(stat)).min(1.0),
        format!(
            "offset {m:.4} (t = {t_mean:.2}), slope {:.4} per record half-length (t = {t_slope:.2}), Newey–West with {lags} lags",
            slope
        ),
    ));

    // Spectral lines not shared with the input.
    let (omega, power) = periodogram(r);
    let (_, pu) = periodogram(inp.u);
    let mm = power.len();
    if mm > 20 {
        let low = 4.0 * 2.0 * std::f64::consts::PI / n as f64;
        let (_, _, med_u) = line_scan(&pu, &vec![false; mm]);
        let mut exclude: Vec<bool> = omega.iter().map(|&w| w < low).collect();
        let qu = -(1.0 - (1.0 - LEVEL).powf(1.0 / mm as f64)).ln();
        for i in 0..mm {
            if med_u[i] > 0.0 && pu[i] / (med_u[i] / std::f64::consts::LN_2) > qu {
                for e in exclude
                    .iter_mut()
                    .take((i + 6).min(mm))
                    .skip(i.saturating_sub(5))
                {
                    *e = true;
                }
            }
        }
        let (q, idx, med) = line_scan(&power, &exclude);
        // Every tested bin counts as one ordinate (conservative: neighbouring bins of the
        // zero-padded, Hann-windowed periodogram are correlated).
        let indep = exclude.iter().filter(|&&e| !e).count().max(1) as f64;
        let p = 1.0 - (1.0 - (-q).exp()).powf(indep);
        let thr = -(1.0 - (1.0 - LEVEL).powf(1.0 / indep)).ln();
        let total: f64 = power.iter().sum();
        let g = power.get(idx).copied().unwrap_or(0.0) / total.max(1e-300);
        set.line_frequency = omega.get(idx).copied().unwrap_or(0.0);
        set.tests.push(result(
            Test::SpectralLine,
            q,
            thr,
            p,
            format!(
                "largest line at ω = {:.4} rad/sample (period {:.1} samples), {q:.1} × the local median spectrum; Fisher's g = {g:.4}",
                set.line_frequency,
                2.0 * std::f64::consts::PI / set.line_frequency.max(1e-12)
            ),
        ));
        set.curves.power_threshold = med
            .iter()
            .map(|v| v / std::f64::consts::LN_2 * thr)
            .collect();
        set.curves.omega = omega;
        set.curves.power = power;
        set.curves.power_median = med;
    }

    // State-dependent dynamics: a response whose speed or gain changes with the level leaves
    // a residual driven by the level times the increment of the output. The product is made
    // orthogonal to 1, ŷ and Δŷ (a linear error correlates with those).
    if let Some(w) = level_times_increment(inp.simulated) {
        let (s_w, lag_w, _, _) = xcorr_test(&w, r, &rho, k, true);
        let m_w = k + 1;
        set.tests.push(result(
            Test::StateDependence,
            s_w,
            normal_quantile(1.0 - LEVEL / (2.0 * m_w as f64)),
            max_normal_p(s_w, m_w),
            format!(
                "strongest correlation of the residual with (ŷ − ȳ)·Δŷ at lag {lag_w} ({s_w:.2} σ)"
            ),
        ));
    }

    // Heavy tails: samples beyond 5 robust standard deviations of the median (for Gaussian
    // residuals, P(|Z| > 5) = 5.73e-7 per sample).
    let med = super::stats::median(r);
    let s: Vec<f64> = r.iter().map(|a| a - med).collect();
    let sigma = mad_sigma(&s).max(1e-300);
    let beyond = s.iter().filter(|v| v.abs() > 5.0 * sigma).count();
    let lambda = n as f64 * 5.733e-7;
    let p = poisson_sf(beyond, lambda);
    set.tests.push(result(
        Test::HeavyTails,
        beyond as f64,
        (0..).find(|&c| poisson_sf(c, lambda) < LEVEL).unwrap_or(1) as f64,
        p,
        format!(
            "{beyond} samples beyond 5 robust σ (1.4826 MAD) from the median, {lambda:.2e} expected; excess kurtosis {:.2}",
            excess_kurtosis(r)
        ),
    ));
    set
}
