//! What each figure of `hsid paper` shows and what to look at in it, by the figure's file name
//! (without the `.svg`): the paper's Figs. 6–11 per case, and the refinement's figures of
//! `--method`.

/// `(title, caption)` of the figure written as `stem.svg` by `hsid paper`; `None` for a name
/// this table does not know.
pub fn paper_caption(stem: &str) -> Option<(String, String)> {
    if let Some(rest) = stem.strip_prefix("pem-") {
        let (case, kind) = split_case(rest)?;
        return method_caption(case, kind);
    }
    let rest = stem.strip_prefix("fig")?;
    let (number, rest) = rest.split_once('-')?;
    let number: u32 = number.parse().ok()?;
    let (case, kind) = split_case(rest)?;
    let (what, caption) = match kind {
        "poles" => (
            "estimated poles",
            "The eigenvalues of the estimated A of every run (small markers) and the true \
             poles of the paper's G(q) (crosses), near the unit circle. The paper's claim is \
             no bias and a low spread: the markers should form a small cloud centred on each \
             cross; a cloud off its cross is a bias, and the table's pole std is its width.",
        ),
        "bode" => (
            "Bode magnitude, true and average model",
            "The magnitude of the true G(q) and the average of the runs' magnitudes. The \
             two curves should overlap at every frequency; the table's Bode max error is \
             the largest gap between them in dB.",
        ),
        "borders" => (
            "H[·] and its average estimate",
            "The true ascending and descending paths P_a and P_d and the average of the \
             runs' estimated borders. The average should follow each true path up to \
             what a piecewise-linear function on these knots can do (the table's best PWL \
             fit); the gap between the paths is the hysteresis.",
        ),
        _ => return None,
    };
    Some((
        format!("Fig. {number}, {case}: {what}"),
        caption.to_string(),
    ))
}

/// `("switch", "poles")` from `"switch-poles"`: the case, then the figure's kind.
fn split_case(s: &str) -> Option<(&str, &str)> {
    ["switch", "backlash"].into_iter().find_map(|case| {
        s.strip_prefix(case)
            .and_then(|r| r.strip_prefix('-'))
            .map(|kind| (case, kind))
    })
}

fn method_caption(case: &str, kind: &str) -> Option<(String, String)> {
    let (what, caption) = match kind {
        "poles" => (
            "poles of PI-MOESP and PEM with the Cramér–Rao 2σ ellipse",
            "The upper pole of every run by both methods, the true pole and the 2σ ellipse of \
             the Cramér–Rao bound around it. The cloud of an unbiased estimator at the \
             bound fills the ellipse; a wider cloud is an estimator short of the bound (the \
             table's std/CRB says by how much), a cloud off centre is a bias.",
        ),
        "bode-band" => (
            "Bode magnitude of one run (PEM) with its ±2σ band",
            "Run 0 refined by the prediction-error method with the ±2σ band it reports, beside \
             PI-MOESP on the same run and the true G. The true curve should lie inside the \
             band at most frequencies: a band that misses it says the reported uncertainty \
             is too optimistic.",
        ),
        "borders-band" => (
            "borders of one run (PEM) with their ±2σ bands",
            "Run 0's refined P_a and P_d with their ±2σ bands and the true paths. The true \
             paths should stay inside the bands, except where a piecewise-linear border on \
             these knots cannot follow the arctangent.",
        ),
        _ => return None,
    };
    Some((format!("{case}: {what}"), caption.to_string()))
}

#[cfg(test)]
mod tests {
    use super::paper_caption;

    #[test]
    fn every_figure_of_paper_has_a_caption() {
        for stem in [
            "fig6-switch-poles",
            "fig7-switch-bode",
            "fig8-switch-borders",
            "fig9-backlash-poles",
            "fig10-backlash-bode",
            "fig11-backlash-borders",
            "pem-switch-poles",
            "pem-backlash-bode-band",
            "pem-switch-borders-band",
        ] {
            assert!(paper_caption(stem).is_some(), "{stem}");
        }
        let (title, _) = paper_caption("fig10-backlash-bode").unwrap_or_default();
        assert_eq!(
            title,
            "Fig. 10, backlash: Bode magnitude, true and average model"
        );
        for stem in [
            "fig6-valve-poles",
            "figx-switch-poles",
            "pem-switch-x",
            "poles",
        ] {
            assert!(paper_caption(stem).is_none(), "{stem}");
        }
    }
}
