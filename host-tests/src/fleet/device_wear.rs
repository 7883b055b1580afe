//! One device's weekly gaps and verdict ([`DeviceWear`]), the parts of a checkpoint id
//! ([`split_id`]) and the per-device table ([`device_csv`]): what the wear report
//! ([`wear`](super::wear)) and its score against a simulated fleet's truth
//! ([`score`](super::score)) share.

use std::fmt::Write as _;

use super::trend::Trend;

/// One device's weeks and verdict.
#[derive(Clone, Debug, PartialEq)]
pub struct DeviceWear {
    /// Device id (the checkpoint file name up to `-w`).
    pub device: String,
    /// `(week, gap)` of every week with a model.
    pub gaps: Vec<(f64, f64)>,
    /// The trend, when at least three weeks have a model.
    pub trend: Option<Trend>,
    /// Growth beyond `k` standard errors.
    pub wearing: bool,
    /// The trend's last-week gap above the limit.
    pub over_limit: bool,
}

/// `d00042-w03.bin` → `("d00042", 3)`.
pub fn split_id(id: &str) -> Option<(&str, usize)> {
    let (device, rest) = id.rsplit_once("-w")?;
    let week = rest.split('.').next()?.parse().ok()?;
    Some((device, week))
}

/// The per-device table: `device,weeks,slope,slope_se,wearing,over_limit,gaps` with the
/// weekly gaps separated by `;`.
pub fn device_csv(devices: &[DeviceWear]) -> String {
    let mut s = String::from("device,weeks,slope,slope_se,wearing,over_limit,gaps\n");
    for d in devices {
        let (slope, se) = d
            .trend
            .map_or((f64::NAN, f64::NAN), |t| (t.slope, t.slope_se));
        let gaps: Vec<String> = d.gaps.iter().map(|(w, g)| format!("{w}:{g:.5}")).collect();
        let _ = writeln!(
            s,
            "{},{},{slope:.6},{se:.6},{},{},{}",
            d.device,
            d.gaps.len(),
            d.wearing,
            d.over_limit,
            gaps.join(";")
        );
    }
    s
}
