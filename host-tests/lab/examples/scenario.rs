//! Writes one simulated scenario of the diagnosis tests as CSV (columns `u,y`) on stdout, and
//! the matching `hsid diagnose` options on stderr.
//!
//! ```text
//! cargo run --release -p hsid-lab --example scenario -- EFFECT|clean paper|first backlash|switch SEED > data.csv
//! ```

use hsid_host::diagnose::Effect;
use hsid_host::io::write_columns_to;
use hsid_host::model::Element;
use hsid_lab::scenario::{Plant, Scenario, generate};

fn main() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let usage = "usage: scenario EFFECT|clean paper|first backlash|switch SEED";
    let [effect, plant, kind, seed] = args.as_slice() else {
        return Err(usage.into());
    };
    let effect = match effect.as_str() {
        "clean" => None,
        name => Some(Effect::from_name(name).ok_or(format!("unknown effect {name}"))?),
    };
    let plant = match plant.as_str() {
        "paper" => Plant::Paper,
        "first" => Plant::FirstOrder,
        _ => return Err(usage.into()),
    };
    let kind = match kind.as_str() {
        "backlash" => Element::Backlash,
        "switch" => Element::Switch,
        _ => return Err(usage.into()),
    };
    let seed: u64 = seed.parse().map_err(|_| usage.to_string())?;
    let d = generate(&Scenario::new(effect, plant, kind, seed))?;
    let o = &d.options.identify;
    eprintln!(
        "hsid diagnose --nonlinearity {} --umin {} --umax {} --segments {} --order {} --f {} --p {} --hold {} --split 0.7  (noise floor {:.5}, innovations {:.5})",
        kind.name(),
        o.u_min(),
        o.u_max(),
        o.knots_asc.len() - 1,
        o.order.unwrap_or(0),
        o.f,
        o.p,
        o.hold,
        d.noise_floor,
        d.innovation_floor
    );
    let stdout = std::io::stdout();
    write_columns_to(
        "<stdout>",
        stdout.lock(),
        &["u", "y"],
        &[d.record.u.clone(), d.record.y.clone()],
    )
    .map_err(|e| e.to_string())
}
