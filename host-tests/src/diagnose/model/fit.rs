//! The extended model fitted on a record by backfitting.

use std::ops::Range;

use crate::diagnose::dynamics::{Borders, DynamicsFit};
use crate::diagnose::error::DiagnoseError;
use crate::diagnose::output_map::OutputMap;
use crate::diagnose::simulate::delay_input;
use crate::diagnose::stores::{self, StoresClass};
use crate::identify::HostModel;
use crate::validation::noise::fit_ar;

use super::additive::Additive;
use super::borders::{estimate_x0, refit_borders};
use super::element::fit_element;
use super::estimator::{Estimator, estimate};
use super::extended::ExtendedModel;
use super::fit_options::{FitOptions, InitialState};
use super::friction::fit_friction_into;
use super::outliers::detect_outliers;
use super::poles::{refine_poles, refine_poles_mapped};
use super::refine_linear::{LinearFitParams, refine_linear};
use super::structure::Structure;
use super::two_mass::fit_two_mass_into;
use crate::model::Record;

/// Fits a structure on a record.
pub fn fit_structure(
    s: &Structure,
    rec: &Record,
    opts: &FitOptions,
) -> Result<ExtendedModel, DiagnoseError> {
    fit_structure_impl(s, rec, opts, None)
}

/// [`fit_structure`] for a fold of the cross-validation: `fit_part` is `whole` without the
/// samples `block`, joined at the gap. The linear part is fitted on `fit_part`; the
/// level-dependent stores and the element with memory, whose simulation error a join would
/// corrupt, on the simulation of `whole` with the block's samples left out of the error (the
/// input is known throughout).
pub fn fit_structure_fold(
    s: &Structure,
    fit_part: &Record,
    opts: &FitOptions,
    whole: &Record,
    block: Range<usize>,
) -> Result<ExtendedModel, DiagnoseError> {
    fit_structure_impl(s, fit_part, opts, Some((whole, block)))
}

/// Fits level-dependent stores to a fitted model ([`Dynamics::Stores`]): started from its
/// linear part, on the simulation error of `rec` without the `skip` samples, the borders
/// refitted with them, the output map and the additive terms held.
pub(super) fn fit_stores(
    model: &mut ExtendedModel,
    rec: &Record,
    skip: &[bool],
    opts: &FitOptions,
    class: StoresClass,
) -> Result<(), DiagnoseError> {
    let ud = delay_input(&rec.u, model.structure.delay);
    let h = model.hammerstein.nonlinearity_output(&ud);
    let target = model.less_additive(rec);
    let data = DynamicsFit {
        h: &h,
        y: &target,
        skip,
        map: model.output_map.as_ref(),
        fit_x0: true,
        radius_limit: 1.0,
        iterations: stores::ITERATIONS,
        borders: Some(Borders {
            u: &ud,
            shared: opts.identify.static_nonlinearity,
        }),
    };
    let (st, hm) = stores::fit(&model.hammerstein, &model.x0, &data, class)
        .map_err(DiagnoseError::Dynamics)?;
    model.hammerstein = hm;
    model.stores = Some(st);
    Ok(())
}

pub(super) fn fit_structure_impl(
    s: &Structure,
    rec: &Record,
    opts: &FitOptions,
    held: Option<(&Record, Range<usize>)>,
) -> Result<ExtendedModel, DiagnoseError> {
    // End stops fitted to the data stand in for the levels the data check finds.
    let stopped;
    let opts = match &s.end_stop {
        Some(stop) => {
            stopped = FitOptions {
                saturation: stop.levels,
                ..opts.clone()
            };
            &stopped
        }
        None => opts,
    };
    // With an element, an output map is the output saturation clamping the element's
    // simulation ([`fit_element`]); the linear part that starts the element's fit is the
    // element's without it.
    let full = s;
    let unclamped;
    let clamp = (full.element.is_some() && full.output_map_segments.is_some())
        .then_some(&opts.saturation)
        .filter(|sat| sat.any());
    let s = if full.element.is_some() && full.output_map_segments.is_some() {
        unclamped = Structure {
            output_map_segments: None,
            ..full.clone()
        };
        &unclamped
    } else {
        full
    };
    // Stores start from the linear part refined on the simulation error: the subspace
    // estimate of a slow, well-damped plant can put a lightly damped complex pair where the
    // plant has two real poles. The closed-loop estimate from a reference is not refined (see
    // [`Estimator`]).
    let refined;
    let refine =
        Estimator::of(rec).refines_poles() && (opts.refine_poles || s.dynamics.stores().is_some());
    let opts = if refine != opts.refine_poles {
        refined = FitOptions {
            refine_poles: refine,
            ..opts.clone()
        };
        &refined
    } else {
        opts
    };
    let n = rec.len();
    let ud = delay_input(&rec.u, s.delay);
    let rd = rec.reference.as_ref().map(|r| delay_input(r, s.delay));
    let mut idopts = opts.identify.clone();
    // The subspace estimate is only the start: the poles are refined on the simulation error
    // below and a model too slow for the record is refused there, so a slow plant's pole that
    // the subspace step puts just outside the unit circle is taken here.
    idopts.poles = hsid::Poles::Any;
    if s.order.is_some() {
        idopts.order = s.order;
    }
    if let Some(h) = s.horizon {
        idopts.f = h;
        idopts.p = h;
    }
    let mut additive = Additive {
        trend: vec![0.0; s.trend_degree.map_or(0, |d| d + 1)],
        settling: s.settling.map(|k| (k, 0.0)),
        frequencies: s.frequencies.clone(),
        sin_cos: vec![(0.0, 0.0); s.frequencies.len()],
        center: opts.time_center,
        scale: opts.time_scale.max(1.0),
    };
    let mut map: Option<OutputMap> = None;
    let mut flags = vec![false; n];
    // Outliers flagged without a re-estimation: left out of the error and of the noise model.
    let mut excluded = vec![false; n];
    let mut lin_prev: Option<Vec<f64>> = None;
    let rounds = s.rounds().min(opts.rounds.max(1));
    let mut last: Option<(HostModel, Vec<f64>)> = None;
    let mut best_round: Option<(f64, HostModel, Vec<f64>, Option<OutputMap>)> = None;
    for _ in 0..rounds {
        let add: Vec<f64> = rec.time.iter().map(|&t| additive.eval(t)).collect();
        let mut target: Vec<f64> = rec.y.iter().zip(&add).map(|(y, a)| y - a).collect();
        // Samples whose target is imputed from the previous iterate: outliers, and outputs on a
        // flat part of the output map. The subspace step needs every sample (imputed); the
        // least-squares refit leaves them out.
        let mut imputed = flags.clone();
        if let Some(lp) = &lin_prev {
            if let Some(g) = &map {
                let min_slope = 0.1 * g.mean_slope().max(0.0);
                for ((tv, &l), im) in target.iter_mut().zip(lp).zip(imputed.iter_mut()) {
                    match g.invert(*tv, min_slope).filter(|x| x.is_finite()) {
                        Some(x) => *tv = x,
                        None => {
                            *tv = l;
                            *im = true;
                        }
                    }
                }
            }
            for (i, &f) in flags.iter().enumerate() {
                if f {
                    target[i] = lp[i];
                }
            }
        }
        let m = match estimate(&ud, &target, rd.as_deref(), &idopts) {
            Ok(m) => m,
            // A later round is identified on the output inverted through the map, its
            // clipped samples imputed: where that estimate fails, the best round before it
            // stands (as when it fits worse).
            Err(_)
                if s.output_map_segments.is_some() && !s.robust_refit && best_round.is_some() =>
            {
                if let Some((_, bm, bx, bg)) = &best_round {
                    last = Some((bm.clone(), bx.clone()));
                    map = bg.clone();
                }
                break;
            }
            Err(e) => return Err(e),
        };
        let refit = if opts.refit {
            refit_borders(
                &m,
                &ud,
                &target,
                &imputed,
                opts.initial,
                idopts.static_nonlinearity,
            )
        } else {
            None
        };
        let (m, x0) = match refit {
            Some(r) => r,
            None => {
                let h = m.nonlinearity_output(&ud);
                let x0 = match opts.initial {
                    InitialState::Rest => m.rest_state(),
                    InitialState::Estimated => estimate_x0(&m, &h, &target, &imputed),
                };
                (m, x0)
            }
        };
        let minus_add: Vec<f64> = rec.y.iter().zip(&add).map(|(y, a)| y - a).collect();
        let params = LinearFitParams {
            u: &ud,
            y: &minus_add,
            skip: &flags,
            map_segments: s.output_map_segments,
            sat: &opts.saturation,
            initial: opts.initial,
            shared: idopts.static_nonlinearity,
        };
        let (m, x0) = if opts.refit {
            let (m2, x2, g) = refine_linear(&m, &x0, &params);
            if g.is_some() {
                map = g;
            }
            (m2, x2)
        } else {
            (m, x0)
        };
        let (m, x0) = if opts.refine_poles && s.output_map_segments.is_none() {
            refine_poles(&m, &x0, &params).unwrap_or((m, x0))
        } else if opts.refine_poles && opts.refit {
            match refine_poles_mapped(&m, &x0, &params) {
                Some((m2, x2, g)) => {
                    if g.is_some() {
                        map = g;
                    }
                    (m2, x2)
                }
                None => (m, x0),
            }
        } else {
            (m, x0)
        };
        let h = m.nonlinearity_output(&ud);
        let lin = m.linear_response(&h, &x0);
        let out: Vec<f64> = lin
            .iter()
            .map(|&l| map.as_ref().map_or(l, |g| g.eval(l)))
            .collect();
        let r: Vec<f64> = rec.y.iter().zip(&out).map(|(y, o)| y - o).collect();
        // With an output map, a later round (identified on the inverted output) is kept only if
        // it fits better: the inversion can mislead the subspace step.
        if s.output_map_segments.is_some() && !s.robust_refit {
            let sse: f64 = r
                .iter()
                .zip(&rec.time)
                .map(|(v, &t)| (v - additive.eval(t)).powi(2))
                .sum();
            if let Some((best_sse, bm, bx, bg)) = &best_round
                && sse.partial_cmp(best_sse) != Some(std::cmp::Ordering::Less)
            {
                let h = bm.nonlinearity_output(&ud);
                lin_prev = Some(bm.linear_response(&h, bx));
                last = Some((bm.clone(), bx.clone()));
                map = bg.clone();
                continue;
            }
            best_round = Some((sse, m.clone(), x0.clone(), map.clone()));
        }
        additive.fit(&r, &rec.time, &flags);
        if s.robust {
            let res: Vec<f64> = r
                .iter()
                .zip(&rec.time)
                .map(|(v, &t)| v - additive.eval(t))
                .collect();
            // Flags feed the next round's imputation only for a re-estimation.
            let detected = detect_outliers(&res, opts.outlier_k);
            if s.robust_refit {
                flags = detected;
            } else {
                excluded = detected;
            }
        }
        lin_prev = Some(lin);
        last = Some((m, x0));
    }
    let Some((hammerstein, x0)) = last else {
        return Err(DiagnoseError::TooShort {
            samples: n,
            need: 1,
        });
    };
    let mut model = ExtendedModel {
        structure: full.clone(),
        hammerstein,
        x0,
        output_map: map,
        additive,
        noise: None,
        outlier_k: opts.outlier_k,
        flagged: flags
            .iter()
            .zip(&excluded)
            .filter(|(a, b)| **a || **b)
            .count(),
        stores: None,
        hysteresis: None,
        friction: None,
        two_mass: None,
    };
    if let Some(kind) = s.element {
        let shared = opts.identify.static_nonlinearity;
        match &held {
            Some((whole, block)) => {
                let skip: Vec<bool> = (0..whole.len()).map(|t| block.contains(&t)).collect();
                fit_element(&mut model, whole, &skip, kind, shared, rec.len(), clamp)?;
            }
            None => fit_element(&mut model, rec, &flags, kind, shared, rec.len(), clamp)?,
        }
    }
    if s.friction {
        match &held {
            Some((whole, block)) => {
                let skip: Vec<bool> = (0..whole.len()).map(|t| block.contains(&t)).collect();
                fit_friction_into(&mut model, whole, &skip, s.friction_on_speed)?;
            }
            None => fit_friction_into(&mut model, rec, &flags, s.friction_on_speed)?,
        }
    }
    if s.play_between {
        match &held {
            Some((whole, block)) => {
                let skip: Vec<bool> = (0..whole.len()).map(|t| block.contains(&t)).collect();
                fit_two_mass_into(&mut model, whole, &skip)?;
            }
            None => fit_two_mass_into(&mut model, rec, &flags)?,
        }
    }
    if let Some(class) = s.dynamics.stores() {
        match held {
            Some((whole, block)) => {
                let skip: Vec<bool> = (0..whole.len()).map(|t| block.contains(&t)).collect();
                fit_stores(&mut model, whole, &skip, opts, class)?;
            }
            None => fit_stores(&mut model, rec, &flags, opts, class)?,
        }
    }
    if let Some(p) = s.noise_ar_order {
        let sim = model.simulate(&rec.u, &rec.time);
        let r: Vec<f64> = rec
            .y
            .iter()
            .zip(&sim)
            .zip(flags.iter().zip(&excluded))
            .map(|((y, s), (&f, &e))| if f || e { 0.0 } else { y - s })
            .collect();
        model.noise = fit_ar(&r, p);
    }
    Ok(model)
}
