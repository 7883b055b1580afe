//! The model to report: the refined one with its noise model and standard deviations, or the
//! subspace one with the noise model of its residual (Remark 6).

use super::{IdentifyRequest, Lines};
use crate::choose::{Best, model_std};
use crate::identify::HostModel;
use crate::model::Record;
use crate::model_file::ModelStd;
use crate::refine::pem::PemOptions;
use crate::refine::stochastic::estimate_noise;
use crate::refine::{NoiseModel, NoiseOrder};

/// The model to report and its estimator in words.
#[derive(Clone, Debug)]
pub struct Estimate {
    /// The model.
    pub model: HostModel,
    /// Its noise model, when one could be fitted.
    pub noise: Option<NoiseModel>,
    /// Standard deviations and each pole's `(re, im)` covariance, when refined.
    pub std: Option<(ModelStd, Vec<[[f64; 2]; 2]>)>,
    /// How the model was estimated, in words.
    pub estimator: String,
}

/// The [`Estimate`] of `best` on `record`, and the notes to print (the refinement, or why
/// there is no noise model).
pub fn estimate(best: &Best, record: &Record, request: &IdentifyRequest) -> (Estimate, Lines) {
    let mut notes = Vec::new();
    if let Some(fit) = &best.fit {
        let stopped = match fit.unconverged {
            Some(d) => format!(
                " (stopped at the iteration limit before converging, last relative decrease \
                 {d:.1e}: the model is the last iterate)"
            ),
            None => String::new(),
        };
        let estimator = format!(
            "refined by the prediction-error method: {} iterations{stopped}, {} parameters, D {}",
            fit.iterations,
            fit.parameters(),
            if fit.layout.feedthrough {
                "estimated"
            } else {
                "= 0 (not significant)"
            }
        );
        notes.push(estimator.clone());
        if fit.singular {
            notes.push(
                "no standard deviations: the information matrix JᵀJ of the refined model is \
                 singular (the data do not determine every parameter)"
                    .to_string(),
            );
        }
        let estimate = Estimate {
            model: fit.model.clone(),
            noise: Some(fit.noise.clone()),
            std: (!fit.singular).then(|| model_std(fit)),
            estimator,
        };
        return (estimate, notes);
    }
    let pem = PemOptions::for_identify(&best.options);
    let model = best.model.clone();
    // Remark 6 for the subspace model; without it only the simulation is reported.
    let nf = estimate_noise(
        &model,
        &record.u,
        &record.y,
        pem.start,
        NoiseOrder::default(),
    );
    if let Err(e) = &nf {
        notes.push(format!("no noise model: {e}"));
    }
    let estimator = match request.reference {
        Some(_) => super::closed_loop::ESTIMATOR.to_string(),
        None => "subspace (PI-MOESP), not refined".to_string(),
    };
    let estimate = Estimate {
        model,
        noise: nf.ok().map(|f| f.model),
        std: None,
        estimator,
    };
    (estimate, notes)
}
