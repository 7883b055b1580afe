//! Tick positions on linear and logarithmic axes, and their labels.

use super::style::TICK_SIZE;
use super::svg::{escape, num, text_width};

pub(super) fn is_pow10(v: f64) -> bool {
    let e = v.log10().round();
    (v / 10f64.powf(e) - 1.0).abs() < 1e-9
}

/// The "nice" step (1, 2 or 5 times a power of ten) that splits `span` into at most about
/// `target` intervals. Returns 1 for a non-finite or non-positive span.
pub fn nice_step(span: f64, target: f64) -> f64 {
    if !(span.is_finite() && span > 0.0) {
        return 1.0;
    }
    let raw = span / target.max(1.0);
    let mag = 10f64.powf(raw.log10().floor());
    let norm = raw / mag;
    let m = if norm <= 1.0 + 1e-9 {
        1.0
    } else if norm <= 2.0 + 1e-9 {
        2.0
    } else if norm <= 5.0 + 1e-9 {
        5.0
    } else {
        10.0
    };
    m * mag
}

/// Nice tick values inside `[min, max]`: multiples of [`nice_step`]`(max - min, target)`,
/// rounded so that they print exactly (`0.3`, not `0.30000000000000004`). Empty if the range is
/// not finite or `min > max`; `[min]` if `min == max`.
pub fn nice_ticks(min: f64, max: f64, target: usize) -> Vec<f64> {
    if !(min.is_finite() && max.is_finite()) || min > max {
        return Vec::new();
    }
    if min == max {
        return vec![min];
    }
    at_least_two_ticks(min, max, nice_step(max - min, target as f64)).0
}

/// Ticks at multiples of `step`, with the step lowered (5 → 2 → 1 → 0.5 ...) until at least two
/// fall inside the range. Returns the ticks and the step used.
pub(super) fn at_least_two_ticks(lo: f64, hi: f64, mut step: f64) -> (Vec<f64>, f64) {
    for _ in 0..6 {
        let ticks = ticks_with_step(lo, hi, step);
        if ticks.len() >= 2 {
            return (ticks, step);
        }
        let mag = 10f64.powf((step.log10() + 1e-9).floor());
        let m = (step / mag).round();
        step = if m >= 5.0 {
            2.0 * mag
        } else if m >= 2.0 {
            mag
        } else {
            0.5 * mag
        };
    }
    (ticks_with_step(lo, hi, step), step)
}

/// Ticks of a logarithmic axis over `[min, max]` (both > 0): the powers of ten inside the range
/// (every k-th decade if there are more than about `target`), or 1-2-5 multiples when the range
/// spans less than about two decades. The second vector holds the minor ticks (2..9 × 10ⁿ).
pub fn log_ticks(min: f64, max: f64, target: f64) -> (Vec<f64>, Vec<f64>) {
    if !(min.is_finite() && max.is_finite() && min > 0.0 && min < max) {
        return (Vec::new(), Vec::new());
    }
    let lo = min.log10();
    let hi = max.log10();
    let e0 = (lo - 1e-9).floor() as i32;
    let e1 = (hi + 1e-9).ceil() as i32;
    let inside = |v: f64| v.log10() >= lo - 1e-9 && v.log10() <= hi + 1e-9;
    let decades: Vec<i32> = (e0..=e1).filter(|&e| inside(pow10(e))).collect();
    let mut minor = Vec::new();
    if decades.len() >= 2 {
        let every = ((decades.len() as f64 / target.max(2.0)).ceil() as i32).max(1);
        let mut major = Vec::new();
        for &e in &decades {
            if e.rem_euclid(every) == 0 {
                major.push(pow10(e));
            } else {
                minor.push(pow10(e));
            }
        }
        if every == 1 {
            for e in e0..e1 {
                for m in 2..10 {
                    let v = snap(f64::from(m) * pow10(e), pow10(e));
                    if inside(v) {
                        minor.push(v);
                    }
                }
            }
        }
        return (major, minor);
    }
    // Less than two decades: label 1, 2 and 5 times the powers of ten.
    let mut major = Vec::new();
    for e in e0..=e1 {
        for m in 1..10 {
            let v = snap(f64::from(m) * pow10(e), pow10(e));
            if inside(v) {
                if m == 1 || m == 2 || m == 5 {
                    major.push(v);
                } else {
                    minor.push(v);
                }
            }
        }
    }
    (major, minor)
}

fn pow10(e: i32) -> f64 {
    format!("1e{e}").parse().unwrap_or(10f64.powi(e))
}

fn ticks_with_step(lo: f64, hi: f64, step: f64) -> Vec<f64> {
    if !(lo.is_finite() && hi.is_finite() && step.is_finite() && step > 0.0) {
        return Vec::new();
    }
    let k0 = (lo / step - 1e-9).ceil();
    let k1 = (hi / step + 1e-9).floor();
    if k1 < k0 || k1 - k0 > 1000.0 {
        return Vec::new();
    }
    let n = (k1 - k0) as usize;
    (0..=n)
        .map(|i| snap((k0 + i as f64) * step, step))
        .collect()
}

/// Rounds `v` to the decimal precision of `step` so that it prints exactly.
pub(super) fn snap(v: f64, step: f64) -> f64 {
    let d = decimals(step);
    if d == 0 {
        return v.round();
    }
    let text = format!("{v:.d$}");
    let snapped: f64 = text.parse().unwrap_or(v);
    if snapped == 0.0 { 0.0 } else { snapped }
}

/// Number of decimals needed to print multiples of a 1-2-5 `step`.
pub(super) fn decimals(step: f64) -> usize {
    if step >= 1.0 {
        0
    } else {
        ((-step.log10() - 1e-9).ceil().max(0.0) as usize).min(17)
    }
}

pub(super) fn tick_labels(ticks: &[f64], step: f64) -> Vec<TickLabel> {
    let biggest = ticks.iter().fold(0.0f64, |m, t| m.max(t.abs()));
    let scientific = step < 1e-4 || biggest >= 1e6;
    ticks
        .iter()
        .map(|&t| {
            let text = if t == 0.0 {
                "0".to_string()
            } else if scientific {
                format!("{t:e}")
            } else {
                format!("{t:.*}", decimals(step))
            };
            TickLabel::Text(minus(&text))
        })
        .collect()
}

/// Replaces ASCII hyphen-minus by the typographic minus sign.
pub(super) fn minus(s: &str) -> String {
    s.replace('-', "\u{2212}")
}

/// A tick label: plain text or a power of ten.
pub(super) enum TickLabel {
    Text(String),
    Pow10(i32),
}

impl TickLabel {
    pub(super) fn width(&self, size: f64) -> f64 {
        match self {
            TickLabel::Text(t) => text_width(t, size),
            TickLabel::Pow10(e) => {
                text_width("10", size) + text_width(&minus(&e.to_string()), 0.75 * size)
            }
        }
    }

    pub(super) fn svg(&self) -> String {
        match self {
            TickLabel::Text(t) => escape(t),
            TickLabel::Pow10(e) => format!(
                r#"10<tspan dy="-{}" font-size="{}">{}</tspan>"#,
                num(0.45 * TICK_SIZE),
                num(0.75 * TICK_SIZE),
                minus(&e.to_string())
            ),
        }
    }
}
