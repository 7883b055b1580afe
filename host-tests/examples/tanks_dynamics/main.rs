//! What model classes beyond the catalog can do on the cascaded tanks benchmark, and whether
//! the estimation data could choose them: a polynomial state term ([`poly`], fitted by
//! [`poly_fit`]) and an internal overflow ([`overflow`]).
//!
//! Settings as `hsid diagnose` uses them in README ("Closing the loop on measured data"):
//! static input border with 7 uniform segments (its BIC choice), order 2, no hold, poles
//! refined on the simulation error, with and without the 5-segment output map clipped at the
//! overflow it adds. On top of each: a polynomial state term of degree 2 and 3, and the
//! internal overflow (a cascade of two stores, the first spilling into the second).
//!
//! Three numbers per model:
//! * in-sample: simulation RMSE on the estimation record it was fitted on;
//! * cross-validation: the blocks `hsid diagnose` scores (tenths of the estimation record
//!   that the base model fitted without them simulates within 3 × its in-sample error),
//!   each left out in turn: the base model fitted on the rest joined at the gap, the
//!   extension fitted on the simulation of the whole record with the block's samples left
//!   out of its error, scored on the block; the squared errors pooled. This is the score
//!   that could choose a model from the estimation data alone;
//! * validation: fitted on the whole estimation record, simulated on the validation record
//!   from the estimated rest level (not allowed for choosing; it bounds what the class does).
//!
//! ```text
//! cargo run --release -p hsid-host --example tanks_dynamics [DATA.csv]
//! ```

use std::ops::Range;

mod error;
#[cfg(test)]
#[path = "../../src/diagnose/stores/fixtures.rs"]
mod fixtures;
mod overflow;
mod poly;
mod poly_fit;
#[cfg(test)]
mod tests;

use hsid_host::diagnose::dynamics::{Borders, DynamicsFit};
use hsid_host::diagnose::effects::Holdout;
use hsid_host::diagnose::model::{
    self, ExtendedModel, FitOptions, InitialState, Metric, Structure,
};
use hsid_host::diagnose::simulate;
use hsid_host::model::Record;
use hsid_host::validation::{checks, residual};
// The shared test fixtures name the model through their parent module.
#[cfg(test)]
use hsid_host::identify::HostModel;
use hsid_host::identify::IdentifyOptions;
use hsid_host::io::read_columns;

use crate::error::ClassError;

/// A model class on top of a fitted model.
#[derive(Clone, Copy)]
enum Class {
    Linear,
    /// Degree, and whether the borders are refitted with it.
    Polynomial(usize, bool),
    Overflow,
}

impl Class {
    fn label(self) -> String {
        match self {
            Class::Linear => "—".into(),
            Class::Polynomial(d, false) => format!("state polynomial, degree {d}"),
            Class::Polynomial(d, true) => format!("state polynomial, degree {d}, borders refitted"),
            Class::Overflow => "internal overflow".into(),
        }
    }
}

/// A fitted model's simulation of a record.
type Simulator = Box<dyn Fn(&Record) -> Vec<f64>>;

/// An extension fitted: its simulator and what the steady-state check says.
struct Fitted {
    simulate: Simulator,
    steady: String,
}

/// The extension of `base` fitted on `rec` (samples with `skip` left out of the error);
/// returns the simulator of the whole model for an input record.
fn extend(
    class: Class,
    base: &ExtendedModel,
    rec: &Record,
    skip: &[bool],
) -> Result<Fitted, String> {
    let hm = base.hammerstein.clone();
    let target: Vec<f64> = rec
        .y
        .iter()
        .zip(&rec.time)
        .map(|(y, &t)| y - base.additive.eval(t))
        .collect();
    let ud = simulate::delay_input(&rec.u, base.structure.delay);
    let hr = hm.nonlinearity_output(&ud);
    let refit_borders = matches!(class, Class::Polynomial(_, true));
    let data = DynamicsFit {
        h: &hr,
        y: &target,
        skip,
        map: base.output_map.as_ref(),
        fit_x0: true,
        radius_limit: 1.0 - 0.5 / rec.len().max(4) as f64,
        iterations: 30,
        // The tanks' input nonlinearity is static: one border for both directions.
        borders: refit_borders.then_some(Borders {
            u: &ud,
            shared: true,
        }),
    };
    let b = base.clone();
    let finish = move |lin: Option<Vec<f64>>, r: &Record| -> Vec<f64> {
        lin.unwrap_or_else(|| vec![f64::NAN; r.len()])
            .iter()
            .zip(&r.time)
            .map(|(&l, &t)| b.output_map.as_ref().map_or(l, |g| g.eval(l)) + b.additive.eval(t))
            .collect()
    };
    let delay = base.structure.delay;
    Ok(match class {
        Class::Linear => {
            let b = base.clone();
            Fitted {
                simulate: Box::new(move |r: &Record| b.simulate(&r.u, &r.time)),
                steady: "one (linear)".into(),
            }
        }
        Class::Polynomial(degree, _) => {
            let (m, poly, x0) =
                poly_fit::fit(&hm, &base.x0, degree, &data).map_err(|e| e.to_string())?;
            let h_fit = m.nonlinearity_output(&ud);
            let steady = match poly::unique_steady_states(&m, &poly, &h_fit, &x0) {
                Ok(()) => "one".to_string(),
                Err(ClassError::Multistable { level, outputs }) => format!(
                    "more than one: at h = {level:.2} ({:.2} V and {:.2} V)",
                    outputs.0, outputs.1
                ),
                Err(e) => e.to_string(),
            };
            Fitted {
                simulate: Box::new(move |r: &Record| {
                    let h = m.nonlinearity_output(&simulate::delay_input(&r.u, delay));
                    finish(poly::simulate(&m, Some(&poly), &h, &x0), r)
                }),
                steady,
            }
        }
        Class::Overflow => {
            let o = overflow::fit_overflow(&hm, &base.x0, &data).map_err(|e| e.to_string())?;
            Fitted {
                simulate: Box::new(move |r: &Record| {
                    let h = hm.nonlinearity_output(&simulate::delay_input(&r.u, delay));
                    finish(o.simulate(&h), r)
                }),
                steady: "one (stable cascade)".into(),
            }
        }
    })
}

fn rmse(sim: &[f64], y: &[f64], r: Range<usize>) -> f64 {
    let s: f64 = r.clone().map(|t| (sim[t] - y[t]).powi(2)).sum();
    (s / r.len().max(1) as f64).sqrt()
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let path = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "../shared/data/cascaded-tanks/dataBenchmark.csv".into());
    let c = read_columns(&path, &["uEst", "yEst", "uVal", "yVal"])?;
    let est = Record::new(c[0].clone(), c[1].clone())?;
    let val = Record::new(c[2].clone(), c[3].clone())?;
    let (lo, hi) = est
        .u
        .iter()
        .chain(&val.u)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &v| {
            (l.min(v), h.max(v))
        });
    let mut id = IdentifyOptions::uniform(lo, hi, 7, 0);
    id.order = Some(2);
    id.static_nonlinearity = true;
    id.knots_desc = id.knots_asc.clone();
    let n = est.len();
    let (_, _, bins, bin_count) = residual::regressor(&est.u, &id.knots_asc, &id.knots_desc, true);
    let opts = FitOptions {
        identify: id,
        initial: InitialState::Estimated,
        time_center: 0.5 * (n as f64 - 1.0),
        time_scale: 0.5 * (n as f64 - 1.0),
        outlier_k: 5.0,
        rounds: 3,
        refit: true,
        refine_poles: true,
        saturation: checks::saturation(&est.y),
    };
    let base = model::fit_structure(&Structure::base(), &est, &opts)?;
    let in_sample0 = model::evaluate(&base, &est, 0..n, Metric::Simulation).rmse;
    let blocks: Vec<Range<usize>> = Holdout::fold_blocks(&est, 0, 10, &bins, bin_count, true)
        .into_iter()
        .filter(|r| {
            model::fit_structure(
                &Structure::base(),
                &est.joined(&[0..r.start, r.end..n]),
                &opts,
            )
            .is_ok_and(|m| {
                let e = model::evaluate(&m, &est, r.clone(), Metric::Simulation).rmse;
                e.is_finite() && e <= 3.0 * in_sample0
            })
        })
        .collect();
    let list: Vec<String> = blocks
        .iter()
        .map(|r| format!("{}..{}", r.start, r.end))
        .collect();
    println!("cross-validation blocks: {}\n", list.join(", "));
    println!(
        "| output map | dynamics | in-sample RMSE (V) | cross-validation RMSE (V) | validation RMSE (V) | steady states per input level |"
    );
    println!("|---|---|---|---|---|---|");
    for map in [None, Some(5)] {
        let mut s = Structure::base();
        s.output_map_segments = map;
        let full = model::fit_structure(&s, &est, &opts)?;
        let fold_models: Vec<Option<ExtendedModel>> = blocks
            .iter()
            .map(|r| model::fit_structure(&s, &est.joined(&[0..r.start, r.end..n]), &opts).ok())
            .collect();
        for class in [
            Class::Linear,
            Class::Polynomial(2, false),
            Class::Polynomial(3, false),
            Class::Polynomial(2, true),
            Class::Polynomial(3, true),
            Class::Overflow,
        ] {
            let map_label = map.map_or("none".to_string(), |k| format!("{k} segments"));
            let label = class.label();
            let fitted = match extend(class, &full, &est, &vec![false; n]) {
                Ok(f) => f,
                Err(e) => {
                    println!("| {map_label} | {label} | not fitted: {e} | | | |");
                    continue;
                }
            };
            let in_sample = rmse(&(fitted.simulate)(&est), &est.y, 0..n);
            let validation = rmse(&(fitted.simulate)(&val), &val.y, 0..val.len());
            let (mut sse, mut count) = (0.0, 0usize);
            let mut failed = Vec::new();
            for (r, m) in blocks.iter().zip(&fold_models) {
                let skip: Vec<bool> = (0..n).map(|t| r.contains(&t)).collect();
                let fold = m
                    .as_ref()
                    .ok_or_else(|| "the base model".to_string())
                    .and_then(|m| extend(class, m, &est, &skip));
                match fold {
                    Ok(f) => {
                        let e = rmse(&(f.simulate)(&est), &est.y, r.clone());
                        sse += e * e * r.len() as f64;
                        count += r.len();
                    }
                    Err(e) => failed.push(format!("{}..{}: {e}", r.start, r.end)),
                }
            }
            let cv = if failed.is_empty() {
                format!("{:.3}", (sse / count.max(1) as f64).sqrt())
            } else {
                format!("not fitted without block {}", failed.join("; "))
            };
            println!(
                "| {map_label} | {label} | {in_sample:.3} | {cv} | {validation:.3} | {} |",
                fitted.steady
            );
        }
    }
    // The catalog's class (static input border, linear G, output map) over a grid of its
    // settings, every combination fitted on the estimation record and scored on the
    // validation record: not a choice (the validation data choose nothing), a bound on what
    // the class can do.
    println!(
        "\nthe catalog's class on a grid (validation RMSE, V; rows: input segments, columns: output-map segments)\n"
    );
    let maps = [None, Some(1), Some(2), Some(3), Some(5), Some(8)];
    let head: Vec<String> = maps
        .iter()
        .map(|m| m.map_or("none".into(), |k| k.to_string()))
        .collect();
    println!("| input segments | {} |", head.join(" | "));
    println!("|---|{}", "---|".repeat(maps.len()));
    let mut best: Option<(f64, usize, Option<usize>)> = None;
    let mut best_unmapped: Option<(f64, usize)> = None;
    for segments in 3..=9 {
        let mut grid_opts = opts.clone();
        let u = IdentifyOptions::uniform(lo, hi, segments, 0);
        grid_opts.identify.knots_desc = u.knots_asc.clone();
        grid_opts.identify.knots_asc = u.knots_asc;
        let mut row = Vec::new();
        for map in maps {
            let mut s = Structure::base();
            s.output_map_segments = map;
            let v = model::fit_structure(&s, &est, &grid_opts).map_or(f64::NAN, |m| {
                model::evaluate(&m, &val, 0..val.len(), Metric::Simulation).rmse
            });
            row.push(format!("{v:.3}"));
            if v.is_finite() {
                if best.is_none_or(|b| v < b.0) {
                    best = Some((v, segments, map));
                }
                if map.is_none() && best_unmapped.is_none_or(|b| v < b.0) {
                    best_unmapped = Some((v, segments));
                }
            }
        }
        println!("| {segments} | {} |", row.join(" | "));
    }
    if let (Some((v, segs, map)), Some((vu, su))) = (best, best_unmapped) {
        println!(
            "\nbest: {v:.3} V ({segs} input segments, output map {}); without a map: {vu:.3} V ({su} input segments)",
            map.map_or("none".into(), |k| format!("{k} segments"))
        );
    }
    Ok(())
}
