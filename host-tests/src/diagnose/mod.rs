//! Closing the loop: residual → missing effect → added → error before and after.
//!
//! [`diagnose`] takes an estimation record and validation data, and
//!
//! 1. checks the data against the method's assumptions ([`checks`]): Table I structure, both
//!    paths over the whole interval, persistent excitation, the hold for μ0, saturation,
//!    quantisation, input levels;
//! 2. identifies the paper's model and simulates it on the validation data;
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
//! The validation data never choose anything: they are only scored. [`scenario`] simulates
//! Table I experiments with one undeclared effect, for the tests and the confusion table, and
//! two-tank plants for the stores.

use std::ops::Range;

use crate::identify::{IdentifyError, IdentifyOptions};

pub mod bench;
pub mod checks;
pub mod cli;
pub mod delay;
pub mod diagnosis;
pub mod dynamics;
pub mod effects;
pub mod error;
pub mod figures;
pub mod model;
pub mod noise;
pub mod optimise;
pub mod options;
pub mod output_map;
pub mod report;
pub mod residual;
pub mod scenario;
pub mod simulate;
pub mod stats;
pub mod stores;

pub use checks::{Check, Warning};
pub use diagnosis::{Diagnosis, Rejected, Step};
pub use effects::Effect;
pub use error::DiagnoseError;
pub use model::{Evaluation, ExtendedModel, InitialState, Metric, Record, Structure};
pub use options::{DiagnoseOptions, Nonlinearity, PoleRefinement, Validation};
pub use residual::{Test, TestSet};

fn check_record(
    rec: &Record,
    which: &'static str,
    u_min: f64,
    u_max: f64,
) -> Result<(), DiagnoseError> {
    if rec.u.len() != rec.y.len() {
        return Err(DiagnoseError::LengthMismatch {
            u: rec.u.len(),
            y: rec.y.len(),
        });
    }
    if let Some((index, &value)) = rec
        .u
        .iter()
        .enumerate()
        .find(|(_, v)| !(**v >= u_min && **v <= u_max))
    {
        return Err(DiagnoseError::InputOutOfRange {
            record: which,
            index,
            value,
            u_min,
            u_max,
        });
    }
    Ok(())
}

/// Tests of a model's residual on `range` of `rec`.
pub fn residual_tests(
    model: &ExtendedModel,
    rec: &Record,
    range: Range<usize>,
    ev: &Evaluation,
    shared: bool,
) -> TestSet {
    let h = &model.hammerstein;
    let (delta, z, bins, count) = residual::regressor(&rec.u, &h.knots_asc, &h.knots_desc, shared);
    let r = range.clone();
    let zs: Vec<Vec<f64>> = z.iter().map(|c| c[r.clone()].to_vec()).collect();
    residual::run_tests(&residual::ResidualInput {
        residual: &ev.residual,
        u: &rec.u[r.clone()],
        delta: &delta[r.clone()],
        regressor: &zs,
        bins: &bins[r.clone()],
        bin_count: count,
        simulated: &ev.output[r],
    })
}

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
        })) if opts.nonlinearity == Nonlinearity::Static => {
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
    let mut id = opts.identify.clone();
    id.static_nonlinearity = opts.nonlinearity == Nonlinearity::Static;
    if id.static_nonlinearity {
        id.knots_desc = id.knots_asc.clone();
    }
    let (u_min, u_max) = (id.u_min(), id.u_max());
    check_record(record, "estimation", u_min, u_max)?;
    let hold = id.hold;
    let n = record.len();
    let min_len = hold + 4 * (id.f + id.p) + 50;
    if n < min_len {
        return Err(DiagnoseError::TooShort {
            samples: n,
            need: min_len,
        });
    }
    let (est, vrec, vrange, description) = match validation {
        Validation::Separate { record: v, skip } => {
            check_record(v, "validation", u_min, u_max)?;
            if *skip >= v.len() {
                return Err(DiagnoseError::InvalidHoldout {
                    start: *skip,
                    end: v.len(),
                    len: v.len(),
                });
            }
            (
                record.clone(),
                v.clone(),
                *skip..v.len(),
                format!(
                    "estimation: all {n} samples of the estimation record; validation: a separate record of {} samples, simulated from its start with the input only, scored from sample {skip}",
                    v.len()
                ),
            )
        }
        Validation::Split(frac) => {
            if !(*frac > 0.0 && *frac < 1.0) {
                return Err(DiagnoseError::InvalidSplit(*frac));
            }
            let at = hold + ((n - hold) as f64 * frac).round() as usize;
            if at + 50 > n || at < min_len {
                return Err(DiagnoseError::TooShort {
                    samples: n,
                    need: min_len.max(at + 50),
                });
            }
            (
                record.slice(0..at),
                record.clone(),
                at..n,
                format!(
                    "no validation record: samples 0..{at} ({:.0} % of the samples after the hold) estimate, samples {at}..{n} validate; the validation simulation runs from the start of the record with the input only",
                    100.0 * frac
                ),
            )
        }
        Validation::Holdout(r) => {
            if r.start >= r.end || r.start < hold || r.end > n {
                return Err(DiagnoseError::InvalidHoldout {
                    start: r.start,
                    end: r.end,
                    len: n,
                });
            }
            let est = record.parts(&[0..r.start, r.end..n]);
            (
                est,
                record.clone(),
                r.clone(),
                format!(
                    "samples {}..{} are held out for validation; the other {} samples, joined at the gap, estimate; the validation simulation runs from the start of the record with the input only",
                    r.start,
                    r.end,
                    n - (r.end - r.start)
                ),
            )
        }
    };
    if est.len() < min_len {
        return Err(DiagnoseError::TooShort {
            samples: est.len(),
            need: min_len,
        });
    }
    let shared = id.static_nonlinearity;
    // Uniform segment count chosen on the estimation data: the BIC of the in-sample simulation
    // error, N ln(MSE) + k ln N, k = border values + 2 n + 2.
    let mut segment_choice = String::new();
    if let Some(range) = &opts.select_segments {
        let initial = opts.initial.unwrap_or(if hold > 0 {
            InitialState::Rest
        } else {
            InitialState::Estimated
        });
        let ne = est.len();
        let mut best: Option<(f64, usize)> = None;
        let mut tried = Vec::new();
        for segs in range.clone() {
            let trial = IdentifyOptions::uniform(u_min, u_max, segs, hold);
            let mut ids = id.clone();
            ids.knots_desc = trial.knots_asc.clone();
            ids.knots_asc = trial.knots_asc;
            let fo = model::FitOptions {
                identify: ids,
                initial,
                time_center: 0.0,
                time_scale: 1.0,
                outlier_k: opts.outlier_k,
                rounds: 1,
                refit: true,
                refine_poles: opts.refine_poles != PoleRefinement::Never,
                saturation: model::Saturation::default(),
            };
            let Ok(m) = model::fit_structure(&Structure::base(), &est, &fo) else {
                continue;
            };
            let e = model::evaluate(&m, &est, hold..ne, Metric::Simulation);
            let borders = if shared { segs + 1 } else { 2 * segs + 1 };
            let k = (borders + 2 * m.hammerstein.order + 2) as f64;
            let nn = (ne - hold) as f64;
            let bic = nn * (e.rmse * e.rmse).max(1e-300).ln() + k * nn.ln();
            if bic.is_finite() {
                tried.push(format!("{segs}: {bic:.1}"));
                if best.is_none_or(|(b, _)| bic < b) {
                    best = Some((bic, segs));
                }
            }
        }
        if let Some((_, segs)) = best {
            let u = IdentifyOptions::uniform(u_min, u_max, segs, hold);
            id.knots_desc = u.knots_asc.clone();
            id.knots_asc = u.knots_asc;
            segment_choice = format!(
                "; {segs} uniform segments per path, chosen by the BIC of the estimation simulation error (tried {})",
                tried.join(", ")
            );
        }
    }
    let description = format!("{description}{segment_choice}");
    let warnings = checks::check_data(
        &est.u,
        &est.y,
        &checks::CheckSetup {
            kind: opts.nonlinearity,
            knots_asc: &id.knots_asc,
            knots_desc: &id.knots_desc,
            hold,
            settle: id.settle,
            mu0_known: id.mu0.is_some(),
            f: id.f,
            p: id.p,
        },
    );
    let (tmin, tmax) = est
        .time
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &t| {
            (a.min(t), b.max(t))
        });
    let fit_opts = model::FitOptions {
        initial: opts.initial.unwrap_or(if hold > 0 {
            InitialState::Rest
        } else {
            InitialState::Estimated
        }),
        identify: id.clone(),
        time_center: 0.5 * (tmin + tmax),
        time_scale: 0.5 * (tmax - tmin),
        outlier_k: opts.outlier_k,
        rounds: 3,
        refit: true,
        refine_poles: opts.refine_poles == PoleRefinement::Always,
        saturation: checks::saturation(&est.y),
    };
    let final_opts = model::FitOptions {
        refine_poles: opts.refine_poles != PoleRefinement::Never,
        ..fit_opts.clone()
    };
    // The paper's estimate alone (subspace, borders from the rank-1 split), for reference.
    let paper_opts = model::FitOptions {
        refit: false,
        refine_poles: false,
        ..fit_opts.clone()
    };
    let paper = model::fit_structure(&Structure::base(), &est, &paper_opts)
        .map(|m| model::evaluate(&m, &vrec, vrange.clone(), Metric::Simulation))
        .ok();
    let ne = est.len();
    let block_len = ((ne - hold) as f64 * (1.0 - opts.inner_fraction)).round() as usize;
    let (_, _, est_bins, est_bin_count) =
        residual::regressor(&est.u, &id.knots_asc, &id.knots_desc, shared);
    let block = effects::Holdout::choose_block(
        &est,
        hold,
        block_len,
        &est_bins,
        est_bin_count,
        fit_opts.initial == InitialState::Estimated,
    );

    let mut current = Structure::base();
    let mut model = model::fit_structure(&current, &est, &final_opts)?;
    let base = model.clone();
    let before = model::evaluate(&base, &vrec, vrange.clone(), Metric::Simulation);
    let tests_before = residual_tests(&base, &vrec, vrange.clone(), &before, shared);

    // The inner validation: the block above if the base model fitted without it simulates it
    // about as well as the model fits the record (at most 3 × the in-sample RMSE); otherwise
    // leave-block-out cross-validation over tenths of the record (10-fold) that are scorable in
    // that sense (at least two), their scores pooled.
    let in_sample0 = model::evaluate(&model, &est, hold..ne, Metric::Simulation).rmse;
    let scorable = |r: &Range<usize>| -> bool {
        let fit_part = est.parts(&[0..r.start, r.end..ne]);
        model::fit_structure(&current, &fit_part, &fit_opts).is_ok_and(|m| {
            let e = model::evaluate(&m, &est, r.clone(), Metric::Simulation).rmse;
            e.is_finite() && e <= 3.0 * in_sample0
        })
    };
    let folds: Vec<Range<usize>> = if scorable(&block) {
        vec![block.clone()]
    } else {
        let good: Vec<Range<usize>> = effects::Holdout::fold_blocks(
            &est,
            hold,
            10,
            &est_bins,
            est_bin_count,
            fit_opts.initial == InitialState::Estimated,
        )
        .into_iter()
        .filter(|r| scorable(r))
        .collect();
        if good.len() >= 2 {
            good
        } else {
            vec![block.clone()]
        }
    };
    let holdout = effects::Holdout::with_folds(&est, folds.clone(), &fit_opts);
    let description = if folds.len() == 1 {
        format!(
            "{description}; every setting and every effect is chosen on the estimation data: fitted without its samples {}..{} (of {ne}), scored on them",
            block.start, block.end
        )
    } else {
        let list: Vec<String> = folds
            .iter()
            .map(|r| format!("{}..{}", r.start, r.end))
            .collect();
        format!(
            "{description}; every setting and every effect is chosen on the estimation data by leave-block-out cross-validation (10 blocks; blocks that leave a knot segment unexcited, the first with an estimated initial state, and blocks the base model fitted without them simulates with more than 3 × its in-sample error are not used): fitted without each of the blocks {} (of {ne}) in turn, scored on it, the scores pooled (the last 30 % of the record, {}..{}, cannot be scored: the model fitted without it simulates it with more than 3 × its in-sample error)",
            list.join(", "),
            block.start,
            block.end
        )
    };

    let (_, est_z, _, _) = residual::regressor(&est.u, &id.knots_asc, &id.knots_desc, shared);
    let dead = delay::dead_time(
        &est_z,
        &est.y,
        &est.time,
        opts.max_delay + 1,
        delay::model_dead_time(&base.hammerstein, opts.max_delay + 1),
    );
    let mut steps: Vec<Step> = Vec::new();
    let mut rejected = Vec::new();
    let mut unexplained = Vec::new();
    let mut previous_validation = before.clone();
    let mut final_tests: Option<TestSet> = None;
    // Whether the loop ended because no extension passed the inner validation.
    let mut no_candidate = false;
    for _ in 0..opts.max_steps {
        let ev = model::evaluate(&model, &est, hold..ne, Metric::Simulation);
        let tests = residual_tests(&model, &est, hold..ne, &ev, shared);
        let (inner_model, baseline) = match holdout.evaluate_folds(
            &current,
            Metric::Simulation,
            false,
        ) {
            Ok(Some(v)) => v,
            Ok(None) => break,
            // The current model cannot be fitted without one of the blocks: nothing can
            // be scored against it.
            Err(e @ (DiagnoseError::Identify(_) | DiagnoseError::Dynamics(_))) => {
                unexplained.push(format!(
                        "the estimation data cannot score extensions: the current model cannot be fitted without one of the inner validation's blocks ({e})"
                    ));
                break;
            }
            Err(e) => return Err(e),
        };
        // The inner hold-out can only score extensions if the model fitted without the block
        // predicts the block about as well as the model fits the record: three times the
        // in-sample error means the fitting part leaves the block's behaviour unseen (a level
        // or input range visited only there), and every score would be noise.
        let in_sample = model::evaluate(&model, &est, hold..ne, Metric::Simulation).rmse;
        if baseline.rmse.is_nan() || baseline.rmse > 3.0 * in_sample {
            unexplained.push(format!(
                "the estimation data cannot score extensions: the model fitted without samples {}..{} simulates them with RMSE {:.4}, more than 3 × its in-sample RMSE {:.4} (that block holds behaviour the rest of the record does not show)",
                block.start, block.end, baseline.rmse, in_sample
            ));
            break;
        }
        let resid = &ev.residual;
        let proposal = effects::Proposal {
            holdout: &holdout,
            current: &current,
            baseline: &baseline,
            inner_model: &inner_model,
            order: model.hammerstein.order,
            f: current.horizon.unwrap_or(id.f),
            max_delay: opts.max_delay,
            residual: resid,
            input: &est.u[hold..],
            tests: &tests,
        };
        let mut cands = Vec::new();
        for e in Effect::PROPOSED {
            // A saturated output found by the data checks is direct evidence of an output
            // nonlinearity, even when the residual tests lack power.
            let saturated = e == Effect::OutputNonlinearity
                && warnings.iter().any(|w| w.check == Check::OutputSaturation);
            if !e.deterministic() || !(effects::has_evidence(e, &tests) || saturated) {
                continue;
            }
            if let Some(c) = proposal.propose(e)? {
                cands.push(c);
            }
        }
        let mut chosen = effects::choose(&cands, opts.min_gain, opts.tie);
        // The dead time of the data (ARX test, independent of the simulation error) beyond the
        // model's: a delay found by a test at 1 %, added unless it makes the inner score
        // significantly worse (the simulation error of measured data is dominated by what else
        // the model lacks, and cannot be asked to confirm a delay of a few samples).
        if chosen.is_none() && current.delay == 0 && dead.extra() > 0 {
            let mut s = current.clone();
            s.delay = dead.extra();
            let scored = match holdout.score(&s, Metric::Simulation) {
                Err(DiagnoseError::Identify(_) | DiagnoseError::Dynamics(_)) => None,
                other => other?,
            };
            if let Some((m, ev)) = scored {
                let (gain, p_value) = effects::compare(&baseline, &ev);
                let (_, worse_p) = effects::compare(&ev, &baseline);
                if worse_p >= residual::LEVEL {
                    // One input_delay candidate: the dead-time test's delay replaces the one
                    // the screen proposed (whose settings stay listed as tried).
                    let mut tried = Vec::new();
                    if let Some(i) = cands.iter().position(|c| c.effect == Effect::InputDelay) {
                        tried = cands.remove(i).tried;
                    }
                    tried.push((format!("d = {} (dead-time test)", dead.extra()), ev.rmse));
                    cands.push(effects::Candidate {
                        effect: Effect::InputDelay,
                        structure: s,
                        inner_model: m,
                        tried,
                        evaluation: ev,
                        gain,
                        p_value,
                        complexity: 1.0,
                    });
                    chosen = Some(cands.len() - 1);
                }
            }
        }
        if chosen.is_none()
            && effects::has_evidence(Effect::ColoredNoise, &tests)
            && let Some(c) = proposal.propose(Effect::ColoredNoise)?
        {
            cands.push(c);
            let last = cands.len() - 1;
            if effects::choose(&cands[last..], opts.min_gain, opts.tie).is_some() {
                chosen = Some(last);
            }
        }
        let evidence_of = |e: Effect| -> Vec<String> {
            let mut v: Vec<String> = e
                .evidence_tests()
                .iter()
                .filter_map(|&t| tests.get(t))
                .filter(|t| t.fired)
                .map(|t| format!("{}: {} (p = {:.2e})", t.name, t.detail, t.p_value))
                .collect();
            if e == Effect::InputDelay && dead.extra() > 0 {
                v.push(dead_time_text(&dead));
            }
            if e == Effect::OutputNonlinearity {
                v.extend(
                    warnings
                        .iter()
                        .filter(|w| w.check == Check::OutputSaturation)
                        .map(|w| format!("data check output_saturation: {}", w.message)),
                );
            }
            v
        };
        // The chosen extension refitted on the whole estimation record; if that model has a
        // mode too slow to validate, the next candidate is taken.
        // The refit must also fit the estimation record at least about as well as the
        // hold-out model does (a subspace fit can land on a poor local solution); otherwise
        // the hold-out model, fitted on 70 % of the same data, is kept.
        let mut refitted: Option<ExtendedModel> = None;
        while let Some(ci) = chosen {
            let inner = &cands[ci].inner_model;
            // An extension that cannot be fitted on the whole record keeps its hold-out fit.
            let m = match model::fit_structure(&cands[ci].structure, &est, &final_opts) {
                Err(DiagnoseError::Identify(_) | DiagnoseError::Dynamics(_)) => inner.clone(),
                other => other?,
            };
            let rmse_full = model::evaluate(&m, &est, hold..ne, Metric::Simulation).rmse;
            let rmse_inner = model::evaluate(inner, &est, hold..ne, Metric::Simulation).rmse;
            let m = if rmse_full.is_finite() && rmse_full <= 1.1 * rmse_inner {
                m
            } else {
                inner.clone()
            };
            if !effects::too_slow(&m, ne) {
                refitted = Some(m);
                break;
            }
            cands[ci].gain = f64::NEG_INFINITY;
            chosen = effects::choose(&cands, opts.min_gain, opts.tie);
        }
        let Some(ci) = chosen else {
            rejected = cands
                .iter()
                .map(|c| Rejected {
                    effect: c.effect,
                    evidence: evidence_of(c.effect),
                    inner_gain: c.gain,
                    inner_p: c.p_value,
                })
                .collect();
            for t in tests.tests.iter().filter(|t| t.fired) {
                let tried: Vec<String> = cands
                    .iter()
                    .filter(|c| c.effect.evidence_tests().contains(&t.name))
                    .map(|c| {
                        format!(
                            "{} changes the hold-out MSE by {:+.1} % (p = {:.2})",
                            c.effect.name(),
                            -100.0 * c.gain,
                            c.p_value
                        )
                    })
                    .collect();
                let why = if tried.is_empty() {
                    "no catalog effect left to try".to_string()
                } else {
                    tried.join("; ")
                };
                unexplained.push(format!(
                    "{} fired ({}; p = {:.2e}) but no catalog effect explains it ({why}): effect not identified",
                    t.name, t.detail, t.p_value
                ));
            }
            final_tests = Some(tests);
            no_candidate = true;
            break;
        };
        let c = cands[ci].clone();
        let Some(new_model) = refitted else { break };
        let metric = if c.effect.deterministic() {
            Metric::Simulation
        } else {
            Metric::Prediction
        };
        let after = model::evaluate(&new_model, &vrec, vrange.clone(), metric);
        // The previous model on the same samples (outliers of the new model excluded).
        let prev_same = {
            let mut s = 0.0;
            let mut k = 0usize;
            for (r, &e) in previous_validation.residual.iter().zip(&after.excluded) {
                if !e {
                    s += r * r;
                    k += 1;
                }
            }
            (s / k.max(1) as f64).sqrt()
        };
        let error_before = if after.excluded.iter().any(|&e| e) {
            prev_same
        } else {
            previous_validation.rmse
        };
        steps.push(Step {
            effect: c.effect,
            evidence: evidence_of(c.effect),
            setting: effects::setting(c.effect, &c.structure, Some(&new_model)),
            inner_gain: c.gain,
            inner_p: c.p_value,
            tried: c.tried.clone(),
            competitors: cands
                .iter()
                .enumerate()
                .filter(|(i, _)| *i != ci)
                .map(|(_, o)| (o.effect, o.gain, o.p_value))
                .collect(),
            metric,
            error_before,
            error_after: after.rmse,
            nrmse_after: after.nrmse,
            fit_after: after.fit_percent,
            excluded: after.excluded.iter().filter(|&&e| e).count(),
            model: new_model.clone(),
        });
        current = c.structure;
        model = new_model;
        previous_validation = after;
        if !c.effect.deterministic() {
            break;
        }
    }
    let final_tests = match final_tests {
        Some(t) => t,
        None => {
            let ev = model::evaluate(&model, &est, hold..ne, Metric::Simulation);
            residual_tests(&model, &est, hold..ne, &ev, shared)
        }
    };
    let after = model::evaluate(&model, &vrec, vrange.clone(), Metric::Simulation);
    let after_prediction = model
        .noise
        .is_some()
        .then(|| model::evaluate(&model, &vrec, vrange.clone(), Metric::Prediction));
    let tests_after = match &after_prediction {
        Some(p) => residual_tests(&model, &vrec, vrange.clone(), p, shared),
        None => residual_tests(&model, &vrec, vrange.clone(), &after, shared),
    };
    // Effects the tests or the data checks find that the catalog has no extension for.
    if shared && final_tests.fired(Test::DirectionCorrelation) {
        unexplained.push(
            "found, not in the catalog: the residual depends on the direction of the input (direction_correlation fires) although the nonlinearity is static: the plant behaves differently when the input falls (e.g. coasting down when the drive returns to 0); a backlash or switch element, or a direction-dependent model, would be needed".into(),
        );
    }
    if final_tests.fired(Test::StateDependence) {
        unexplained.push(if current.dynamics == model::Dynamics::Stores {
            "found, not in the catalog: state dependence beyond the level-dependent stores (state_dependence still fires with them: the residual follows the level times the increment of the simulated output in a form the stores do not have); `diagnose::dynamics` has further model classes, measured by the example `tanks_dynamics`".into()
        } else {
            "found, not in the catalog: state-dependent dynamics (state_dependence fires: the residual follows the level times the increment of the simulated output, a speed or gain that changes with the level); the level-dependent stores (`state_dependent_dynamics`) were not added: they start from an order-2 model, and the hold-out must confirm them".into()
        });
    }
    if warnings
        .iter()
        .any(|w| w.check == Check::OutputQuantisation)
    {
        unexplained.push(
            "found, not in the catalog: the output is quantised (data check output_quantisation); quantisation is measurement noise bounded by half a step and is left in the residual".into(),
        );
    }
    let fired = final_tests.fired_names();
    let unscorable = unexplained
        .iter()
        .any(|u| u.starts_with("the estimation data cannot score"));
    let verdict = if steps.is_empty() && unscorable {
        format!(
            "The estimation data cannot score any extension (the inner hold-out block holds behaviour the rest of the record does not show): nothing is added, and the tests that fire ({}) are reported without a diagnosis.",
            fired.join(", ")
        )
    } else if steps.is_empty() && fired.is_empty() {
        "No test fires on the estimation residual: the residual is consistent with the model, nothing is added.".to_string()
    } else if steps.is_empty() {
        format!(
            "Tests fire ({}) but no catalog effect explains them: the missing effect is not identified; the model is left as identified.",
            fired.join(", ")
        )
    } else {
        let names: Vec<&str> = steps.iter().map(|s| s.effect.name()).collect();
        let rest = if fired.is_empty() {
            "the final residual is consistent with the extended model".to_string()
        } else if unscorable {
            format!(
                "then the estimation data could not score further extensions; tests still fire ({})",
                fired.join(", ")
            )
        } else if steps.last().is_some_and(|s| !s.effect.deterministic()) {
            format!(
                "the noise model is the last step; on the simulation residual tests still fire ({}) that no deterministic catalog effect explained",
                fired.join(", ")
            )
        } else if no_candidate {
            format!(
                "tests still fire ({}) and no further catalog effect explains them",
                fired.join(", ")
            )
        } else {
            format!(
                "the step limit was reached with tests still firing ({})",
                fired.join(", ")
            )
        };
        // Effects found outside the catalog are named, not counted as unexplained tests.
        let outside: Vec<&str> = unexplained
            .iter()
            .filter_map(|u| u.strip_prefix("found, not in the catalog: "))
            .filter_map(|u| u.split(" (").next())
            .collect();
        let rest = if outside.is_empty() {
            rest
        } else {
            format!("{rest}; found, not in the catalog: {}", outside.join("; "))
        };
        let last_metric = match steps.last().map(|s| s.metric) {
            Some(Metric::Prediction) => " (the last in one-step prediction)",
            _ => "",
        };
        format!(
            "Added {} (in this order); validation error {:.4} → {:.4}{last_metric}; {rest}.",
            names.join(", "),
            before.rmse,
            steps.last().map_or(after.rmse, |s| s.error_after)
        )
    };
    Ok(Diagnosis {
        nonlinearity: opts.nonlinearity,
        data_description: description,
        estimation_samples: est.len(),
        validation_samples: vrange.len(),
        warnings,
        base,
        model,
        steps,
        rejected,
        unexplained,
        verdict,
        paper,
        before,
        poles_refined: opts.refine_poles != PoleRefinement::Never,
        after,
        after_prediction,
        tests_before,
        tests_after,
        tests_estimation: final_tests,
        validation_record: vrec,
        validation_range: vrange,
        dead_time: dead,
    })
}

/// The dead-time test's finding, in words.
pub fn dead_time_text(d: &delay::DeadTime) -> String {
    match d.lag {
        Some(l) => format!(
            "dead_time: the output first responds to the input at lag {l} (ARX({}) likelihood-ratio tests of no response at lags 0…j: p = {} for j = 0…{l}), the model at lag {}: {} extra samples",
            d.ar_order,
            d.p_values
                .iter()
                .take(l + 1)
                .map(|p| format!("{p:.2e}"))
                .collect::<Vec<_>>()
                .join(", "),
            d.model_lag,
            d.extra()
        ),
        None => "dead_time: no lag tested is significant".into(),
    }
}
