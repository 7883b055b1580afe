//! What the diagnosis found but could not add: tests no catalog effect explains, effects outside
//! the catalog, and estimation data that cannot score extensions. Typed here; put in words in
//! [`verdict`](super::verdict).

use super::effects::Effect;
use crate::validation::residual::Test;

/// A finding the loop could not act on.
#[derive(Clone, Debug, PartialEq)]
pub enum Finding {
    /// The current model cannot be fitted without one of the inner validation's blocks.
    FoldsUnfittable {
        /// Why the fit failed, in words.
        error: String,
    },
    /// The model fitted without the inner hold-out block simulates it with more than 3 × its
    /// in-sample RMSE.
    BlockUnscorable {
        /// Block start.
        start: usize,
        /// Block end (exclusive).
        end: usize,
        /// RMSE on the block.
        rmse: f64,
        /// In-sample RMSE.
        in_sample: f64,
    },
    /// A test fired on the estimation residual that no catalog effect explains.
    NotExplained {
        /// The test.
        test: Test,
        /// What it found, in words.
        detail: String,
        /// Its p-value.
        p_value: f64,
        /// The effects tried on its evidence: `(effect, gain, p)`.
        tried: Vec<(Effect, f64, f64)>,
    },
    /// Outside the catalog: the residual depends on the input's direction although the
    /// nonlinearity is static, and no element with memory was added.
    DirectionDependence,
    /// Outside the catalog: the residual still depends on the input's direction with the
    /// element with memory (`hysteresis`) added.
    DirectionDependenceBeyondElement,
    /// Outside the catalog: state dependence the level-dependent stores leave.
    StateDependenceBeyondStores,
    /// Outside the catalog: state-dependent dynamics not added.
    StateDependence,
    /// Outside the catalog: the final model's equation error depends on the sign of its
    /// simulated velocity ([`friction`]):
    /// Coulomb friction on the model's velocity, which `hsid identify --friction` fits.
    Friction {
        /// The sign's t statistic (Newey–West errors).
        t: f64,
        /// The sign's coefficient in the equation (output units).
        difference: f64,
    },
    /// Outside the catalog: the output is quantised.
    Quantised,
    /// The output integrates (data check `integrating`): nothing is scored against a model
    /// normalised to `G(1) = 1`.
    Integrating,
}

impl Finding {
    /// Whether the finding is that the estimation data cannot score extensions.
    pub(crate) fn unscorable(&self) -> bool {
        matches!(
            self,
            Finding::FoldsUnfittable { .. } | Finding::BlockUnscorable { .. }
        )
    }

    /// Whether the finding is an effect outside the catalog.
    pub fn outside_catalog(&self) -> bool {
        matches!(
            self,
            Finding::DirectionDependence
                | Finding::DirectionDependenceBeyondElement
                | Finding::StateDependenceBeyondStores
                | Finding::StateDependence
                | Finding::Friction { .. }
                | Finding::Quantised
        )
    }
}

/// The effects outside the catalog that the final estimation tests (`tests`) and the data
/// checks (`warnings`) find; `shared`: a static nonlinearity, `stores`: the model has the
/// level-dependent stores, `element`: the element with memory.
pub fn outside_catalog(
    tests: &crate::validation::residual::TestSet,
    warnings: &[crate::validation::checks::Warning],
    shared: bool,
    stores: bool,
    element: bool,
) -> Vec<Finding> {
    let mut out = Vec::new();
    if shared && tests.fired(Test::DirectionCorrelation) {
        out.push(if element {
            Finding::DirectionDependenceBeyondElement
        } else {
            Finding::DirectionDependence
        });
    }
    if tests.fired(Test::StateDependence) {
        out.push(if stores {
            Finding::StateDependenceBeyondStores
        } else {
            Finding::StateDependence
        });
    }
    if warnings
        .iter()
        .any(|w| w.check == crate::validation::checks::Check::OutputQuantisation)
    {
        out.push(Finding::Quantised);
    }
    out
}

/// Friction on the velocity of `model` (the diagnosis's final model) on the estimation record
/// `est` from sample `from` on: [`friction_evidence`].
pub fn friction(
    model: &super::model::ExtendedModel,
    est: &crate::model::Record,
    from: usize,
    increments: bool,
) -> Option<Finding> {
    // A plant that does not integrate may measure a position (the velocity the output's
    // change) or a speed (the output itself): the first reading that fires.
    let readings: &[bool] = if increments { &[true] } else { &[false, true] };
    readings
        .iter()
        .find_map(|&on_output| friction_evidence(model, est, from, on_output))
        .map(|e| Finding::Friction {
            t: e.t,
            difference: e.difference,
        })
}

/// The friction step's evidence on `model` and the record `est` from sample `from` on
/// ([`velocity_sign_on`](crate::friction::velocity_sign_on)): the sign of the model's
/// simulated velocity in its output-error equation (its simulated output as the past), the
/// velocity the change of its simulated output (the output itself when `increments`: an
/// integrating plant's increments, or a speed, are the velocity). Asked only of a model whose simulation
/// is its element and `G` (no element with memory, stores, output map or friction already):
/// the equation the test writes is that model's. `None` below `|t| =`
/// [`THRESHOLD`](crate::friction::VelocitySign::THRESHOLD): on the t statistic alone, as with
/// the simulated past, whose lags are nearly functions of the element's past output, the
/// regression's own `B`, and so the force it implies, is poorly determined.
pub fn friction_evidence(
    model: &super::model::ExtendedModel,
    est: &crate::model::Record,
    from: usize,
    increments: bool,
) -> Option<crate::friction::VelocitySign> {
    if model.hysteresis.is_some()
        || model.stores.is_some()
        || model.output_map.is_some()
        || model.friction.is_some()
    {
        return None;
    }
    let ud = super::simulate::delay_input(&est.u, model.structure.delay);
    let h = model.hammerstein.nonlinearity_output(&ud);
    let sim = model.hammerstein_output(&est.u);
    let change;
    let velocity = match increments {
        true => &sim,
        false => {
            change = crate::friction::evidence::change_from_rest(&sim);
            &change
        }
    };
    let s = model.less_additive(est);
    let from = from.min(s.len());
    crate::friction::velocity_sign_on(
        &s[from..],
        &sim[from..],
        &h[from..],
        &velocity[from..],
        model.hammerstein.order,
    )
    .filter(|e| e.t.abs() > crate::friction::VelocitySign::THRESHOLD)
}
