//! The top of `index.html`: per scene, what a reader came for. The reference beside the error
//! map of the scene's best run, the error-against-cost chart of its settings at its largest
//! resolution (the Pareto front drawn; a click on a point opens that setting's run in the
//! viewer), and the best setting of each technique at each resolution.

use super::palette::{BEST, SERIES, TOTAL_ERROR};
use super::summary::{GroupSummary, SettingSummary, per_scene, summaries};
use crate::escape::escape_html as escape;
use shadowtruth::record::{Report, RunRecord};
use std::fmt::Write as _;

/// Per run (report order): its figures as (reference, technique, error map), where written.
pub type RunImages<'a> = dyn Fn(usize) -> Option<(&'a str, &'a str, &'a str)> + 'a;

pub fn answer_section(h: &mut String, report: &Report, images: &RunImages) {
    let groups = summaries(report, per_scene);
    if groups.is_empty() {
        return;
    }
    h.push_str(
        "<section id=\"answer\"><h2>The answer</h2><p>Per scene: the exact shadows beside the error map of \
         its best run; every setting's error against its shading cost (click a point to open its run in \
         the viewer); the best setting of each technique. ",
    );
    h.push_str(&super::palette::colour_code_legend());
    h.push_str(".</p>");
    for g in &groups {
        scene_answer(h, report, g, images);
    }
    h.push_str("</section>");
}

fn scene_answer(h: &mut String, report: &Report, g: &GroupSummary, images: &RunImages) {
    let _ = write!(h, "<div class=\"scene-answer\"><h3>{}</h3><div class=\"answer-row\">", escape(&g.name));
    let runs: Vec<usize> = (0..report.runs.len()).filter(|&i| report.runs[i].scene == g.name).collect();
    // The least error among the runs whose figures were written, then the least cost.
    let best = runs.iter().copied().filter(|&i| images(i).is_some()).min_by(|&a, &b| {
        let key = |i: usize| (report.runs[i].rates.error, report.runs[i].timings.ns_per_pixel);
        key(a).partial_cmp(&key(b)).unwrap_or(std::cmp::Ordering::Equal)
    });
    if let Some((i, (reference, _, error))) = best.and_then(|i| Some((i, images(i)?))) {
        let r = &report.runs[i];
        let _ = write!(
            h,
            "<figure><img class=\"answer-img\" src=\"{}\" alt=\"reference\"><figcaption>exact shadows: {}/{}\
             </figcaption></figure><figure><img class=\"answer-img\" src=\"{}\" alt=\"error map\"><figcaption>\
             best run: {} at {}², {:.3} % error</figcaption></figure>",
            escape(reference),
            escape(&r.camera),
            escape(&r.light),
            escape(error),
            escape(&r.label),
            r.resolution,
            100.0 * r.rates.error
        );
    }
    if let Some(&resolution) = g.resolutions().last() {
        let at: Vec<&SettingSummary> = g.settings.iter().filter(|s| s.resolution == resolution).collect();
        let front = g.pareto(resolution);
        let run_of = |s: &SettingSummary| {
            runs.iter().copied().find(|&i| same_setting(&report.runs[i], s) && images(i).is_some())
        };
        h.push_str(&cost_chart(&g.name, resolution, &at, &front, &run_of));
    }
    h.push_str("</div>");
    super::summary_table::scene_summary(h, g);
    h.push_str("</div>");
}

fn same_setting(r: &RunRecord, s: &SettingSummary) -> bool {
    (r.label.as_str(), r.resolution, r.depth_format.as_str())
        == (s.label.as_str(), s.resolution, &s.depth_format)
}

const WIDTH: f64 = 460.0;
const HEIGHT: f64 = 260.0;
/// Room for the axes' labels: left, right, top, bottom.
const MARGIN: [f64; 4] = [52.0, 12.0, 14.0, 40.0];
/// Where settings without a measured cost stand: a strip left of the cost axis.
const UNMEASURED_X: f64 = 20.0;

/// The SVG chart of `settings`: error (linear, from zero) against cost (ns/pixel, log10), the
/// cost's range as a bar, the front as a step line, colours by technique. A point whose run has
/// figures carries `data-run` (its index in the report), which the page opens in the viewer.
fn cost_chart(
    scene: &str,
    resolution: u32,
    settings: &[&SettingSummary],
    front: &[&SettingSummary],
    run_of: &dyn Fn(&SettingSummary) -> Option<usize>,
) -> String {
    let measured: Vec<&&SettingSummary> = settings.iter().filter(|s| s.cost_measured).collect();
    let positive = |v: f64| v.is_finite() && v > 0.0;
    let costs: Vec<f64> = measured
        .iter()
        .flat_map(|s| [s.ns_per_pixel_range[0], s.ns_per_pixel_range[1], s.ns_per_pixel])
        .filter(|&c| positive(c))
        .collect();
    let (lo, hi) = costs.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &c| (a.min(c), b.max(c)));
    let (log_lo, log_hi) = if lo.is_finite() {
        (lo.log10().floor(), hi.log10().ceil().max(lo.log10().floor() + 1.0))
    } else {
        (0.0, 1.0)
    };
    let top_error = settings.iter().map(|s| s.error).fold(0.0f64, f64::max).max(1e-6) * 100.0;
    let top_error = nice_ceiling(top_error);
    let [ml, mr, mt, mb] = MARGIN;
    let x_of = |cost: f64| ml + (cost.log10() - log_lo) / (log_hi - log_lo) * (WIDTH - ml - mr);
    let y_of = |error_percent: f64| mt + (1.0 - error_percent / top_error) * (HEIGHT - mt - mb);
    let mut svg = String::new();
    let _ = write!(
        svg,
        "<svg class=\"cost-chart\" width=\"{WIDTH}\" height=\"{HEIGHT}\" viewBox=\"0 0 {WIDTH} {HEIGHT}\" \
         role=\"img\" aria-label=\"{0}: error against shading cost at {resolution}²\" font-size=\"11\">\
         <rect x=\"{ml}\" y=\"{mt}\" width=\"{1}\" height=\"{2}\" fill=\"#fff\" stroke=\"#999\"/>",
        escape(scene),
        WIDTH - ml - mr,
        HEIGHT - mt - mb
    );
    // Axes: a tick at every power of ten of cost, five of error.
    for p in log_lo as i32..=log_hi as i32 {
        let x = x_of(10f64.powi(p));
        let _ = write!(
            svg,
            "<line x1=\"{x:.1}\" y1=\"{0}\" x2=\"{x:.1}\" y2=\"{1}\" stroke=\"#eee\"/><text x=\"{x:.1}\" y=\"{2}\" \
             text-anchor=\"middle\">{3}</text>",
            mt,
            HEIGHT - mb,
            HEIGHT - mb + 14.0,
            10f64.powi(p)
        );
    }
    for k in 0..=4 {
        let e = top_error * k as f64 / 4.0;
        let y = y_of(e);
        let _ = write!(
            svg,
            "<line x1=\"{ml}\" y1=\"{y:.1}\" x2=\"{0}\" y2=\"{y:.1}\" stroke=\"#eee\"/><text x=\"{1}\" y=\"{2:.1}\" \
             text-anchor=\"end\">{3}</text>",
            WIDTH - mr,
            ml - 4.0,
            y + 4.0,
            trim_number(e)
        );
    }
    let _ = write!(
        svg,
        "<text x=\"{0}\" y=\"{1}\" text-anchor=\"middle\">shading cost, ns/pixel (this tool's CPU; log scale)</text>\
         <text x=\"12\" y=\"{2}\" text-anchor=\"middle\" transform=\"rotate(-90 12 {2})\">error % at {resolution}²</text>",
        (ml + WIDTH - mr) / 2.0,
        HEIGHT - 6.0,
        (mt + HEIGHT - mb) / 2.0
    );
    // The front, as the staircase a reader walks: cheaper to the left, better downwards.
    let mut steps: Vec<&&SettingSummary> =
        front.iter().filter(|s| s.cost_measured && positive(s.ns_per_pixel)).collect();
    steps.sort_by(|a, b| a.ns_per_pixel.total_cmp(&b.ns_per_pixel));
    if !steps.is_empty() {
        let mut path = String::new();
        for (k, s) in steps.iter().enumerate() {
            let (x, y) = (x_of(s.ns_per_pixel), y_of(100.0 * s.error));
            let _ = if k == 0 { write!(path, "M{x:.1},{y:.1}") } else { write!(path, " H{x:.1} V{y:.1}") };
        }
        let [r, g, b] = BEST;
        let _ = write!(
            svg,
            "<path class=\"front\" d=\"{path}\" fill=\"none\" stroke=\"#{r:02X}{g:02X}{b:02X}\" stroke-width=\"2\" \
             stroke-dasharray=\"5 3\"/>"
        );
    }
    let mut techniques: Vec<&str> = Vec::new();
    for s in settings {
        if !techniques.contains(&s.technique.as_str()) {
            techniques.push(&s.technique);
        }
    }
    for s in settings {
        let family = techniques.iter().position(|t| *t == s.technique).unwrap_or(0);
        let [r, g, b] = SERIES[family % SERIES.len()];
        let on_front = front.iter().any(|f| std::ptr::eq(*f, *s));
        let y = y_of(100.0 * s.error);
        let x = if s.cost_measured && positive(s.ns_per_pixel) { x_of(s.ns_per_pixel) } else { UNMEASURED_X };
        if s.cost_measured
            && positive(s.ns_per_pixel_range[0])
            && s.ns_per_pixel_range[0] < s.ns_per_pixel_range[1]
        {
            let _ = write!(
                svg,
                "<line x1=\"{:.1}\" y1=\"{y:.1}\" x2=\"{:.1}\" y2=\"{y:.1}\" stroke=\"#{r:02X}{g:02X}{b:02X}\"/>",
                x_of(s.ns_per_pixel_range[0]),
                x_of(s.ns_per_pixel_range[1])
            );
        }
        let [er, eg, eb] = TOTAL_ERROR;
        let run = run_of(s).map(|i| format!(" data-run=\"{i}\"")).unwrap_or_default();
        let _ = write!(
            svg,
            "<circle class=\"pt{}\"{run} cx=\"{x:.1}\" cy=\"{y:.1}\" r=\"{}\" fill=\"{}\" stroke=\"#{3:02X}{4:02X}{5:02X}\" \
             stroke-width=\"{6}\"><title>{7}: {8:.3} % error, {9} ns/pixel{10}</title></circle>",
            if run.is_empty() { "" } else { " open" },
            if on_front { 6 } else { 4 },
            if s.cost_measured { format!("#{r:02X}{g:02X}{b:02X}") } else { "#fff".into() },
            if on_front { er } else { r },
            if on_front { eg } else { g },
            if on_front { eb } else { b },
            if on_front { 2 } else { 1 },
            escape(&s.label),
            100.0 * s.error,
            s.cost_text(),
            if on_front {
                " — on the Pareto front"
            } else if !s.cost_measured {
                " — cost not measured here, never on the front"
            } else {
                ""
            }
        );
    }
    if settings.iter().any(|s| !s.cost_measured) {
        let _ = write!(
            svg,
            "<text x=\"{UNMEASURED_X}\" y=\"{}\" text-anchor=\"middle\">no cost</text>",
            HEIGHT - mb + 14.0
        );
    }
    svg.push_str("</svg>");
    svg
}

/// The least of 1, 2, 2.5, 5 times a power of ten at or above `v` (v > 0): an axis top.
fn nice_ceiling(v: f64) -> f64 {
    let p = 10f64.powf(v.log10().floor());
    [1.0, 2.0, 2.5, 5.0, 10.0].iter().map(|m| m * p).find(|&t| t >= v * (1.0 - 1e-12)).unwrap_or(10.0 * p)
}

/// A tick label: no more digits than it needs.
fn trim_number(v: f64) -> String {
    let s = format!("{v:.4}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn axis_tops_are_round_numbers_at_or_above_the_data() {
        assert_eq!(nice_ceiling(0.7), 1.0);
        assert_eq!(nice_ceiling(1.0), 1.0);
        assert_eq!(nice_ceiling(1.3), 2.0);
        assert_eq!(nice_ceiling(2.2), 2.5);
        assert_eq!(nice_ceiling(48.0), 50.0);
        assert_eq!(nice_ceiling(0.031), 0.05);
        assert_eq!(trim_number(12.5), "12.5");
        assert_eq!(trim_number(10.0), "10");
        assert_eq!(trim_number(0.0125), "0.0125");
    }
}
