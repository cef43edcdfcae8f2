//! Plots (SVG and PNG) of a report: error rate against each swept parameter, error against
//! shadow-map resolution, and shading cost against error with the Pareto front marked.
//! Drawn with plotters; text uses the bundled DejaVu Sans, so no system font is needed.

use super::bundled_font::DEJAVU_SANS_TTF;
use super::palette::{BEST, SERIES, rate_colour};
use super::pareto::{CostPoint, pareto_front};
use plotters::coord::CoordTranslate;
use plotters::prelude::*;
use shadowtruth::atomic_file::{encode_rgb_png, write_atomic};
use shadowtruth::file_name;
use shadowtruth::record::{Report, RunRecord};
use std::collections::BTreeMap;
use std::path::Path;

/// One chart: series of (x, y) points, optionally a Pareto front drawn over them.
#[derive(Clone, Debug)]
pub struct Chart {
    /// File stem under `plots/`.
    pub stem: String,
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub log_x: bool,
    /// A linear y axis from 0 (pixel counts) instead of the log axis of rates.
    pub linear_y: bool,
    /// The x values are whole numbers (frames): a linear x axis labels whole ticks only.
    pub integer_x: bool,
    /// The x values are base-2 logarithms (of resolutions): with `integer_x`, each whole tick
    /// is labelled with its power of two, so every resolution is.
    pub x_powers_of_two: bool,
    /// Series drawn as lines with markers (`points_only` draws markers alone).
    pub series: Vec<(String, Vec<(f64, f64)>)>,
    pub points_only: bool,
    /// Per series, the x range of its one point (a cost's least and greatest over the repeats),
    /// drawn as a horizontal bar; empty when no point has one.
    pub x_ranges: Vec<Option<[f64; 2]>>,
    pub pareto: Option<Vec<(f64, f64)>>,
    /// Per panel, a point marked (an optimum) with an x band around it (its safe range).
    pub marks: Vec<Option<Marks>>,
    /// Series per panel: more are drawn as small multiples on the same axes.
    pub panel_size: usize,
    /// What tells the panels apart (added to the title); "k/n" when empty.
    pub panel_titles: Vec<String>,
}

impl Default for Chart {
    /// No series; lines with markers; one panel per six series (one per colour).
    fn default() -> Self {
        Chart {
            stem: String::new(),
            title: String::new(),
            x_label: String::new(),
            y_label: String::new(),
            log_x: false,
            linear_y: false,
            integer_x: false,
            x_powers_of_two: false,
            series: Vec::new(),
            points_only: false,
            x_ranges: Vec::new(),
            pareto: None,
            marks: Vec::new(),
            panel_size: SERIES_PER_PANEL,
            panel_titles: Vec::new(),
        }
    }
}

#[derive(Clone, Debug)]
pub struct Marks {
    pub point: (f64, f64),
    pub point_label: String,
    pub band: (f64, f64),
    pub band_label: String,
}

fn register_font() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        // The bundled font parses; a failure would only lose the text, not the plot.
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, DEJAVU_SANS_TTF);
    });
}

/// An error (in %) no larger than this is drawn as the least of the log axis' data.
const Y_FLOOR: f64 = 1e-5;
/// What a log axis' label adds when it draws zeros (`ZeroRow`).
const ZERO_NOTE: &str = "0 drawn below the axis break";

/// A rate (a fraction) as a log axis takes it, in %: zeros stay zeros (`ZeroRow` draws them).
pub(super) fn percent_on_log_axis(fraction: f64) -> f64 {
    match 100.0 * fraction {
        0.0 => 0.0,
        v => v.max(Y_FLOOR),
    }
}

/// Where a log axis draws exact zeros: a row of their own, labelled 0, below a break under the
/// power of ten at or below the least positive value, so that a zero never reads as a small
/// error and the axis spans only the data's decades.
#[derive(Clone, Copy, Debug, PartialEq)]
struct ZeroRow {
    /// The lowest power of ten of the axis proper.
    floor: f64,
    /// Whether the chart has zeros at all: without, no row and no break are drawn.
    zeros: bool,
}

impl ZeroRow {
    fn of(c: &Chart) -> Self {
        let ys = c.series.iter().flat_map(|s| s.1.iter().map(|p| p.1));
        let ys = ys.chain(c.pareto.iter().flatten().map(|p| p.1));
        let (lowest, zeros) =
            ys.fold(
                (f64::INFINITY, false),
                |(low, zeros), y| if y > 0.0 { (low.min(y), zeros) } else { (low, true) },
            );
        let floor = if lowest.is_finite() { 10f64.powf(lowest.log10().floor()) } else { 0.01 };
        ZeroRow { floor, zeros }
    }
    fn row(self) -> f64 {
        self.floor / 4.0
    }
    /// The break's middle: the axis proper's ticks start above it.
    fn axis_break(self) -> f64 {
        self.floor / 2.0
    }
    fn bottom(self) -> f64 {
        if self.zeros { self.floor / 6.0 } else { self.floor * 0.7 }
    }
    /// `c` with its zeros moved onto the row, and its y label saying so when it has zeros.
    fn place(self, c: &Chart) -> Chart {
        let at = |(x, y): (f64, f64)| (x, if y == 0.0 { self.row() } else { y });
        let mut placed = c.clone();
        if self.zeros {
            placed.y_label = format!("{}; {ZERO_NOTE}", c.y_label);
        }
        for (_, points) in &mut placed.series {
            points.iter_mut().for_each(|p| *p = at(*p));
        }
        for p in placed.pareto.iter_mut().flatten() {
            *p = at(*p);
        }
        for m in placed.marks.iter_mut().flatten() {
            m.point = at(m.point);
        }
        placed
    }
}

fn error_percent(r: &RunRecord) -> f64 {
    percent_on_log_axis(r.rates.error)
}

/// A number with at most three significant digits, for axis labels.
fn compact(x: f64) -> String {
    if x == 0.0 {
        return "0".into();
    }
    let magnitude = x.abs().log10().floor();
    if !(-3.0..5.0).contains(&magnitude) {
        return format!("{x:.1e}");
    }
    let decimals = (2.0 - magnitude).max(0.0) as usize;
    let text = format!("{x:.decimals$}");
    if text.contains('.') { text.trim_end_matches('0').trim_end_matches('.').to_string() } else { text }
}

/// The (scene, camera, light) names of a run, the first part of every chart's key.
type View = (String, String, String);

fn view_of(r: &RunRecord) -> View {
    (r.scene.clone(), r.camera.clone(), r.light.clone())
}

/// `scene/camera/light`, as chart titles name a view.
fn view_title((scene, camera, light): &View) -> String {
    format!("{scene}/{camera}/{light}")
}

/// The stem under `plots/` of a chart of `kind` (`sweep`, `resolution`, `cost`) about `view`
/// and the rest of its key `exact_rest` (`readable_rest` as a reader should see it): bounded,
/// and one per identity (`src/file_name.rs`).
fn chart_stem(kind: &str, (scene, camera, light): &View, exact_rest: &[&str], readable_rest: &str) -> String {
    let readable = format!("{kind}_{scene}_{camera}_{light}_{readable_rest}");
    let exact: Vec<&str> =
        [kind, scene, camera, light].into_iter().chain(exact_rest.iter().copied()).collect();
    file_name::stem_with(&readable, &exact)
}

/// Every chart of a report.
pub fn charts(report: &Report) -> Vec<Chart> {
    let mut out = Vec::new();
    out.extend(parameter_sweeps(report));
    out.extend(resolution_charts(report));
    out.extend(cost_charts(report));
    out
}

/// The three rates of a run (in %, zeros on the zero row): total, false shadow, false lit.
fn rates_percent(r: &RunRecord) -> [f64; 3] {
    [r.rates.error, r.rates.false_shadow, r.rates.false_lit].map(percent_on_log_axis)
}

/// Error against each numeric parameter that varies while everything else about the run is
/// fixed: per resolution the error and its two parts, false shadow and false lit, whose
/// trade-off is what a bias sets. The lowest error of a one-resolution sweep is marked, with
/// the swept values whose error is within `SAFE_SLACK` of it.
fn parameter_sweeps(report: &Report) -> Vec<Chart> {
    // (scene/camera/light, technique, format, parameter, the other parameters) → resolution → points
    type Key = (View, String, String, String, String);
    type ByResolution = BTreeMap<u32, Vec<(f64, [f64; 3])>>;
    let mut groups: BTreeMap<Key, ByResolution> = BTreeMap::new();
    for r in &report.runs {
        for (name, value) in &r.parameters {
            let Some(x) = value.as_f64() else { continue };
            let mut others = r.parameters.clone();
            others.remove(name);
            let key = (
                view_of(r),
                r.technique.clone(),
                r.depth_format.clone(),
                name.clone(),
                serde_json::Value::Object(others).to_string(),
            );
            groups.entry(key).or_default().entry(r.resolution).or_default().push((x, rates_percent(r)));
        }
    }
    groups
        .into_iter()
        .filter(|(_, by_res)| by_res.values().any(|p| p.len() >= 2))
        .map(|((view, technique, format, param, others), by_res)| {
            // Two values are two measurements, not a curve: no line between them.
            let points_only = by_res.values().all(|p| p.len() < 3);
            let xs: Vec<f64> = by_res.values().flatten().map(|p| p.0).collect();
            let (lo, hi) = xs.iter().fold((f64::INFINITY, 0.0f64), |(a, b), &x| (a.min(x), b.max(x)));
            let others_text = others.trim_matches(|c| c == '{' || c == '}').replace('"', "");
            let (mut series, mut marks, mut panel_titles) = (Vec::new(), Vec::new(), Vec::new());
            for (res, mut pts) in by_res {
                pts.sort_by(|a, b| a.0.total_cmp(&b.0));
                for (k, part) in ["error", "false shadow", "false lit"].iter().enumerate() {
                    series.push((part.to_string(), pts.iter().map(|p| (p.0, p.1[k])).collect()));
                }
                marks.push(sweep_marks(&pts));
                panel_titles.push(format!("{res}²"));
            }
            Chart {
                stem: chart_stem(
                    "sweep",
                    &view,
                    &[&technique, &param, &format, &others],
                    &format!("{technique}_{param}_{format}_{others_text}"),
                ),
                title: format!(
                    "{}: {technique} {}{}",
                    view_title(&view),
                    if others_text.is_empty() { String::new() } else { format!("({others_text}) ") },
                    format
                ),
                x_label: param,
                y_label: "% of evaluated pixels".into(),
                log_x: lo > 0.0 && hi / lo > 20.0,
                points_only,
                series,
                marks,
                panel_size: 3,
                panel_titles,
                ..Chart::default()
            }
        })
        .collect()
}

/// A swept value is "safe" when its error is at most this much (relative) above the lowest.
const SAFE_SLACK: f64 = 0.1;

/// The lowest error of a sweep (sorted by x) and the contiguous swept values around it whose
/// error stays within `SAFE_SLACK` of it.
fn sweep_marks(points: &[(f64, [f64; 3])]) -> Option<Marks> {
    let best = (0..points.len()).min_by(|&a, &b| points[a].1[0].total_cmp(&points[b].1[0]))?;
    let bound = points[best].1[0] * (1.0 + SAFE_SLACK);
    let within = |i: &usize| points[*i].1[0] <= bound;
    let lo = (0..best).rev().take_while(within).last().unwrap_or(best);
    let hi = (best + 1..points.len()).take_while(within).last().unwrap_or(best);
    Some(Marks {
        point: (points[best].0, points[best].1[0]),
        point_label: format!("lowest error at {}", compact(points[best].0)),
        band: (points[lo].0, points[hi].0),
        band_label: format!("within {:.0} % of it", 100.0 * SAFE_SLACK),
    })
}

/// Points (x, y) of a chart's series, by series name.
type SeriesByName = BTreeMap<String, Vec<(f64, f64)>>;

/// Error against resolution, one series per technique setting.
fn resolution_charts(report: &Report) -> Vec<Chart> {
    // By (view, depth format).
    let mut groups: BTreeMap<(View, String), SeriesByName> = BTreeMap::new();
    for r in &report.runs {
        groups
            .entry((view_of(r), r.depth_format.clone()))
            .or_default()
            .entry(r.label.clone())
            .or_default()
            .push((r.resolution as f64, error_percent(r)));
    }
    groups
        .into_iter()
        .filter(|(_, s)| s.values().any(|p| p.len() >= 2))
        .map(|((view, format), series)| Chart {
            stem: chart_stem("resolution", &view, &[&format], &format),
            title: format!("{}: error against shadow-map resolution ({format})", view_title(&view)),
            x_label: "shadow-map resolution (texels per side)".into(),
            y_label: "error (% of evaluated pixels)".into(),
            // Resolutions double: equal steps on a log2 axis, each labelled.
            integer_x: true,
            x_powers_of_two: true,
            series: series
                .into_iter()
                .map(|(label, mut pts)| {
                    pts.sort_by(|a, b| a.0.total_cmp(&b.0));
                    (label, pts.into_iter().map(|(res, error)| (res.log2(), error)).collect())
                })
                .collect(),
            ..Chart::default()
        })
        .collect()
}

/// Shading cost against error at each resolution, one point per technique setting, with the
/// Pareto front.
fn cost_charts(report: &Report) -> Vec<Chart> {
    // By (view, resolution, depth format): (label, cost and error) per run.
    type Points = Vec<(String, CostPoint)>;
    let mut groups: BTreeMap<(View, u32, String), Points> = BTreeMap::new();
    for r in &report.runs {
        let point = CostPoint {
            cost: r.timings.ns_per_pixel,
            cost_range: r.timings.cost_range(),
            error: error_percent(r),
            measured: r.timings.cost_measured(),
        };
        groups
            .entry((view_of(r), r.resolution, r.depth_format.clone()))
            .or_default()
            .push((r.label.clone(), point));
    }
    groups
        .into_iter()
        .filter(|(_, pts)| pts.len() >= 2)
        .map(|((view, res, format), pts)| {
            let all: Vec<CostPoint> = pts.iter().map(|p| p.1).collect();
            let front = pareto_front(&all).into_iter().map(|i| (all[i].cost, all[i].error)).collect();
            Chart {
                stem: chart_stem("cost", &view, &[&res.to_string(), &format], &format!("{res}_{format}")),
                title: format!("{}: cost against error at {res}² ({format})", view_title(&view)),
                x_label: "shading cost (ns per evaluated pixel)".into(),
                y_label: "error (% of evaluated pixels)".into(),
                log_x: false,
                x_ranges: all.iter().map(|p| p.measured.then_some(p.cost_range)).collect(),
                series: pts.into_iter().map(|(label, p)| (label, vec![(p.cost, p.error)])).collect(),
                points_only: true,
                pareto: Some(front),
                ..Chart::default()
            }
        })
        .collect()
}

/// The x range of charts drawn on one x axis; None when they have no points.
fn x_range(charts: &[Chart]) -> Option<(f64, f64)> {
    let (mut x0, mut x1) = (f64::INFINITY, f64::NEG_INFINITY);
    for &(x, _) in charts.iter().flat_map(|c| &c.series).flat_map(|s| s.1.iter()) {
        x0 = x0.min(x);
        x1 = x1.max(x);
    }
    if !x0.is_finite() {
        return None;
    }
    Some((x0, if x1 <= x0 { x0 + 1.0 } else { x1 }))
}

/// The top of the chart's y axis: the labelled tick above its data.
fn y_top(c: &Chart) -> f64 {
    let y1 = c.series.iter().flat_map(|s| s.1.iter()).fold(0.0f64, |top, p| top.max(p.1));
    if c.linear_y {
        return if y1 <= 0.0 { 1.0 } else { linear_top_above(y1 * 1.05) };
    }
    // Errors span orders of magnitude (0.01 % to 50 %): a log axis, with zeros below its break.
    if y1 <= Y_FLOOR { 1.0 } else { labelled_tick_above(y1 * 1.2) }
}

/// The colours of series that are not an error rate (palette.rs), then the same colours with
/// another marker: no two series look alike.
const COLOURS: [RGBColor; SERIES.len()] = {
    let mut out = [RGBColor(0, 0, 0); SERIES.len()];
    let mut i = 0;
    while i < SERIES.len() {
        out[i] = RGBColor(SERIES[i][0], SERIES[i][1], SERIES[i][2]);
        i += 1;
    }
    out
};

/// The colour and marker of series `i`.
pub fn series_style(i: usize) -> (RGBColor, MarkerShape) {
    const SHAPES: [MarkerShape; 4] =
        [MarkerShape::Circle, MarkerShape::Triangle, MarkerShape::Square, MarkerShape::Cross];
    (COLOURS[i % COLOURS.len()], SHAPES[(i / COLOURS.len()) % SHAPES.len()])
}

/// The colour and marker of series `i` named `name`: an error rate's own colour (the colour
/// code, palette.rs) with a circle, else `series_style(i)`.
fn named_series_style(name: &str, i: usize) -> (RGBColor, MarkerShape) {
    match rate_colour(name) {
        Some([r, g, b]) => (RGBColor(r, g, b), MarkerShape::Circle),
        None => series_style(i),
    }
}

/// A sweep's best value and its band (palette.rs).
const BEST_COLOUR: RGBColor = RGBColor(BEST[0], BEST[1], BEST[2]);

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MarkerShape {
    Circle,
    Triangle,
    Square,
    Cross,
}

/// A marker of `shape` at `at` (backend pixels), `size` pixels across.
fn marker<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    shape: MarkerShape,
    at: (i32, i32),
    size: i32,
    colour: RGBColor,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let (x, y) = at;
    let r = size / 2;
    match shape {
        MarkerShape::Circle => area.draw(&Circle::new(at, r, colour.filled())),
        MarkerShape::Triangle => {
            area.draw(&Polygon::new(vec![(x, y - r), (x - r, y + r), (x + r, y + r)], colour.filled()))
        }
        MarkerShape::Square => area.draw(&Rectangle::new([(x - r, y - r), (x + r, y + r)], colour.filled())),
        MarkerShape::Cross => {
            area.draw(&PathElement::new(vec![(x - r, y - r), (x + r, y + r)], colour.stroke_width(2)))?;
            area.draw(&PathElement::new(vec![(x - r, y + r), (x + r, y - r)], colour.stroke_width(2)))
        }
    }
}

/// Tick labels of a log axis: only at 1, 2 and 5 times a power of ten, so that they never run
/// into each other.
fn log_tick(x: f64) -> String {
    if x <= 0.0 {
        return String::new();
    }
    let mantissa = x / 10f64.powf(x.log10().floor());
    if [1.0, 2.0, 5.0, 10.0].iter().any(|m| (mantissa - m).abs() < 1e-6 * m) {
        compact(x)
    } else {
        String::new()
    }
}

/// The ticks of a log axis over [lo, hi]: 1, 2 and 5 times each power of ten (each power alone
/// over more than four decades), once each; none
/// unless 0 < lo < hi are finite (a linear axis asks too, and ignores them).
fn log_key_points(lo: f64, hi: f64) -> Vec<f64> {
    if !(lo > 0.0 && lo < hi && hi.is_finite()) {
        return Vec::new();
    }
    // f64 spans 632 decades: the range below is bounded whatever the numbers.
    let (first, last) = (lo.log10().floor() as i32, hi.log10().ceil() as i32);
    // Over many decades, 2 and 5 would crowd the labels: powers of ten alone.
    let steps: &[f64] = if last - first > 4 { &[1.0] } else { &[1.0, 2.0, 5.0] };
    (first..=last)
        .flat_map(|p| steps.iter().map(move |m| m * 10f64.powi(p)))
        .filter(|&t| t >= lo * (1.0 - 1e-9) && t <= hi * (1.0 + 1e-9))
        .collect()
}

/// The least of 1, 2 and 5 times a power of ten that is at least `y` (> 0).
fn labelled_tick_above(y: f64) -> f64 {
    let decade = 10f64.powf(y.log10().floor());
    [1.0, 2.0, 5.0, 10.0].iter().map(|m| m * decade).find(|&t| t >= y).unwrap_or(10.0 * decade)
}

/// The least round number (1, 1.2, 1.5, 2, 2.5, 3, 4, 5, 6 or 8 times a power of ten) that is at
/// least `y` (> 0): the top of a linear axis, finer than the log axis' steps so that the data fill
/// the panel.
fn linear_top_above(y: f64) -> f64 {
    let decade = 10f64.powf(y.log10().floor());
    [1.0, 1.2, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0, 6.0, 8.0, 10.0]
        .iter()
        .map(|m| m * decade)
        .find(|&t| t >= y)
        .unwrap_or(10.0 * decade)
}

/// The Pareto front as a step line: from each non-dominated point across at its error to the
/// next one's cost, then down to it.
pub fn pareto_steps(front: &[(f64, f64)]) -> Vec<(f64, f64)> {
    let mut out = Vec::new();
    for (i, &p) in front.iter().enumerate() {
        if i > 0 {
            out.push((p.0, front[i - 1].1));
        }
        out.push(p);
    }
    out
}

/// Most markers drawn on one series.
const MAX_MARKERS: usize = 60;

/// Width of the legend column right of the plot, in pixels.
const LEGEND_WIDTH: u32 = 330;
/// Longest series name drawn in the legend, in characters.
const LEGEND_CHARS: usize = 48;

/// Most series in one panel: a chart with more is drawn as small multiples, a panel per eight
/// series on the same axes, so that colours never repeat within a panel.
pub const SERIES_PER_PANEL: usize = COLOURS.len();

/// The chart's panels: itself, or its series `panel_size` at a time (each panel with the whole
/// chart's Pareto front and its own marks).
pub fn panels(c: &Chart) -> Vec<Chart> {
    if c.series.len() <= c.panel_size {
        return vec![c.clone()];
    }
    let count = c.series.len().div_ceil(c.panel_size);
    c.series
        .chunks(c.panel_size)
        .enumerate()
        .map(|(i, chunk)| Chart {
            title: match c.panel_titles.get(i) {
                Some(t) => format!("{}: {t}", c.title),
                None => format!("{} ({}/{count})", c.title, i + 1),
            },
            series: chunk.to_vec(),
            x_ranges: c.x_ranges.iter().skip(i * c.panel_size).take(chunk.len()).copied().collect(),
            marks: vec![c.marks.get(i).cloned().flatten()],
            ..c.clone()
        })
        .collect()
}

/// The rows of charts drawn one above the other: each chart's panels, on its own y axis.
fn rows(charts: &[Chart]) -> Vec<(Chart, f64)> {
    charts.iter().flat_map(|c| panels(c).into_iter().map(move |p| (p, y_top(c)))).collect()
}

/// Charts one above the other (usually one), each as its panels, all on the same x axis.
fn draw<DB: DrawingBackend>(
    root: DrawingArea<DB, plotters::coord::Shift>,
    charts: &[Chart],
) -> Result<(), String>
where
    DB::ErrorType: 'static,
{
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    root.fill(&WHITE).map_err(err)?;
    let Some((x0, x1)) = x_range(charts) else { return Ok(()) };
    let rows = rows(charts);
    for (area, (panel, y1)) in root.split_evenly((rows.len(), 1)).into_iter().zip(&rows) {
        draw_panel(area, panel, (x0, x1, *y1))?;
    }
    root.present().map_err(err)
}

/// Draws a panel's grid, series, Pareto front and marks on `$chart` (a chart context over any
/// of the four pairs of linear and log axes, which are different types): `$c` the panel,
/// `$band_y` the y extent of its marked band, `$x_tick`/`$y_tick` its tick labels, `$zero` the
/// zero row of a log y axis.
macro_rules! panel_body {
    ($chart:expr, $c:expr, $band_y:expr, $x_tick:expr, $y_tick:expr, $zero:expr, $err:expr) => {{
        let (c, err, (band_bottom, band_top)) = ($c, $err, $band_y);
        let mut chart = $chart;
        chart
            .configure_mesh()
            // No light lines: on a log axis they crowd into grey bands.
            .max_light_lines(0)
            .x_label_formatter(&|x: &f64| $x_tick(*x))
            .y_label_formatter(&|y: &f64| $y_tick(*y))
            .x_desc(c.x_label.as_str())
            .y_desc(c.y_label.as_str())
            .label_style(("sans-serif", 13))
            .draw()
            .map_err(err)?;
        if let Some(zero) = $zero.filter(|z: &ZeroRow| z.zeros) {
            // The axis break: a white band across the plot, edged with dashes, and the zero row's
            // label at its left.
            let (x_lo, x_hi, middle) = (chart.x_range().start, chart.x_range().end, zero.axis_break());
            let band = [(x_lo, middle * 0.85), (x_hi, middle * 1.15)];
            chart.draw_series(std::iter::once(Rectangle::new(band, WHITE.filled()))).map_err(err)?;
            for edge in [middle * 0.85, middle * 1.15] {
                chart
                    .draw_series(DashedLineSeries::new(
                        [(x_lo, edge), (x_hi, edge)],
                        4,
                        3,
                        BLACK.mix(0.5).into(),
                    ))
                    .map_err(err)?;
            }
            // Just inside the plot, where the series' zeros start.
            use plotters::style::text_anchor::{HPos, Pos, VPos};
            let style =
                TextStyle::from(("sans-serif", 13).into_font()).pos(Pos::new(HPos::Left, VPos::Center));
            let label = Text::new("0", (x_lo, zero.row()), style);
            chart.draw_series(std::iter::once(label)).map_err(err)?;
        }
        if let Some(Some(m)) = c.marks.first() {
            let band = [(m.band.0, band_bottom), (m.band.1, band_top)];
            chart
                .draw_series(std::iter::once(Rectangle::new(band, BEST_COLOUR.mix(0.15).filled())))
                .map_err(err)?;
        }
        for (i, (name, points)) in c.series.iter().enumerate() {
            let (colour, shape) = named_series_style(name, i);
            if !c.points_only {
                chart
                    .draw_series(LineSeries::new(points.iter().copied(), colour.stroke_width(2)))
                    .map_err(err)?;
            }
            draw_markers(&mut chart, points, shape, colour).map_err(err)?;
            if let (Some(Some([lo, hi])), Some(&(x, y))) = (c.x_ranges.get(i), points.first()) {
                let bar = ErrorBar::new_horizontal(y, *lo, x, *hi, colour.stroke_width(1), 8);
                chart.draw_series(std::iter::once(bar)).map_err(err)?;
            }
        }
        if let Some(front) = &c.pareto {
            chart.draw_series(LineSeries::new(pareto_steps(front), BLACK.stroke_width(2))).map_err(err)?;
            chart
                .draw_series(front.iter().map(|&p| Circle::new(p, 7, BLACK.stroke_width(2))))
                .map_err(err)?;
        }
        if let Some(Some(m)) = c.marks.first() {
            chart
                .draw_series(std::iter::once(Cross::new(m.point, 9, BEST_COLOUR.stroke_width(3))))
                .map_err(err)?;
        }
    }};
}

/// One panel of a chart, on the axes of `range` (the whole chart's).
fn draw_panel<DB: DrawingBackend>(
    root: DrawingArea<DB, plotters::coord::Shift>,
    c: &Chart,
    (x0, x1, y1): (f64, f64, f64),
) -> Result<(), String>
where
    DB::ErrorType: 'static,
{
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    let (plot_area, legend_area) = root.split_horizontally(root.dim_in_pixel().0 - LEGEND_WIDTH);
    let mut builder = ChartBuilder::on(&plot_area);
    builder.caption(&c.title, ("sans-serif", 18)).margin(12).x_label_area_size(40).y_label_area_size(56);
    let zero = (!c.linear_y).then(|| ZeroRow::of(c));
    let placed = zero.map(|z| z.place(c));
    let c = placed.as_ref().unwrap_or(c);
    let y0 = zero.map_or(0.0, ZeroRow::bottom);
    let pad = (x1 - x0) * 0.05;
    let (log_x, linear_x) = (x0 * 0.9..x1 * 1.1, (x0 - pad).max(0.0)..x1 + pad);
    let x_tick = |x: f64| match (c.integer_x && x.fract() != 0.0, c.x_powers_of_two) {
        (true, _) => String::new(),
        (false, true) => compact(x.exp2()),
        (false, false) => compact(x),
    };
    // Log axes get their ticks from us (1, 2 and 5 times each power of ten), each once: left to
    // itself, the log scale may put two ticks on one round value and print it twice.
    // Ticks from the axis proper's floor up (with a little room for the floor's rounding).
    let y_from = zero.filter(|z| z.zeros).map_or(y0, |z| z.floor * (1.0 - 1e-9));
    let (x_keys, y_keys) = (log_key_points(log_x.start, log_x.end), log_key_points(y_from, y1));
    // No tick label under the break: the zero row is labelled on its own.
    let y_tick = |y: f64| if y < y_from { String::new() } else { log_tick(y) };
    let log_x = || log_x.clone().log_scale().with_key_points(x_keys.clone());
    let log_y = || (y0..y1).log_scale().with_key_points(y_keys.clone());
    match (c.log_x, c.linear_y) {
        (true, false) => panel_body!(
            builder.build_cartesian_2d(log_x(), log_y()).map_err(err)?,
            c,
            (y0, y1),
            log_tick,
            y_tick,
            zero,
            err
        ),
        (true, true) => panel_body!(
            builder.build_cartesian_2d(log_x(), y0..y1).map_err(err)?,
            c,
            (y0, y1),
            log_tick,
            compact,
            zero,
            err
        ),
        (false, false) => panel_body!(
            builder.build_cartesian_2d(linear_x, log_y()).map_err(err)?,
            c,
            (y0, y1),
            x_tick,
            y_tick,
            zero,
            err
        ),
        (false, true) => panel_body!(
            builder.build_cartesian_2d(linear_x, y0..y1).map_err(err)?,
            c,
            (y0, y1),
            x_tick,
            compact,
            zero,
            err
        ),
    }
    draw_legend(&legend_area, c).map_err(err)
}

/// The markers of one series at its data points.
fn draw_markers<DB: DrawingBackend, CT: CoordTranslate<From = (f64, f64)>>(
    chart: &mut ChartContext<'_, DB, CT>,
    points: &[(f64, f64)],
    shape: MarkerShape,
    colour: RGBColor,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let r = 4;
    // Markers on a long series (the frames of a path) would hide its line: at most
    // `MAX_MARKERS` of them, evenly spaced.
    let at = points.iter().copied().step_by(points.len().div_ceil(MAX_MARKERS).max(1));
    match shape {
        MarkerShape::Circle => {
            chart.draw_series(at.map(|p| EmptyElement::at(p) + Circle::new((0, 0), r, colour.filled())))?;
        }
        MarkerShape::Triangle => {
            chart.draw_series(at.map(|p| TriangleMarker::new(p, r + 1, colour.filled())))?;
        }
        MarkerShape::Square => {
            chart.draw_series(
                at.map(|p| EmptyElement::at(p) + Rectangle::new([(-r, -r), (r, r)], colour.filled())),
            )?;
        }
        MarkerShape::Cross => {
            chart.draw_series(at.map(|p| Cross::new(p, r, colour.stroke_width(2))))?;
        }
    }
    Ok(())
}

/// The legend's names of series named `technique(k=v,…)`: where a name is too long for the
/// legend, the parameters every series of its technique shares are left out (marked `…`), so
/// that what tells the series apart is what stays.
fn legend_names(names: &[&str]) -> Vec<String> {
    let split = |name: &str| -> Option<(String, Vec<String>)> {
        let (technique, rest) = name.split_once('(')?;
        let params = rest.strip_suffix(')')?;
        Some((technique.to_string(), params.split(',').map(str::to_string).collect()))
    };
    let parsed: Vec<Option<(String, Vec<String>)>> = names.iter().map(|n| split(n)).collect();
    names
        .iter()
        .zip(&parsed)
        .map(|(name, parts)| match parts {
            Some((technique, params)) if name.chars().count() > LEGEND_CHARS => {
                let siblings: Vec<&Vec<String>> =
                    parsed.iter().flatten().filter(|(t, _)| t == technique).map(|(_, p)| p).collect();
                let shared = |p: &String| siblings.len() > 1 && siblings.iter().all(|s| s.contains(p));
                let kept: Vec<&str> = params.iter().filter(|p| !shared(p)).map(String::as_str).collect();
                if kept.len() == params.len() {
                    name.to_string()
                } else {
                    format!("{technique}(…,{})", kept.join(","))
                }
            }
            _ => name.to_string(),
        })
        .collect()
}

/// The legend in its own column, beside the data rather than over it.
fn draw_legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    c: &Chart,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let font = ("sans-serif", 12).into_font();
    let mut y = 48;
    let row = |area: &DrawingArea<DB, plotters::coord::Shift>, text: &str, y: i32| {
        let shown: String = if text.chars().count() > LEGEND_CHARS {
            text.chars().take(LEGEND_CHARS - 1).chain(std::iter::once('…')).collect()
        } else {
            text.to_string()
        };
        area.draw(&Text::new(shown, (34, y - 7), font.clone()))
    };
    let names: Vec<&str> = c.series.iter().map(|(name, _)| name.as_str()).collect();
    for (i, (name, shown)) in names.iter().zip(legend_names(&names)).enumerate() {
        let (colour, shape) = named_series_style(name, i);
        if !c.points_only {
            area.draw(&PathElement::new(vec![(4, y), (26, y)], colour.stroke_width(2)))?;
        }
        marker(area, shape, (15, y), 8, colour)?;
        row(area, &shown, y)?;
        y += 18;
    }
    if c.pareto.is_some() {
        area.draw(&PathElement::new(vec![(4, y), (26, y)], BLACK.stroke_width(2)))?;
        row(area, "Pareto front (non-dominated)", y)?;
        y += 18;
    }
    if let Some(Some(m)) = c.marks.first() {
        area.draw(&Cross::new((15, y), 9, BEST_COLOUR.stroke_width(3)))?;
        row(area, &m.point_label, y)?;
        y += 18;
        area.draw(&Rectangle::new([(4, y - 6), (26, y + 6)], BEST_COLOUR.mix(0.15).filled()))?;
        row(area, &m.band_label, y)?;
    }
    Ok(())
}

const WIDTH: u32 = 1180;
const HEIGHT: u32 = 560;
const PANEL_HEIGHT: u32 = 440;

#[cfg(test)]
/// The chart as SVG text.
pub fn chart_svg(chart: &Chart) -> std::io::Result<String> {
    stacked_svg(std::slice::from_ref(chart))
}

/// Charts one above the other on one x axis (each with its own y axis, and as small multiples
/// when it has many series), as SVG text.
pub fn stacked_svg(charts: &[Chart]) -> std::io::Result<String> {
    register_font();
    let mut svg = String::new();
    draw(SVGBackend::with_string(&mut svg, (WIDTH, charts_height(charts))).into_drawing_area(), charts)
        .map_err(std::io::Error::other)?;
    Ok(svg)
}

/// Pixels tall: one panel, or a shorter one per panel of small multiples or stacked charts.
fn charts_height(charts: &[Chart]) -> u32 {
    match charts.iter().map(|c| panels(c).len()).sum::<usize>() {
        0 | 1 => HEIGHT,
        n => n as u32 * PANEL_HEIGHT,
    }
}

/// Draws `chart` as `dir/<stem>.svg` and `dir/<stem>.png`.
pub fn write_chart(dir: &Path, chart: &Chart) -> std::io::Result<()> {
    write_stacked(dir, &chart.stem, std::slice::from_ref(chart))
}

/// Draws `charts` one above the other (see [`stacked_svg`]) as `dir/<stem>.svg` and
/// `dir/<stem>.png`.
pub fn write_stacked(dir: &Path, stem: &str, charts: &[Chart]) -> std::io::Result<()> {
    write_atomic(&dir.join(format!("{stem}.svg")), stacked_svg(charts)?.as_bytes())?;
    let height = charts_height(charts);
    let mut rgb = vec![255u8; (WIDTH * height * 3) as usize];
    draw(BitMapBackend::with_buffer(&mut rgb, (WIDTH, height)).into_drawing_area(), charts)
        .map_err(std::io::Error::other)?;
    write_atomic(&dir.join(format!("{stem}.png")), &encode_rgb_png(WIDTH, height, &rgb)?)
}

/// `plots/`: every chart of the report, each as SVG and PNG.
pub struct PlotsExport;

impl crate::export::Export for PlotsExport {
    fn write(&self, dir: &Path, report: &Report) -> std::io::Result<()> {
        use rayon::prelude::*;
        let plots_dir = dir.join("plots");
        std::fs::create_dir_all(&plots_dir)?;
        charts(report).par_iter().try_for_each(|c| write_chart(&plots_dir, c))
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    use crate::drawing::palette::{FALSE_LIT, FALSE_SHADOW, TOTAL_ERROR};

    fn chart(series: usize) -> Chart {
        Chart {
            stem: "t".into(),
            title: "t".into(),
            x_label: "x".into(),
            y_label: "y".into(),
            log_x: false,
            series: (0..series)
                .map(|i| (format!("s{i}"), vec![(1.0, 1.0 + i as f64), (2.0, 2.0 + i as f64)]))
                .collect(),
            ..Chart::default()
        }
    }

    /// The stroke colours of the series lines (width 2) in an SVG, each once per line drawn.
    pub(crate) fn line_colours(svg: &str) -> Vec<String> {
        let doc = roxmltree::Document::parse(svg).expect("plotters writes valid SVG");
        doc.descendants()
            .filter(|n| n.has_tag_name("polyline") && n.attribute("stroke-width") == Some("2"))
            .filter_map(|n| n.attribute("stroke").map(str::to_string))
            .collect()
    }

    /// The colour code (palette.rs): wherever the rates are drawn, false shadow is vermillion,
    /// false lit blue and the error black, whatever their order; other series take none of them.
    #[test]
    fn rates_are_drawn_in_the_colour_code() {
        let hex = |[r, g, b]: [u8; 3]| format!("#{r:02X}{g:02X}{b:02X}");
        let mut c = chart(5);
        for (k, name) in ["false lit", "error", "false shadow"].into_iter().enumerate() {
            c.series[k + 1].0 = name.into();
        }
        let colours = line_colours(&chart_svg(&c).unwrap());
        let (shadow, lit, total) = (hex(FALSE_SHADOW), hex(FALSE_LIT), hex(TOTAL_ERROR));
        // Each line twice: in the plot and in the legend.
        assert_eq!(colours.len(), 10, "{colours:?}");
        assert_eq!([&colours[1], &colours[2], &colours[3]], [&lit, &total, &shadow], "{colours:?}");
        assert!(![&colours[0], &colours[4]].iter().any(|c| [&shadow, &lit, &total].contains(c)));
    }

    #[test]
    fn long_legend_names_keep_what_tells_the_series_apart() {
        let long = [
            "normal_offset(falloff=sin_theta,scale_texels=0.5)",
            "normal_offset(falloff=sin_theta,scale_texels=1.0)",
        ];
        let names = [long[0], long[1], "none", "receiver_plane(bias_depth=0.0)"];
        let shown = legend_names(&names);
        assert_eq!(shown[..2], ["normal_offset(…,scale_texels=0.5)", "normal_offset(…,scale_texels=1.0)"]);
        assert_eq!(shown[2..], ["none", "receiver_plane(bias_depth=0.0)"], "short names stay whole");
        // A long name alone of its technique keeps every parameter (then the legend cuts it).
        assert_eq!(legend_names(&[long[0], "none"])[0], long[0]);
    }

    #[test]
    fn series_in_one_panel_never_share_a_colour_and_marker() {
        let styles: Vec<_> = (0..COLOURS.len() * 4).map(series_style).collect();
        for (i, a) in styles.iter().enumerate() {
            for b in &styles[i + 1..] {
                assert_ne!(a, b);
            }
        }
        // Drawn: 20 series make three panels, and within each the lines' colours differ.
        let c = chart(20);
        let panels = panels(&c);
        assert_eq!(panels.iter().map(|p| p.series.len()).collect::<Vec<_>>(), [6, 6, 6, 2]);
        for panel in &panels {
            let mut colours = line_colours(&chart_svg(panel).unwrap());
            // The legend repeats each series' line once.
            colours.sort();
            colours.dedup();
            assert_eq!(colours.len(), panel.series.len(), "{colours:?}");
        }
    }

    #[test]
    fn the_pareto_step_line_turns_only_at_front_points() {
        for points in crate::drawing::pareto::tests::random_point_sets() {
            let front: Vec<(f64, f64)> =
                pareto_front(&points).into_iter().map(|i| (points[i].cost, points[i].error)).collect();
            // Every other corner is (next x, previous y).
            let steps = pareto_steps(&front);
            assert_eq!(steps.len(), 2 * front.len() - 1);
            for (k, w) in steps.windows(2).enumerate() {
                assert!(w[0].0 == w[1].0 || w[0].1 == w[1].1, "segment {k} is not a step");
            }
        }
    }

    /// A cost chart draws each measured point's cost range as a bar, and no front mark on a
    /// point whose cost was not measured.
    #[test]
    fn cost_ranges_are_drawn_and_unmeasured_costs_stay_off_the_front() {
        let run = |label: &str, ns: f64, range: Option<[f64; 2]>, shade: f64, false_shadow: u64| {
            let counts = shadowtruth::metrics::Counts { evaluated: 1000, false_shadow, ..Default::default() };
            let mut r = crate::gate::test_run("s", "constant", serde_json::json!({}), label, counts);
            r.rates = r.counts.rates();
            r.timings = shadowtruth::record::Timings {
                prepare: 1.0,
                shade,
                ns_per_pixel: ns,
                ns_per_pixel_min: range.map(|r| r[0]),
                ns_per_pixel_max: range.map(|r| r[1]),
            };
            r
        };
        let report = Report {
            runs: vec![
                run("none", 9.0, Some([8.5, 10.5]), 5.0, 480),
                run("constant", 9.6, Some([9.0, 11.0]), 5.0, 5),
                run("external", 0.0, None, 0.0, 1),
            ],
            ..Report::new()
        };
        let charts = cost_charts(&report);
        assert_eq!(charts.len(), 1);
        let c = &charts[0];
        assert_eq!(c.x_ranges, [Some([8.5, 10.5]), Some([9.0, 11.0]), None]);
        assert_eq!(c.pareto, Some(vec![(9.6, 0.5)]), "none is within constant's noise; external unmeasured");
        assert!(chart_svg(c).is_ok());
    }

    /// A zero is drawn as 0: on a row of its own below a break in the log axis, labelled "0",
    /// never at the axis' least value; the axis starts at the power of ten below the least
    /// positive value. A chart without zeros has no break.
    #[test]
    fn zeros_sit_on_their_own_row_below_the_axis_break() {
        let mut c = chart(1);
        c.series[0].1 = vec![(1.0, percent_on_log_axis(0.0)), (2.0, percent_on_log_axis(0.0003))];
        let zero = ZeroRow::of(&c);
        assert_eq!(zero, ZeroRow { floor: 0.01, zeros: true });
        let placed = zero.place(&c);
        assert_eq!(placed.series[0].1, [(1.0, 0.0025), (2.0, 0.03)]);
        assert!(
            zero.row() < zero.axis_break() && zero.axis_break() < zero.floor && zero.bottom() < zero.row()
        );
        let svg = chart_svg(&c).unwrap();
        let doc = roxmltree::Document::parse(&svg).unwrap();
        let texts: Vec<&str> = doc
            .descendants()
            .filter(|n| n.has_tag_name("text"))
            .filter_map(|n| n.text())
            .map(str::trim)
            .collect();
        assert!(texts.contains(&"0"), "the zero row is labelled: {texts:?}");
        assert!(texts.iter().any(|t| t.ends_with(ZERO_NOTE)), "the y label says where zeros are: {texts:?}");
        assert!(
            !texts.iter().any(|t| t.contains("e-3") || *t == "0.005"),
            "no tick under the break: {texts:?}"
        );
        // The break's dashes: short half-grey segments.
        let dashed = |svg: &str| svg.matches("opacity=\"0.5\"").count();
        assert!(dashed(&svg) > 20, "the break is drawn");
        c.series[0].1[0].1 = 0.02;
        assert!(!ZeroRow::of(&c).zeros);
        let svg = chart_svg(&c).unwrap();
        assert_eq!(dashed(&svg), 0, "no zeros, no break");
        assert!(!svg.contains(ZERO_NOTE), "no zeros, no word of them");
    }

    #[test]
    fn log_ticks_are_labelled_only_at_one_two_and_five() {
        let labelled: Vec<f64> = [1e-4, 1.5e-4, 2e-4, 3e-4, 5e-4, 7e-4, 1e-3, 0.02, 0.09, 40.0, 50.0]
            .into_iter()
            .filter(|&x| !log_tick(x).is_empty())
            .collect();
        assert_eq!(labelled, [1e-4, 2e-4, 5e-4, 1e-3, 0.02, 50.0]);
        assert_eq!(labelled_tick_above(0.07), 0.1);
        assert_eq!(log_key_points(3e-4, 0.02), [5e-4, 1e-3, 2e-3, 5e-3, 1e-2, 2e-2].map(|v: f64| v));
        assert!(log_key_points(0.0, 1.0).is_empty() && log_key_points(1.0, f64::INFINITY).is_empty());
        assert_eq!(labelled_tick_above(3.0), 5.0);
        assert_eq!(linear_top_above(210.0), 250.0);
        assert_eq!(linear_top_above(7.0), 8.0);
    }
}
