//! The Monte Carlo table of Section IV (Markdown), as printed by `hsid paper`.

use std::fmt::Write;

use super::case::PaperConfig;
use super::monte_carlo::CaseResult;

/// The Monte Carlo table (Markdown).
pub fn paper_table(cfg: &PaperConfig, results: &[CaseResult]) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "Monte Carlo: {} runs per case, j = {}, f = p = {}, SNR = {} dB, {} uniform segments per path on [{}, {}], {:?} basis, seed {}",
        cfg.runs, cfg.j, cfg.f, cfg.snr_db, cfg.segments, cfg.u_min, cfg.u_max, cfg.basis, cfg.seed
    );
    let _ = writeln!(s);
    let _ = writeln!(
        s,
        "| case | true pole | mean pole | pole std (re, im) | orders selected | Bode max error of average (dB) | border RMS of average | best PWL fit | median single-run border RMS | failures |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|---|---|---|---|");
    for r in results {
        let c = &r.summary;
        let tp = c.true_poles.first().copied().unwrap_or([f64::NAN; 2]);
        let orders: Vec<String> = c
            .order_counts
            .iter()
            .enumerate()
            .filter(|(_, n)| **n > 0)
            .map(|(o, n)| format!("n={o}: {n}"))
            .collect();
        let _ = writeln!(
            s,
            "| {} | {:.4} ± {:.4}j | {:.4} ± {:.4}j | ({:.4}, {:.4}) | {} | {:.3} | {:.4} | {:.4} | {:.4} | {} |",
            c.case,
            tp[0],
            tp[1].abs(),
            c.pole_mean[0],
            c.pole_mean[1].abs(),
            c.pole_std[0],
            c.pole_std[1],
            orders.join(", "),
            c.bode_max_db_error_of_average,
            c.border_rms_of_average,
            c.border_rms_best_pwl,
            c.border_rms_single_median,
            c.failures.len()
        );
    }
    s
}
