//! The loop: at each step the current model's estimation residual is tested, every effect
//! with evidence is proposed and fitted on the estimation data (its setting chosen on the
//! inner validation), scored there, and the best is added if it gains enough — or the loop
//! stops, with what no effect explains recorded as findings.

use std::ops::Range;

use super::delay::DeadTime;
use super::diagnosis::{Rejected, Step};
use super::effects::candidate::compare_common;
use super::effects::{self, Candidate, Effect, Holdout, Proposal};
use super::end_stop::{EndStops, fit_levels};
use super::error::DiagnoseError;
use super::evidence::{Tried, evidence};
use super::findings::Finding;
use super::model::{self, Evaluation, ExtendedModel, FitOptions, Metric, Structure};
use super::options::{DiagnoseOptions, Proposing};
use super::scoring::residual_tests;
use super::verdict::Ending;
use crate::model::Record;
use crate::validation::checks::{Check, Warning};
use crate::validation::residual::TestSet;

/// What the loop works with; nothing here changes while it runs.
pub(crate) struct Context<'a> {
    /// The estimation record.
    pub est: &'a Record,
    /// The record the validation simulation runs over.
    pub validation: &'a Record,
    /// Its scored samples.
    pub range: Range<usize>,
    /// The diagnosis settings.
    pub opts: &'a DiagnoseOptions,
    /// The inner validation.
    pub holdout: &'a Holdout<'a>,
    /// Its single held-out block.
    pub block: &'a Range<usize>,
    /// Fit options of the models reported.
    pub reported: &'a FitOptions,
    /// The data checks.
    pub warnings: &'a [Warning],
    /// The dead time of the estimation data.
    pub dead: &'a DeadTime,
    /// Leave-block-out cross-validation over tenths of the whole estimation record, scoring
    /// the dead-time test's delay when the inner validation is one block and the record can
    /// be cross-validated: a delay shows only at the input's changes, which one block may
    /// hold few of, while the test that found it used the whole record.
    pub delay_holdout: Option<&'a Holdout<'a>>,
    /// A single held-out block inside the record, scoring the steps once the structure has a
    /// trend or settling in time (see
    /// [`InnerValidation::interior`](super::inner::InnerValidation::interior)).
    pub interior: Option<&'a Holdout<'a>>,
}

/// What the loop has done so far.
pub(crate) struct Progress {
    /// The current structure.
    pub current: Structure,
    /// The current model (fitted on the whole estimation record).
    pub model: ExtendedModel,
    /// Effects added.
    pub steps: Vec<Step>,
    /// Effects with evidence not added at the last step.
    pub rejected: Vec<Rejected>,
    /// What no effect explains.
    pub findings: Vec<Finding>,
    /// Validation evaluation of the current model.
    pub previous_validation: Evaluation,
    /// The tests of the last step, when it added nothing.
    pub final_tests: Option<TestSet>,
    /// How the loop ended.
    pub ending: Ending,
}

/// Whether the loop goes on.
enum Flow {
    Continue,
    Stop,
}

impl Context<'_> {
    /// The inner validation that scores extensions of `current`, and its block. The block at
    /// the record's end, unless `current` has a trend or a settling in time and a block inside
    /// the record can be held out: the term, fitted without the end block, extrapolates into
    /// it, and the next effect would be chosen for fitting that extrapolation's error (a sixth
    /// order fitted it in the second family's drift seed 3, and raised the validation error).
    fn inner(&self, current: &Structure) -> (&Holdout<'_>, &Range<usize>) {
        match self.interior {
            Some(h) if current.trend_degree.is_some() => (h, &h.range),
            _ => (self.holdout, self.block),
        }
    }

    fn hold(&self) -> usize {
        self.reported.identify.hold
    }

    fn in_sample(&self, m: &ExtendedModel) -> Evaluation {
        let (hold, ne) = (self.hold(), self.est.len());
        model::evaluate(m, self.est, hold..ne, Metric::Simulation)
    }

    /// Runs at most [`DiagnoseOptions::max_steps`] steps; none when the output integrates
    /// (the data check `integrating`): the base model's normalisation `G(1) = 1` does not
    /// hold, its simulation error is the integrator's drift, and an extension scored against
    /// it is fitted to that drift (an output map added to such a model raised the validation
    /// error thirtyfold in the second scenario family).
    pub fn run(&self, p: &mut Progress) -> Result<(), DiagnoseError> {
        if self.warnings.iter().any(|w| w.check == Check::Integrating) {
            p.findings.push(Finding::Integrating);
            return Ok(());
        }
        for k in 1..=self.opts.max_steps {
            crate::progress::stage(|| {
                format!(
                    "diagnose step {k} of at most {}: testing the residual",
                    self.opts.max_steps
                )
            })?;
            if let Flow::Stop = self.step(p)? {
                break;
            }
        }
        Ok(())
    }

    /// One step: test, propose, choose, refit, record.
    fn step(&self, p: &mut Progress) -> Result<Flow, DiagnoseError> {
        let (hold, ne) = (self.hold(), self.est.len());
        let shared = self.reported.identify.static_nonlinearity;
        let ev = self.in_sample(&p.model);
        let tests = residual_tests(&p.model, self.est, hold..ne, &ev, shared);
        let (holdout, block) = self.inner(&p.current);
        let (inner_model, baseline) =
            match holdout.evaluate_folds(&p.current, Metric::Simulation, false) {
                Ok(Some(v)) => v,
                Ok(None) => return Ok(Flow::Stop),
                // The current model cannot be fitted without one of the blocks: nothing can
                // be scored against it.
                Err(e @ (DiagnoseError::Identify(_) | DiagnoseError::Dynamics(_))) => {
                    p.findings.push(Finding::FoldsUnfittable {
                        error: e.to_string(),
                    });
                    return Ok(Flow::Stop);
                }
                Err(e) => return Err(e),
            };
        // The inner hold-out can only score extensions if the model fitted without the block
        // predicts the block about as well as the model fits the record: three times the
        // in-sample error means the fitting part leaves the block's behaviour unseen (a level
        // or input range visited only there), and every score would be noise.
        let in_sample = self.in_sample(&p.model).rmse;
        if baseline.rmse.is_nan() || baseline.rmse > 3.0 * in_sample {
            p.findings.push(Finding::BlockUnscorable {
                start: block.start,
                end: block.end,
                rmse: baseline.rmse,
                in_sample,
            });
            return Ok(Flow::Stop);
        }
        let proposal = Proposal {
            holdout,
            current: &p.current,
            baseline: &baseline,
            inner_model: &inner_model,
            order: p.model.hammerstein.order,
            f: p.current.horizon.unwrap_or(self.reported.identify.f),
            max_delay: self.opts.max_delay,
            min_gain: self.opts.min_gain,
            residual: &ev.residual,
            input: &self.est.u[hold..],
            tests: &tests,
            increments: self.opts.increments,
            every: self.opts.proposing == Proposing::Every,
        };
        // The end stops the model's simulation shows on the estimation record (evidence of an
        // output nonlinearity the data check cannot see; not for an integrating plant's
        // increments, whose simulation is not the output's level).
        let idx: Vec<usize> = (hold..ne).collect();
        let stops = (!self.opts.increments)
            .then(|| fit_levels(&self.est.y, &ev.output, &idx))
            .flatten();
        let (mut cands, chosen) =
            self.candidates(&proposal, &tests, stops.as_ref(), &baseline, &p.current)?;
        let (chosen, refitted) = self.refit(&mut cands, chosen)?;
        let Some(ci) = chosen else {
            self.reject(p, &cands, tests, stops.as_ref());
            return Ok(Flow::Stop);
        };
        let Some(new_model) = refitted else {
            return Ok(Flow::Stop);
        };
        let deterministic = cands[ci].effect.deterministic();
        self.record(p, &cands, ci, new_model, &tests, stops.as_ref());
        Ok(if deterministic {
            Flow::Continue
        } else {
            Flow::Stop
        })
    }

    /// The candidates of this step and the one chosen, if any: every deterministic effect with
    /// evidence, then the dead-time test's delay, then a noise model.
    fn candidates(
        &self,
        proposal: &Proposal,
        tests: &TestSet,
        stops: Option<&EndStops>,
        baseline: &Evaluation,
        current: &Structure,
    ) -> Result<(Vec<Candidate>, Option<usize>), DiagnoseError> {
        let (min_gain, tie) = (self.opts.min_gain, self.opts.tie);
        let every = self.opts.proposing == Proposing::Every;
        let tried: Vec<Effect> = Effect::PROPOSED
            .into_iter()
            .filter(|&e| {
                // A saturated output found by the data checks, or end stops the model's
                // simulation goes beyond, is direct evidence of an output nonlinearity, even
                // when the residual tests lack power.
                let saturated = e == Effect::OutputNonlinearity
                    && (stops.is_some()
                        || self
                            .warnings
                            .iter()
                            .any(|w| w.check == Check::OutputSaturation));
                e.deterministic() && (effects::has_evidence(e, tests) || saturated || every)
            })
            .collect();
        // The effects are proposed independently: across the cores, kept in their order.
        let proposed = crate::progress::map(&tried, |_, &e| {
            crate::progress::stage(|| format!("diagnose: trying {}", e.name()))?;
            proposal.propose(e)
        });
        let mut cands = Vec::new();
        for c in proposed {
            cands.extend(c?);
        }
        let mut chosen = effects::choose(&cands, min_gain, tie);
        if chosen.is_none() && current.delay == 0 && self.dead.extra() > 0 {
            chosen = self.dead_time_candidate(current, baseline, &mut cands)?;
        }
        if chosen.is_none()
            && effects::has_evidence(Effect::ColoredNoise, tests)
            && let Some(c) = proposal.propose(Effect::ColoredNoise)?
        {
            cands.push(c);
            let last = cands.len() - 1;
            if effects::choose(&cands[last..], min_gain, tie).is_some() {
                chosen = Some(last);
            }
        }
        Ok((cands, chosen))
    }

    /// The dead time of the data (ARX test, independent of the simulation error) beyond the
    /// model's: a delay found by a test at 1 %, proposed like every deterministic effect and
    /// added only if it improves the inner score significantly (the rule of
    /// [`effects::choose`]: Diebold–Mariano at 1 % and at least the minimum gain), the score
    /// taken over the whole record by cross-validation where it can be
    /// ([`Context::delay_holdout`]). No step that does not help is taken on the strength of
    /// the ARX test alone.
    fn dead_time_candidate(
        &self,
        current: &Structure,
        baseline: &Evaluation,
        cands: &mut Vec<Candidate>,
    ) -> Result<Option<usize>, DiagnoseError> {
        let mut s = current.clone();
        s.delay = self.dead.extra();
        let holdout = self.delay_holdout.unwrap_or(self.inner(current).0);
        let fitted = |st: &Structure, check_slow| match holdout.evaluate_folds(
            st,
            Metric::Simulation,
            check_slow,
        ) {
            Err(DiagnoseError::Identify(_) | DiagnoseError::Dynamics(_)) => Ok(None),
            other => other,
        };
        let base = match self.delay_holdout {
            Some(_) => fitted(current, false)?.map(|(_, ev)| ev),
            None => Some(baseline.clone()),
        };
        let (Some(base), Some((m, ev))) = (base, fitted(&s, true)?) else {
            return Ok(None);
        };
        let (gain, p_value) = effects::compare(&base, &ev);
        // One input_delay candidate: the dead-time test's delay replaces the one the screen
        // proposed (whose settings stay listed as tried).
        let mut tried = Vec::new();
        if let Some(i) = cands.iter().position(|c| c.effect == Effect::InputDelay) {
            tried = cands.remove(i).tried;
        }
        tried.push(Tried::DeadTime {
            delay: self.dead.extra(),
            rmse: ev.rmse,
            blocks: holdout.folds.len(),
        });
        cands.push(Candidate {
            effect: Effect::InputDelay,
            structure: s,
            inner_model: m,
            tried,
            evaluation: ev,
            gain,
            p_value,
            significance: effects::Significance::DieboldMariano,
            complexity: 1.0,
        });
        let last = cands.len() - 1;
        let (min_gain, tie) = (self.opts.min_gain, self.opts.tie);
        Ok(effects::choose(&cands[last..], min_gain, tie).map(|_| last))
    }

    /// The chosen extension refitted on the whole estimation record; if that model has a mode
    /// too slow to validate, the next candidate is taken. The refit must also fit the
    /// estimation record at least about as well as the hold-out model does (a subspace fit can
    /// land on a poor local solution); otherwise the hold-out model, fitted on 70 % of the
    /// same data, is kept.
    fn refit(
        &self,
        cands: &mut [Candidate],
        mut chosen: Option<usize>,
    ) -> Result<(Option<usize>, Option<ExtendedModel>), DiagnoseError> {
        let ne = self.est.len();
        while let Some(ci) = chosen {
            let inner = &cands[ci].inner_model;
            // An extension that cannot be fitted on the whole record keeps its hold-out fit.
            let m = match model::fit_structure(&cands[ci].structure, self.est, self.reported) {
                Err(DiagnoseError::Identify(_) | DiagnoseError::Dynamics(_)) => inner.clone(),
                other => other?,
            };
            let rmse_full = self.in_sample(&m).rmse;
            let rmse_inner = self.in_sample(inner).rmse;
            let m = if rmse_full.is_finite() && rmse_full <= 1.1 * rmse_inner {
                m
            } else {
                inner.clone()
            };
            if !effects::too_slow(&m, ne) {
                return Ok((chosen, Some(m)));
            }
            cands[ci].gain = f64::NEG_INFINITY;
            chosen = effects::choose(cands, self.opts.min_gain, self.opts.tie);
        }
        Ok((None, None))
    }

    /// Nothing passed: the candidates are rejected and every test that fired is a finding.
    fn reject(
        &self,
        p: &mut Progress,
        cands: &[Candidate],
        tests: TestSet,
        stops: Option<&EndStops>,
    ) {
        p.rejected = cands
            .iter()
            .map(|c| Rejected {
                effect: c.effect,
                evidence: evidence(c.effect, &tests, self.dead, self.warnings, stops),
                inner_gain: c.gain,
                inner_p: c.p_value,
                inner_test: c.significance,
            })
            .collect();
        for t in tests.tests.iter().filter(|t| t.fired) {
            let tried = cands
                .iter()
                .filter(|c| c.effect.evidence_tests().contains(&t.name))
                .map(|c| (c.effect, c.gain, c.p_value))
                .collect();
            p.findings.push(Finding::NotExplained {
                test: t.name,
                detail: t.detail.clone(),
                p_value: t.p_value,
                tried,
            });
        }
        p.final_tests = Some(tests);
        p.ending = Ending::NoCandidate;
    }

    /// Candidate `ci` is added: its step is recorded with the validation error before and after.
    fn record(
        &self,
        p: &mut Progress,
        cands: &[Candidate],
        ci: usize,
        new_model: ExtendedModel,
        tests: &TestSet,
        stops: Option<&EndStops>,
    ) {
        let c = &cands[ci];
        let metric = if c.effect.deterministic() {
            Metric::Simulation
        } else {
            Metric::Prediction
        };
        let after = model::evaluate(&new_model, self.validation, self.range.clone(), metric);
        // The previous model on the same samples (outliers of the new model excluded).
        let prev = &p.previous_validation;
        let error_before = if after.excluded.iter().any(|&e| e) {
            let mut s = 0.0;
            let mut k = 0usize;
            for (r, &e) in prev.residual.iter().zip(&after.excluded) {
                if !e {
                    s += r * r;
                    k += 1;
                }
            }
            (s / k.max(1) as f64).sqrt()
        } else {
            prev.rmse
        };
        p.steps.push(Step {
            effect: c.effect,
            evidence: evidence(c.effect, tests, self.dead, self.warnings, stops),
            setting: effects::setting(c.effect, &c.structure, Some(&new_model)),
            inner_gain: c.gain,
            inner_p: c.p_value,
            inner_test: c.significance,
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
            p_worse: compare_common(&after, prev).1,
            nrmse_after: after.nrmse,
            fit_after: after.fit_percent,
            excluded: after.excluded.iter().filter(|&&e| e).count(),
            model: new_model.clone(),
        });
        p.current = c.structure.clone();
        p.model = new_model;
        p.previous_validation = after;
    }
}
