//! Closing the loop: residual → missing effect → added → error before and after.
//!
//! [`diagnose`] takes an estimation record and validation data, and
//!
//! 1. checks the data against the method's assumptions ([`checks`]): Table I structure, both
//!    paths over the whole interval, persistent excitation, the hold for μ0, saturation,
//!    quantisation, input levels, and feedback (a closed-loop record) against the base model's
//!    residual;
//! 2. identifies the paper's model — or, for a record that carries the controller's reference
//!    ([`Record::with_reference`](crate::model::Record::with_reference)), the closed-loop consistent estimate
//!    ([`model::Estimator`]), for the base model and every refit — and simulates it on the
//!    validation data;
//! 3. tests the residual ([`residual`]): whiteness, independence from the input, δ and the
//!    regressor, structure against the input per path and against the simulated output,
//!    trend and offset, spectral lines, heavy tails, state dependence, the lag of the
//!    strongest input–residual correlation, all at the 1 % level;
//! 4. traces the residual to the effect of the catalog ([`effects`]), or to state-dependent
//!    dynamics (level-dependent stores, [`stores`]), whose model extension explains it best:
//!    every effect whose evidence tests fired is fitted with its setting
//!    chosen on an inner hold-out of the estimation data, and the one that lowers the inner
//!    hold-out error the most — significantly and by at least the minimum gain, ties to the
//!    simplest — is added;
//! 5. re-identifies with it and repeats (at most [`DiagnoseOptions::max_steps`] times),
//!    reporting the validation error before and after every step;
//! 6. reports ([`report`]) and draws ([`figures`]).
//!
//! The validation data never choose anything: they are only scored. The simulated scenarios
//! of the tests and the confusion tables are in the crate `hsid-lab`.

use crate::identify::IdentifyError;
use crate::model::{Element, Record};
use crate::validation::{checks, data_checks, residual, unit_root};

pub mod base_order;
pub mod delay;
pub mod diagnosis;
pub mod dynamics;
pub mod effects;
pub mod end_stop;
pub mod error;
pub mod evidence;
pub mod figures;
pub mod findings;
pub mod fit_plan;
pub mod inner;
pub mod model;
pub mod options;
pub mod output_map;
pub mod report;
pub mod scoring;
pub mod segments;
pub mod simulate;
pub mod split;
pub mod steps;
pub mod stores;
pub mod verdict;

pub use crate::validation::{Check, Test, TestSet, Warning};
pub use diagnosis::{Diagnosis, Rejected, Step};
pub use effects::Effect;
pub use error::DiagnoseError;
pub use evidence::{Evidence, Tried, Unscored};
pub use findings::Finding;
pub use model::{Estimator, Evaluation, ExtendedModel, InitialState, Metric, Structure};
pub use options::{DiagnoseOptions, PoleRefinement, Proposing, Validation};
pub use scoring::residual_tests;

/// Runs the whole loop. `record` is the estimation record (or the whole record, for
/// [`Validation::Split`] and [`Validation::Holdout`]).
///
/// With a static nonlinearity, an unexcited knot is reported as
/// [`DiagnoseError::KnotNotVisited`] (advice for static data, not the Table I excitation).
pub fn diagnose(
    record: &Record,
    validation: &Validation,
    opts: &DiagnoseOptions,
) -> Result<Diagnosis, DiagnoseError> {
    diagnose_inner(record, validation, opts).map_err(|e| match e {
        DiagnoseError::Identify(IdentifyError::Core(hsid::Error::NoExcitation {
            knot, ..
        })) if opts.nonlinearity == Element::Static => {
            // The knots are the given ones unless the segment count is selected.
            let k = &opts.identify.knots_asc;
            let known = opts.select_segments.is_none();
            let at = |i: usize| known.then(|| k.get(i).copied()).flatten();
            // Channel `knot` is the hat function of knots[knot] (knots[0] = u_min has none):
            // it lives on [knots[knot − 1], knots[knot + 1]].
            let value = at(knot);
            let segment = knot.checked_sub(1).and_then(at).zip(at(knot + 1).or(value));
            DiagnoseError::KnotNotVisited {
                knot,
                value,
                segment,
            }
        }
        e => e,
    })
}

fn diagnose_inner(
    record: &Record,
    validation: &Validation,
    opts: &DiagnoseOptions,
) -> Result<Diagnosis, DiagnoseError> {
    opts.check()?;
    let mut id = opts.identify.clone();
    id.static_nonlinearity = opts.nonlinearity == Element::Static;
    if id.static_nonlinearity {
        id.knots_desc = id.knots_asc.clone();
    }
    let shared = id.static_nonlinearity;
    let data = split::split(record, validation, &id)?;
    let (est, vrec, vrange) = (&data.estimation, &data.validation, data.range.clone());
    if opts.max_delay >= est.len() {
        return Err(DiagnoseError::MaxDelay {
            delay: opts.max_delay,
            samples: est.len(),
        });
    }
    let segment_choice = match &opts.select_segments {
        Some(range) => {
            crate::progress::stage(|| "diagnose: choosing the segment count".to_string())?;
            segments::select_segments(range, est, &mut id, opts, shared)
        }
        None => String::new(),
    };
    let mut warnings = data_checks(&est.u, &est.y, &id, opts.nonlinearity);
    let mut plan = fit_plan::FitPlan::new(opts, &id, est);
    crate::progress::stage(|| "diagnose: the base model".to_string())?;
    let (base, lowered) = base_order::fit_base(est, opts, &mut id, &mut plan)?;
    warnings.extend(lowered);
    let paper = model::fit_structure(&Structure::base(), est, &plan.paper)
        .map(|m| model::evaluate(&m, vrec, vrange.clone(), Metric::Simulation))
        .ok();
    let (hold, ne) = (id.hold, est.len());
    let before = model::evaluate(&base, vrec, vrange.clone(), Metric::Simulation);
    // The feedback check tests the base model's residual on the estimation record.
    let fit = model::evaluate(&base, est, hold..ne, Metric::Simulation);
    warnings.extend(checks::feedback::feedback(
        &est.u[hold.min(ne)..],
        &fit.output[hold.min(ne)..],
        &fit.residual,
        model::Estimator::of(est),
    ));
    let tests_before = residual_tests(&base, vrec, vrange.clone(), &before, shared);
    let inner = inner::InnerValidation::choose_refining(est, opts, &mut plan.inner, &base);
    let description = format!(
        "{}{segment_choice}; {}",
        data.description,
        inner.describe(ne)
    );
    let (_, est_z, _, _) = residual::regressor(&est.u, &id.knots_asc, &id.knots_desc, shared);
    let root = unit_root::unit_root(&est_z, &est.y, &est.time, opts.max_delay + 1);
    warnings.extend(checks::integrating::integrating(root.as_ref()));
    let dead = delay::dead_time(
        &est_z,
        &est.y,
        &est.time,
        opts.max_delay + 1,
        base.hammerstein.dead_time(opts.max_delay + 1),
    );
    let holdouts = inner.holdouts(est, &plan.inner, &base, dead.extra());
    let context = steps::Context {
        est,
        validation: vrec,
        range: vrange.clone(),
        opts,
        holdout: &holdouts.main,
        block: &inner.block,
        reported: &plan.reported,
        warnings: &warnings,
        dead: &dead,
        delay_holdout: holdouts.delay.as_ref(),
        interior: holdouts.interior.as_ref(),
    };
    let mut p = steps::Progress {
        current: Structure::base(),
        model: base.clone(),
        steps: Vec::new(),
        rejected: Vec::new(),
        findings: Vec::new(),
        previous_validation: before.clone(),
        final_tests: None,
        ending: verdict::Ending::Other,
    };
    context.run(&mut p)?;
    let model = p.model;
    let final_tests = match p.final_tests {
        Some(t) => t,
        None => {
            let ev = model::evaluate(&model, est, hold..ne, Metric::Simulation);
            residual_tests(&model, est, hold..ne, &ev, shared)
        }
    };
    let after = model::evaluate(&model, vrec, vrange.clone(), Metric::Simulation);
    let after_prediction = model
        .noise
        .is_some()
        .then(|| model::evaluate(&model, vrec, vrange.clone(), Metric::Prediction));
    let tests_after = match &after_prediction {
        Some(pr) => residual_tests(&model, vrec, vrange.clone(), pr, shared),
        None => residual_tests(&model, vrec, vrange.clone(), &after, shared),
    };
    let mut unexplained = p.findings;
    let stores = p.current.dynamics == model::Dynamics::Stores;
    unexplained.extend(findings::outside_catalog(
        &final_tests,
        &warnings,
        shared,
        stores,
        p.current.element.is_some(),
    ));
    unexplained.extend(findings::friction(&model, est, hold, opts.increments));
    let verdict = verdict::Verdict::new(
        p.steps.iter().map(|s| s.effect).collect(),
        p.steps.last().map(|s| (s.metric, s.error_after)),
        &unexplained,
        final_tests.fired_names(),
        p.ending,
        before.rmse,
        after.rmse,
    );
    Ok(Diagnosis {
        nonlinearity: opts.nonlinearity,
        data_description: description,
        estimation_samples: est.len(),
        validation_samples: vrange.len(),
        warnings,
        base,
        model,
        steps: p.steps,
        rejected: p.rejected,
        unexplained,
        verdict,
        paper,
        before,
        estimator: model::Estimator::of(est),
        poles_refined: opts.refine_poles != PoleRefinement::Never
            && model::Estimator::of(est).refines_poles(),
        after,
        after_prediction,
        tests_before,
        tests_after,
        tests_estimation: final_tests,
        validation_record: data.validation.clone(),
        validation_range: vrange,
        dead_time: dead,
        inner,
    })
}
