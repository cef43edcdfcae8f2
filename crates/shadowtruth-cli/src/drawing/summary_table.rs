//! The page's summary table of a scene: at each resolution, the best setting of each technique
//! family with its error and cost, and which settings are on the Pareto front.

use super::summary::GroupSummary;
use crate::escape::escape_html as escape;
use std::fmt::Write as _;

/// Per scene, at each resolution: the best setting of each technique family with its error
/// and cost, and whether it is in the Pareto set (no setting both cheaper and better).
pub(super) fn scene_summary(h: &mut String, g: &GroupSummary) {
    let _ = write!(
        h,
        "<table class=\"summary\"><caption class=\"l\"><b>{}</b></caption><thead><tr><th>resolution</th>\
         <th class=\"l\">technique</th><th class=\"l\">best setting</th><th>error %</th><th>false shadow %</th>\
         <th>false lit %</th><th title=\"this tool's CPU shading pass per evaluated pixel: the median of the repeats, their range in brackets\">ns/pixel (range)</th><th>Pareto</th></tr></thead><tbody>",
        escape(&g.name)
    );
    for res in g.resolutions() {
        let front: Vec<String> = g.pareto(res).iter().map(|s| s.label.clone()).collect();
        for s in g.best_per_family(res) {
            let on_front = front.contains(&s.label);
            let _ = write!(
                h,
                "<tr><td>{res}</td><td class=\"l\">{}</td><td class=\"l\">{}</td><td>{:.3}</td><td>{:.3}</td>\
                 <td>{:.3}</td><td>{}</td><td class=\"front\">{}</td></tr>",
                escape(&s.technique),
                escape(&s.label),
                100.0 * s.error,
                100.0 * s.false_shadow,
                100.0 * s.false_lit,
                s.cost_text(),
                if on_front { "✓" } else { "" }
            );
        }
    }
    h.push_str("</tbody></table>");
}
