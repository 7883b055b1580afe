//! The model file of a [`Best`]: the model with its noise model and, when refined, the
//! standard deviations of its poles, μ0 and borders — what `hsid identify --json` writes.

use crate::identify::HostModel;
use crate::model::Element;
use crate::model_file::{ModelFile, ModelStd, NoiseFile};
use crate::refine::pem::{PemFit, PemOptions};
use crate::refine::stochastic::estimate_noise;
use crate::refine::uncertainty::{border_std, fit_poles};
use crate::refine::{NoiseModel, NoiseOrder};

use super::Best;

/// The model file of `best` identified from `(u, y)`: a refined model carries the noise
/// model and the standard deviations of its fit; a subspace model carries the noise model
/// fitted to its simulation residual (Remark 6), or none when that fit fails. Sample time and
/// units are left to the caller.
pub fn model_file(best: Best, u: &[f64], y: &[f64], nonlinearity: Option<Element>) -> ModelFile {
    let (model, noise, std): (HostModel, Option<NoiseModel>, Option<ModelStd>) =
        if let Some(fit) = best.fit {
            let (std, _) = model_std(&fit);
            (fit.model, Some(fit.noise), Some(std))
        } else {
            let pem = PemOptions::for_identify(&best.options);
            let nf = estimate_noise(&best.model, u, y, pem.start, NoiseOrder::default());
            (best.model, nf.ok().map(|f| f.model), None)
        };
    let mut file = model.to_json(nonlinearity);
    file.noise = noise.as_ref().map(noise_file);
    file.std = std;
    file
}

/// The noise model in the model file's form.
pub fn noise_file(n: &NoiseModel) -> NoiseFile {
    NoiseFile {
        c: n.c.clone(),
        d: n.d.clone(),
        sigma2: n.sigma2,
    }
}

/// Standard deviations of a refined model, and the covariance of each pole's `(re, im)`: each
/// pole of the model paired with the nearest root of the refined denominator.
pub fn model_std(fit: &PemFit) -> (ModelStd, Vec<[[f64; 2]; 2]>) {
    let roots = fit_poles(fit);
    let nearest: Vec<_> = fit
        .model
        .poles()
        .into_iter()
        .map(|(re, im)| {
            roots.iter().min_by(|a, b| {
                let d = |p: (f64, f64)| (p.0 - re).hypot(p.1 - im);
                d(a.pole).total_cmp(&d(b.pole))
            })
        })
        .collect();
    let poles = nearest
        .iter()
        .map(|r| r.map_or([f64::NAN; 2], |r| [r.std.0, r.std.1]))
        .collect();
    let cov = nearest
        .iter()
        .map(|r| r.map_or([[f64::NAN; 2]; 2], |r| r.cov))
        .collect();
    let (asc, desc) = border_std(fit);
    let std = ModelStd {
        poles,
        mu0: asc.first().copied().unwrap_or(f64::NAN),
        border_asc: asc,
        border_desc: desc,
    };
    (std, cov)
}
