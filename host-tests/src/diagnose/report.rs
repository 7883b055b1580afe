//! The diagnosis as JSON (`error_before`, `error_after`, `nrmse_before`, `nrmse_after`,
//! `effects`, `tests_before`, `tests_after`, `warnings`, …) and as text.

use crate::model::Element;
use std::fmt::Write as _;

use serde::Serialize;

use super::diagnosis::Diagnosis;
use super::effects::Significance;
use super::evidence::{Evidence, Tried};
use super::model::{ExtendedModel, Metric, Structure};
use super::output_map::OutputMap;
use crate::model_file::{ModelFile, NoiseFile};
use crate::validation::checks::{Warning, checks_text};
use crate::validation::residual::TestSet;

/// One entry of `effects`: an effect added, or one with evidence that was not added.
#[derive(Clone, Debug, Serialize)]
pub struct EffectJson {
    /// Catalog name.
    pub name: String,
    /// The tests that pointed at it, with their findings.
    pub evidence: Vec<Evidence>,
    /// Whether it was added.
    pub added: bool,
    /// Its setting (added effects).
    pub setting: Option<String>,
    /// The model extension.
    pub extension: String,
    /// Relative reduction of the inner hold-out MSE (estimation data).
    pub inner_gain: f64,
    /// One-sided p-value of that reduction, by `inner_test`.
    pub inner_p: f64,
    /// The test behind `inner_p`: `diebold_mariano` (the hold-out losses against the model
    /// before), or `heavy_tails` (the `outliers` step that keeps the model).
    pub inner_test: Significance,
    /// Settings tried on the inner hold-out with their RMSE.
    pub tried: Vec<Tried>,
    /// Metric of `error_before` / `error_after`.
    pub metric: Option<Metric>,
    /// Validation error of the model before this effect, output units.
    pub error_before: Option<f64>,
    /// Validation error after adding it, output units (`null` when not added).
    pub error_after: Option<f64>,
    /// NRMSE after.
    pub nrmse_after: Option<f64>,
    /// Fit % after.
    pub fit_after: Option<f64>,
    /// Validation samples excluded as outliers.
    pub excluded: Option<usize>,
}

/// A model in the report: its Hammerstein part as a model file, and the extensions the model
/// file does not hold.
#[derive(Clone, Debug, Serialize)]
pub struct ModelSummary {
    /// The extensions.
    pub structure: Structure,
    /// The Hammerstein part (plant, μ0, borders) and the AR noise model, in the model file's
    /// format (`hsid-model/1`); the extensions below are not part of it.
    pub model: ModelFile,
    /// Initial state of simulations.
    pub x0: Vec<f64>,
    /// Output map.
    pub output_map: Option<OutputMap>,
    /// Trend coefficients (normalised time) and sinusoids.
    pub additive: super::model::Additive,
    /// Estimation samples flagged as outliers.
    pub flagged: usize,
    /// The two-mass drive with play between motor and load, when the model has it (not part
    /// of the model file).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub two_mass: Option<TwoMassSummary>,
}

/// The two-mass drive of a model in the report.
#[derive(Clone, Debug, Serialize)]
pub struct TwoMassSummary {
    /// Its parameters (per motor inertia, time in samples; see [`crate::sandwich::model`]).
    pub model: crate::sandwich::TwoMassPlay,
    /// The play `2α`, output units × samples.
    pub gap: f64,
    /// Its standard deviation, when known.
    pub gap_std: Option<f64>,
}

impl ModelSummary {
    /// Summary of a model whose input element is `kind`.
    pub fn of(m: &ExtendedModel, kind: Element) -> Self {
        let mut model = match (&m.hysteresis, &m.friction) {
            (Some(el), _) => el.to_file(m.hammerstein.samples),
            (None, Some(fm)) => fm.to_file(m.hammerstein.samples, kind),
            (None, None) => m.hammerstein.to_json(Some(kind)),
        };
        // v(t) = Σ a_i v(t − i) + e(t): C = 1, D = 1 − Σ a_i q⁻ⁱ.
        model.noise = m.noise.as_ref().map(|n| NoiseFile {
            c: vec![1.0],
            d: std::iter::once(1.0).chain(n.a.iter().map(|a| -a)).collect(),
            sigma2: n.sigma * n.sigma,
        });
        Self {
            structure: m.structure.clone(),
            model,
            x0: m.x0.clone(),
            output_map: m.output_map.clone(),
            additive: m.additive.clone(),
            flagged: m.flagged,
            two_mass: m.two_mass.as_ref().map(|tm| TwoMassSummary {
                model: tm.model.clone(),
                gap: tm.gap(),
                gap_std: tm.gap_std(),
            }),
        }
    }
}

/// The JSON report.
#[derive(Clone, Debug, Serialize)]
pub struct DiagnosisJson {
    /// Element kind.
    pub nonlinearity: String,
    /// How estimation and validation data were formed.
    pub data: String,
    /// The estimator of the Hammerstein part (`open_loop`, or `reference` for the
    /// closed-loop estimate from the logged reference).
    pub estimator: super::model::Estimator,
    /// Estimation samples.
    pub estimation_samples: usize,
    /// Validation samples scored.
    pub validation_samples: usize,
    /// Data checks.
    pub warnings: Vec<Warning>,
    /// Validation simulation RMSE of the paper's estimate alone (subspace identification and
    /// rank-1 split, no refit), output units.
    pub error_paper: Option<f64>,
    /// Validation simulation RMSE of the base model (the paper's structure refit on the
    /// estimation data), output units: the error before any effect.
    pub error_before: f64,
    /// Its NRMSE.
    pub nrmse_before: f64,
    /// Its fit %.
    pub fit_before: f64,
    /// Validation simulation RMSE of the final model, output units (outliers excluded when
    /// the outliers effect was added).
    pub error_after: f64,
    /// Its NRMSE.
    pub nrmse_after: f64,
    /// Its fit %.
    pub fit_after: f64,
    /// Validation samples excluded as outliers from `error_after`.
    pub excluded_after: usize,
    /// Validation one-step prediction RMSE of the final model (with a noise model).
    pub prediction_error_after: Option<f64>,
    /// Effects added (in order) then effects with evidence that were not added.
    pub effects: Vec<EffectJson>,
    /// Tests that fire and that no catalog effect explains.
    pub unexplained: Vec<String>,
    /// Conclusion.
    pub verdict: String,
    /// Tests on the validation residual of the paper's model.
    pub tests_before: TestSet,
    /// Tests on the final validation residual.
    pub tests_after: TestSet,
    /// Tests on the estimation residual of the last deterministic model.
    pub tests_estimation: TestSet,
    /// The dead time of the estimation data (ARX test) against the base model's.
    pub dead_time: super::delay::DeadTime,
    /// The paper's model.
    pub model_before: ModelSummary,
    /// The final model.
    pub model_after: ModelSummary,
}

/// The JSON report of a diagnosis.
pub fn to_json(d: &Diagnosis) -> DiagnosisJson {
    let mut effects: Vec<EffectJson> = d
        .steps
        .iter()
        .map(|s| EffectJson {
            name: s.effect.name().into(),
            evidence: s.evidence.clone(),
            added: true,
            setting: Some(s.setting.clone()),
            extension: s.effect.extension().into(),
            inner_gain: s.inner_gain,
            inner_p: s.inner_p,
            inner_test: s.inner_test,
            tried: s.tried.clone(),
            metric: Some(s.metric),
            error_before: Some(s.error_before),
            error_after: Some(s.error_after),
            nrmse_after: Some(s.nrmse_after),
            fit_after: Some(s.fit_after),
            excluded: Some(s.excluded),
        })
        .collect();
    for r in &d.rejected {
        effects.push(EffectJson {
            name: r.effect.name().into(),
            evidence: r.evidence.clone(),
            added: false,
            setting: None,
            extension: r.effect.extension().into(),
            inner_gain: r.inner_gain,
            inner_p: r.inner_p,
            inner_test: r.inner_test,
            tried: Vec::new(),
            metric: None,
            error_before: None,
            error_after: None,
            nrmse_after: None,
            fit_after: None,
            excluded: None,
        });
    }
    DiagnosisJson {
        nonlinearity: d.nonlinearity.name().into(),
        data: d.data_description.clone(),
        estimator: d.estimator,
        estimation_samples: d.estimation_samples,
        validation_samples: d.validation_samples,
        warnings: d.warnings.clone(),
        error_paper: d.paper.as_ref().map(|p| p.rmse),
        error_before: d.before.rmse,
        nrmse_before: d.before.nrmse,
        fit_before: d.before.fit_percent,
        error_after: d.after.rmse,
        nrmse_after: d.after.nrmse,
        fit_after: d.after.fit_percent,
        excluded_after: d.after.excluded.iter().filter(|&&e| e).count(),
        prediction_error_after: d.after_prediction.as_ref().map(|e| e.rmse),
        effects,
        unexplained: d.unexplained.iter().map(ToString::to_string).collect(),
        verdict: d.verdict.to_string(),
        tests_before: d.tests_before.clone(),
        tests_after: d.tests_after.clone(),
        tests_estimation: d.tests_estimation.clone(),
        dead_time: d.dead_time.clone(),
        model_before: ModelSummary::of(&d.base, d.nonlinearity),
        model_after: ModelSummary::of(&d.model, d.nonlinearity),
    }
}

fn test_table(s: &mut String, before: &TestSet, after: &TestSet) {
    let _ = writeln!(
        s,
        "  {:<22} {:>12} {:>10} {:>10}   {:>12} {:>10}",
        "test (1 % level)", "before", "p", "", "after", "p"
    );
    for t in &before.tests {
        let a = after.get(t.name);
        let mark = |f: bool| if f { "FIRES" } else { "" };
        let _ = writeln!(
            s,
            "  {:<22} {:>12.3} {:>10.2e} {:>10}   {:>12.3} {:>10.2e} {}",
            t.name,
            t.statistic,
            t.p_value,
            mark(t.fired),
            a.map_or(f64::NAN, |a| a.statistic),
            a.map_or(f64::NAN, |a| a.p_value),
            mark(a.is_some_and(|a| a.fired)),
        );
    }
}

/// The diagnosis as text.
pub fn text(d: &Diagnosis) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "hsid diagnose ({} nonlinearity)", d.nonlinearity.name());
    let _ = writeln!(s, "data: {}", d.data_description);
    let _ = writeln!(s);
    for line in checks_text(&d.warnings, &d.checks_ran()) {
        let _ = writeln!(s, "{line}");
    }
    let _ = writeln!(s);
    let b = &d.base.hammerstein;
    let _ = writeln!(s, "estimator: {}", d.estimator.describe());
    let _ = writeln!(s, "base model: order {}, poles {}", b.order, poles(&d.base));
    if let Some(p) = &d.paper {
        let _ = writeln!(
            s,
            "the paper's estimate alone (subspace, rank-1 split): validation RMSE {:.5}, NRMSE {:.4}",
            p.rmse, p.nrmse
        );
    }
    let _ = writeln!(
        s,
        "validation error before (base model: borders, B, D refit by least squares{}): RMSE {:.5}, NRMSE {:.4}, fit {:.2} %",
        if d.poles_refined {
            ", poles by the simulation error"
        } else {
            ""
        },
        d.before.rmse,
        d.before.nrmse,
        d.before.fit_percent
    );
    let _ = writeln!(s);
    for (i, st) in d.steps.iter().enumerate() {
        let _ = writeln!(
            s,
            "step {}: {} — {} ({})",
            i + 1,
            st.effect.name(),
            st.setting,
            st.effect.extension()
        );
        for e in &st.evidence {
            let _ = writeln!(s, "  evidence: {e}");
        }
        let tried: Vec<String> = st
            .tried
            .iter()
            .map(|t| format!("{t}: {:.5}", t.rmse()))
            .collect();
        let _ = writeln!(
            s,
            "  estimation hold-out: MSE {:+.1} % ({} p = {:.2e}); tried {}",
            -100.0 * st.inner_gain,
            st.inner_test.label(),
            st.inner_p,
            tried.join(", ")
        );
        if !st.competitors.is_empty() {
            let c: Vec<String> = st
                .competitors
                .iter()
                .map(|(e, g, p)| format!("{} MSE {:+.1} % (p = {:.2})", e.name(), -100.0 * g, p))
                .collect();
            let _ = writeln!(s, "  other candidates: {}", c.join(", "));
        }
        let metric = match st.metric {
            Metric::Simulation => "simulation",
            Metric::Prediction => "one-step prediction",
        };
        let excl = if st.excluded > 0 {
            format!(" ({} outliers excluded)", st.excluded)
        } else {
            String::new()
        };
        let _ = writeln!(
            s,
            "  validation {metric} RMSE {:.5} → {:.5}{excl} (NRMSE {:.4}, fit {:.2} %)",
            st.error_before, st.error_after, st.nrmse_after, st.fit_after
        );
    }
    if !d.steps.is_empty() {
        let _ = writeln!(s);
    }
    for r in &d.rejected {
        let _ = writeln!(
            s,
            "not added: {} (estimation hold-out MSE {:+.1} %, {} p = {:.2})",
            r.effect.name(),
            -100.0 * r.inner_gain,
            r.inner_test.label(),
            r.inner_p
        );
    }
    for u in &d.unexplained {
        let _ = writeln!(s, "not identified: {u}");
    }
    let _ = writeln!(s, "{}", d.dead_time);
    let _ = writeln!(s);
    match &d.model.two_mass {
        Some(tm) => {
            let _ = writeln!(
                s,
                "final model: two-mass drive in place of G (order {}, poles {}): {}",
                d.model.hammerstein.order,
                poles(&d.model),
                tm.describe(None, None)
            );
        }
        None => {
            let _ = writeln!(
                s,
                "final model: order {}, poles {}",
                d.model.hammerstein.order,
                poles(&d.model)
            );
        }
    }
    let _ = writeln!(
        s,
        "validation error after: RMSE {:.5}, NRMSE {:.4}, fit {:.2} %{}",
        d.after.rmse,
        d.after.nrmse,
        d.after.fit_percent,
        match &d.after_prediction {
            Some(p) => format!("; one-step prediction RMSE {:.5}", p.rmse),
            None => String::new(),
        }
    );
    let _ = writeln!(s);
    let fired_est = d.tests_estimation.fired_names();
    let _ = writeln!(
        s,
        "tests that fire on the estimation residual of the last deterministic model: {}",
        if fired_est.is_empty() {
            "none".to_string()
        } else {
            fired_est.join(", ")
        }
    );
    let _ = writeln!(s, "residual tests on the validation data:");
    test_table(&mut s, &d.tests_before, &d.tests_after);
    let _ = writeln!(
        s,
        "  strongest input–residual correlation: lag {} before, lag {} after",
        d.tests_before.strongest_input_lag, d.tests_after.strongest_input_lag
    );
    let _ = writeln!(s);
    let _ = write!(s, "verdict: {}", d.verdict);
    s
}

fn poles(m: &ExtendedModel) -> String {
    m.hysteresis
        .as_ref()
        .map_or_else(|| m.hammerstein.poles(), |el| el.poles())
        .iter()
        .map(|(r, i)| {
            if i.abs() < 1e-12 {
                format!("{r:.4}")
            } else {
                format!("{r:.4}{i:+.4}j")
            }
        })
        .collect::<Vec<_>>()
        .join(", ")
}
