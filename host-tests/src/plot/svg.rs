//! SVG text pieces: numbers, escaping, dash patterns, polylines, bands and markers.

use std::fmt::Write as _;

use super::series::Series;
use super::style::{ARROW_TEXT_SIZE, Dash, Marker, PALETTE};

/// A point in px.
pub(super) type Point = (f64, f64);

/// Rough rendered width of a text in a sans-serif font.
pub(super) fn text_width(s: &str, size: f64) -> f64 {
    s.chars()
        .map(|c| match c {
            '0'..='9' => 0.64,
            '.' | ',' | ':' | ';' | '|' | 'i' | 'j' | 'l' | '!' | '\'' => 0.32,
            ' ' => 0.32,
            '\u{2212}' | '+' | '=' | '<' | '>' => 0.84,
            '-' | '(' | ')' | '[' | ']' | 'f' | 't' | 'r' => 0.40,
            'm' | 'w' | 'M' | 'W' => 0.95,
            'A'..='Z' => 0.72,
            _ => 0.60,
        })
        .sum::<f64>()
        * size
}

pub(super) fn series_color(series: &Series, index: usize) -> String {
    series
        .color
        .clone()
        .unwrap_or_else(|| PALETTE[index % PALETTE.len()].to_string())
}

/// A pixel coordinate with at most two decimals and no trailing zeros.
pub(super) fn num(v: f64) -> String {
    if !v.is_finite() {
        return "0".to_string();
    }
    let s = format!("{:.2}", v);
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" || s.is_empty() {
        "0".to_string()
    } else {
        s.to_string()
    }
}

/// `s` for markup text and quoted attribute values, in SVG and in HTML alike: `& < > " '`
/// replaced by their entities, and the control characters XML does not allow (all below
/// U+0020 except tab and line feed) dropped.
pub fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            c if (c as u32) < 0x20 && c != '\t' && c != '\n' => {}
            c => out.push(c),
        }
    }
    out
}

pub(super) fn dash_attr(dash: Dash, width: f64) -> String {
    let k = (width / 1.5).max(1.0);
    let pattern = match dash {
        Dash::Solid => return String::new(),
        Dash::Dashed => vec![7.0, 4.0],
        Dash::Dotted => vec![0.5, 3.5],
        Dash::DashDot => vec![8.0, 3.5, 0.5, 3.5],
    };
    let p: Vec<String> = pattern.iter().map(|v| num(v * k)).collect();
    format!(r#" stroke-dasharray="{}""#, p.join(" "))
}

/// Path data through the points, starting a new sub-path after every missing point.
pub(super) fn polyline(points: impl Iterator<Item = Option<(f64, f64)>>) -> String {
    let mut d = String::new();
    let mut pen_down = false;
    for p in points {
        match p {
            Some((x, y)) => {
                let _ = write!(
                    d,
                    "{}{} {}",
                    if pen_down { "L" } else { "M" },
                    num(x),
                    num(y)
                );
                pen_down = true;
            }
            None => pen_down = false,
        }
    }
    d
}

pub(super) fn band_path(
    x: &[f64],
    lower: &[f64],
    upper: &[f64],
    to_px: &dyn Fn(f64, f64) -> Option<(f64, f64)>,
) -> String {
    let mut d = String::new();
    let mut run: Vec<(Point, Point)> = Vec::new();
    let flush = |run: &mut Vec<(Point, Point)>, d: &mut String| {
        if run.len() >= 2 {
            for (k, (u, _)) in run.iter().enumerate() {
                let _ = write!(
                    d,
                    "{}{} {}",
                    if k == 0 { "M" } else { "L" },
                    num(u.0),
                    num(u.1)
                );
            }
            for (_, l) in run.iter().rev() {
                let _ = write!(d, "L{} {}", num(l.0), num(l.1));
            }
            d.push('Z');
        }
        run.clear();
    };
    for i in 0..x.len() {
        match (to_px(x[i], upper[i]), to_px(x[i], lower[i])) {
            (Some(u), Some(l)) => run.push((u, l)),
            _ => flush(&mut run, &mut d),
        }
    }
    flush(&mut run, &mut d);
    d
}

pub(super) fn marker_path(d: &mut String, marker: Marker, x: f64, y: f64, r: f64) {
    let mut seg = |x0: f64, y0: f64, x1: f64, y1: f64| {
        let _ = write!(d, "M{} {}L{} {}", num(x0), num(y0), num(x1), num(y1));
    };
    let a = r * std::f64::consts::FRAC_1_SQRT_2;
    match marker {
        Marker::Plus => {
            seg(x - r, y, x + r, y);
            seg(x, y - r, x, y + r);
        }
        Marker::Cross => {
            seg(x - a, y - a, x + a, y + a);
            seg(x - a, y + a, x + a, y - a);
        }
        Marker::Star => {
            seg(x - r, y, x + r, y);
            seg(x, y - r, x, y + r);
            seg(x - a, y - a, x + a, y + a);
            seg(x - a, y + a, x + a, y - a);
        }
        Marker::Circle | Marker::Dot => {
            let (rs, d2) = (num(r), num(2.0 * r));
            let _ = write!(
                d,
                "M{} {}a{rs} {rs} 0 1 0 {d2} 0a{rs} {rs} 0 1 0 -{d2} 0",
                num(x - r),
                num(y)
            );
        }
    }
}

/// `class` is empty or a ` class="…"` attribute.
pub(super) fn marker_element(
    d: &str,
    marker: Marker,
    color: &str,
    width: f64,
    class: &str,
) -> String {
    match marker {
        Marker::Dot => format!(r#"<path{class} d="{d}" fill="{color}" stroke="none"/>"#),
        _ => format!(
            r#"<path{class} d="{d}" fill="none" stroke="{color}" stroke-width="{}" stroke-linecap="round"/>"#,
            num(width)
        ),
    }
}

/// Arrowhead length in px for a line `width` px wide.
pub(super) fn arrowhead_len(width: f64) -> f64 {
    5.0 + 2.5 * width
}

/// Where an arrow's text starts, and its width (px): centred under an arrow longer than the
/// text, else starting at the `p1` end, moved left to end before `right`. Bold text is about
/// a tenth wider than [`text_width`] says.
pub(super) fn arrow_text_x((p0, p1): (Point, Point), text: &str, right: f64) -> (f64, f64) {
    let w = 1.1 * text_width(text, ARROW_TEXT_SIZE);
    let len = (p1.0 - p0.0).hypot(p1.1 - p0.1);
    let x = if w + 16.0 < len {
        0.5 * (p0.0 + p1.0) - 0.5 * w
    } else {
        (p1.0 + 4.0).min(right - 4.0 - w)
    };
    (x, w)
}

/// A two-headed arrow between `ends`, from `p0` to `p1` (px) with a bar across each end and `text` below
/// it: centred when the arrow is longer than the text, else starting at the `p1` end (moved
/// left as far as needed to end before `right`, in px); as one `<g>` carrying `class` (empty or a ` class="…"` attribute) and the
/// ends in data coordinates `data` as `data-from` and `data-to`. Heads shrink on a short
/// arrow so that they never overlap.
pub(super) fn arrow_element(
    (p0, p1): (Point, Point),
    data: ((f64, f64), (f64, f64)),
    text: &str,
    right: f64,
    color: &str,
    width: f64,
    class: &str,
) -> String {
    let (dx, dy) = (p1.0 - p0.0, p1.1 - p0.1);
    let len = dx.hypot(dy);
    let (ux, uy) = if len > 0.0 {
        (dx / len, dy / len)
    } else {
        (1.0, 0.0)
    };
    // Normal to the arrow, in px.
    let (nx, ny) = (-uy, ux);
    let head = arrowhead_len(width).min(0.4 * len);
    let half = 0.45 * head;
    let bar = 3.0 * width + 4.0;
    let mut g = format!(
        r#"<g{class} data-from="{} {}" data-to="{} {}">"#,
        data.0.0, data.0.1, data.1.0, data.1.1
    );
    // Shaft between the heads' bases, the bars across the ends.
    let _ = write!(
        g,
        r#"<path d="M{} {}L{} {}M{} {}L{} {}M{} {}L{} {}" fill="none" stroke="{color}" stroke-width="{}" stroke-linecap="butt"/>"#,
        num(p0.0 + ux * 0.8 * head),
        num(p0.1 + uy * 0.8 * head),
        num(p1.0 - ux * 0.8 * head),
        num(p1.1 - uy * 0.8 * head),
        num(p0.0 - nx * bar),
        num(p0.1 - ny * bar),
        num(p0.0 + nx * bar),
        num(p0.1 + ny * bar),
        num(p1.0 - nx * bar),
        num(p1.1 - ny * bar),
        num(p1.0 + nx * bar),
        num(p1.1 + ny * bar),
        num(width)
    );
    // The heads, tips on the ends.
    let mut d = String::new();
    for (tip, dir) in [(p0, 1.0), (p1, -1.0)] {
        let (bx, by) = (tip.0 + dir * ux * head, tip.1 + dir * uy * head);
        let _ = write!(
            d,
            "M{} {}L{} {}L{} {}Z",
            num(tip.0),
            num(tip.1),
            num(bx + nx * half),
            num(by + ny * half),
            num(bx - nx * half),
            num(by - ny * half)
        );
    }
    let _ = write!(g, r#"<path d="{d}" fill="{color}" stroke="none"/>"#);
    if !text.is_empty() {
        let (x, _) = arrow_text_x((p0, p1), text, right);
        let _ = write!(
            g,
            r#"<text x="{}" y="{}" font-size="{}" font-weight="bold" fill="{color}" stroke="white" stroke-width="4" stroke-linejoin="round" paint-order="stroke">{}</text>"#,
            num(x),
            num(p0.1.max(p1.1) + bar + ARROW_TEXT_SIZE),
            ARROW_TEXT_SIZE,
            escape(text)
        );
    }
    g.push_str("</g>");
    g
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_arrows_text_is_centred_under_a_long_arrow_and_kept_in_the_plot() {
        let text = "gap 0.192 ± 0.013 V";
        let w = 1.1 * text_width(text, ARROW_TEXT_SIZE);
        // Longer than the text: centred.
        let (x, tw) = arrow_text_x(((100.0, 50.0), (400.0, 50.0)), text, 800.0);
        assert_eq!(tw, w);
        assert!((x + 0.5 * w - 250.0).abs() < 1e-9, "{x}");
        // Short: from the `to` end, and moved left to end 4 px before the plot's edge.
        let (x, _) = arrow_text_x(((100.0, 50.0), (140.0, 50.0)), text, 800.0);
        assert_eq!(x, 144.0);
        let (x, _) = arrow_text_x(((700.0, 50.0), (740.0, 50.0)), text, 800.0);
        assert!((x + w - 796.0).abs() < 1e-9, "{x}");
        // The element: the ends in data coordinates, the heads' tips on the ends in px.
        let g = arrow_element(
            ((100.0, 50.0), (140.0, 50.0)),
            ((0.0, 0.1), (0.2, 0.1)),
            text,
            800.0,
            "black",
            1.8,
            r#" class="gap-marker""#,
        );
        assert!(g.starts_with(r#"<g class="gap-marker" data-from="0 0.1" data-to="0.2 0.1">"#));
        let heads = g.split("<path d=\"").nth(2).unwrap_or_default();
        assert!(
            heads.starts_with("M100 50L") && heads.contains("ZM140 50L"),
            "{g}"
        );
        assert!(g.contains(">gap 0.192 ± 0.013 V</text>"), "{g}");
    }
}
