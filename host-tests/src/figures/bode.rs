//! Bode magnitude (dB) and phase (degrees) of the LTI part `G`, with ±2σ bands when the
//! uncertainty source has the parameter covariance. The first row of the CSV is `ω = 0`, the
//! static gain (left out of the log-frequency figures).

use super::csv::{Table, band_label, save_svg};
use super::error::FigureError;
use super::{Context, Written};
use crate::plot::{Figure, PALETTE, Series};

/// Frequencies per figure, log-spaced over three decades up to the Nyquist frequency.
const POINTS: usize = 300;
const DECADES: f64 = 3.0;

/// `0` then `POINTS` log-spaced frequencies from `π·10^{−DECADES}` to `π` (rad/sample).
pub(super) fn frequencies() -> Vec<f64> {
    let pi = std::f64::consts::PI;
    std::iter::once(0.0)
        .chain(
            (0..POINTS)
                .map(|i| pi * 10f64.powf(-DECADES + DECADES * i as f64 / (POINTS - 1) as f64)),
        )
        .collect()
}

/// Phase in degrees, unwrapped along the frequencies.
fn unwrapped_phase(response: &[(f64, f64)]) -> Vec<f64> {
    let mut out: Vec<f64> = Vec::with_capacity(response.len());
    for &(re, im) in response {
        let mut p = im.atan2(re).to_degrees();
        if let Some(&prev) = out.last() {
            p += 360.0 * ((prev - p) / 360.0).round();
        }
        out.push(p);
    }
    out
}

pub(super) fn write(cx: &Context, out: &mut Written) -> Result<(), FigureError> {
    let s = cx.settings;
    let w = frequencies();
    let response: Vec<(f64, f64)> = w.iter().map(|&w| cx.model.freq_response(w)).collect();
    let db: Vec<f64> = response
        .iter()
        .map(|(re, im)| 10.0 * (re * re + im * im).log10())
        .collect();
    let deg = unwrapped_phase(&response);
    let freq: Vec<f64> = w.iter().map(|&w| s.frequency(w)).collect();
    let (f_label, f_col) = s.frequency_axis();
    let mut table = Table::default();
    table.col(f_col, freq.clone());
    table.col("|G| [dB]", db.clone());
    table.col("phase [deg]", deg.clone());
    let mut mag = Figure::new("LTI part: magnitude |G|")
        .x_label(f_label)
        .y_label("|G| [dB]")
        .log_x(true);
    let mut phase = Figure::new("LTI part: phase of G")
        .x_label(f_label)
        .y_label("phase [deg]")
        .log_x(true);
    let band = cx.uncertainty.and_then(|u| u.bode_std(&w));
    if let Some(sd) = &band {
        for (fig, v, pick, col) in [
            (&mut mag, &db, 0usize, "|G| [dB]"),
            (&mut phase, &deg, 1, "phase [deg]"),
        ] {
            let sd: Vec<f64> = sd
                .iter()
                .map(|p| if pick == 0 { p.0 } else { p.1 })
                .collect();
            let lo: Vec<f64> = v.iter().zip(&sd).map(|(v, s)| v - 2.0 * s).collect();
            let hi: Vec<f64> = v.iter().zip(&sd).map(|(v, s)| v + 2.0 * s).collect();
            fig.push(
                Series::band(&freq, &lo, &hi)
                    .color(PALETTE[0])
                    .opacity(0.3)
                    .class("band")
                    .label(band_label("", &sd, if pick == 0 { " dB" } else { "°" })),
            );
            table.col(format!("{col} - 2sd"), lo);
            table.col(format!("{col} + 2sd"), hi);
        }
    } else if cx.uncertainty.is_some() {
        out.notes
            .push("bode: no ±2σ band: the model file stores no parameter covariance".to_string());
    }
    mag.push(
        Series::line(&freq, &db)
            .color(PALETTE[0])
            .class("magnitude")
            .label("model"),
    );
    phase.push(
        Series::line(&freq, &deg)
            .color(PALETTE[0])
            .class("phase")
            .label("model"),
    );
    out.files.push(table.save(cx.dir, "bode")?);
    out.files.push(save_svg(&mag, cx.dir, "bode-magnitude")?);
    out.files.push(save_svg(&phase, cx.dir, "bode-phase")?);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn phase_is_unwrapped_across_the_branch_cut() {
        let r: Vec<(f64, f64)> = [170.0f64, 179.0, -179.0, -170.0]
            .iter()
            .map(|d| (d.to_radians().cos(), d.to_radians().sin()))
            .collect();
        let p = unwrapped_phase(&r);
        for (a, b) in p.iter().zip([170.0, 179.0, 181.0, 190.0]) {
            assert!((a - b).abs() < 1e-9, "{a} vs {b}");
        }
    }

    #[test]
    fn frequencies_start_at_zero_and_end_at_nyquist() {
        let w = frequencies();
        assert_eq!(w[0], 0.0);
        assert!((w[POINTS] - std::f64::consts::PI).abs() < 1e-12);
        assert!((w[1] - std::f64::consts::PI * 1e-3).abs() < 1e-15);
        assert!(w.windows(2).all(|p| p[0] < p[1]));
    }
}
