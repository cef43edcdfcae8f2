//! `index.html`: one offline page per report folder — the runs table (sortable), runs over a path
//! (`path_section.rs`), on cascaded shadow maps (`cascades_section.rs`) and under point lights
//! (`point_map_section.rs`), the plots, the
//! figures, the settings and the tool version. Only relative links; no network.

use super::answer_section::answer_section;
use super::cascades_section::cascades_section;
use super::figures::{run_stem, view_stem};
use super::path_section::{PathAssets, path_assets, path_section};
use super::plots::charts;
use super::point_map_section::point_map_section;
use crate::escape::escape_html as escape;
use shadowtruth::record::Report;
use shadowtruth::scene::ViewKey;
use std::fmt::Write as _;
use std::path::Path;

/// Images and links the page shows, relative to the report folder.
#[derive(Clone, Debug, Default)]
pub struct PageAssets {
    /// Plot stems under `plots/` (each has .png and .svg).
    pub plots: Vec<String>,
    /// Figure grids and reference figures, paths under `figures/`, with a caption.
    pub figures: Vec<(String, String)>,
    /// Per run (same order as `report.runs`): its figure paths (technique, error), if written.
    pub run_figures: Vec<Option<(String, String)>>,
    /// Per run: the reference figure of its view, if written.
    pub run_references: Vec<Option<String>>,
    /// A `tune` folder's tune.json and its plots (stems under `plots/`).
    pub tune: Option<(serde_json::Value, Vec<String>)>,
    /// The animations, heat maps and per-frame plots of runs over a path.
    pub path: PathAssets,
}

const STYLE: &str = "body{font-family:system-ui,sans-serif;margin:1.5em;color:#222}\
table{border-collapse:collapse;font-size:13px}th,td{border:1px solid #ccc;padding:3px 6px;text-align:right}\
th{background:#eee;cursor:pointer;position:sticky;top:0}td.l,th.l{text-align:left}\
tr:nth-child(even){background:#fafafa}.plots img,.figs img{max-width:100%;border:1px solid #ddd;margin:4px 0}\
.figs figure{display:inline-block;margin:6px;vertical-align:top;max-width:48%}#status{color:#666;font-size:12px}\
.summary{margin-bottom:1.2em}td.front{color:#070}#filters{margin:.6em 0}#filters label{margin-right:1em}\
#viewer{border:1px solid #ccc;padding:8px;margin:1em 0;background:#f7f7f7}#view-stage{position:relative;overflow:auto;max-height:80vh;max-width:100%}\
#view-stage img{display:block;image-rendering:pixelated}#view-over{position:absolute;left:0;top:0}\
#view-divider{position:absolute;top:0;width:2px;margin-left:-1px;background:#000;box-shadow:0 0 0 1px #fff;pointer-events:none}\
#view-pixel{font-family:monospace;font-size:12px;min-height:1.2em}\
#view-modes button[aria-pressed=true]{font-weight:bold;background:#dde}button.view{font-size:12px}\
body{max-width:1240px}.table-wrap{overflow-x:auto;max-width:100%}#runs{font-size:12px}#runs td.l{max-width:220px;overflow-wrap:anywhere}\
.scene-answer{margin:0 0 1.5em}.answer-row{display:flex;flex-wrap:wrap;gap:8px;align-items:flex-start}\
.answer-row figure{margin:0;max-width:370px}.answer-img{width:100%;border:1px solid #ddd;image-rendering:pixelated}\
.answer-row figcaption{font-size:12px;color:#444}.cost-chart circle.open{cursor:pointer}#pager{margin:.4em 0}";

/// Sorting, filters, the viewer and the images-loaded status line (read by tests).
const SCRIPT: &str = include_str!("page.js");

pub fn index_html(report: &Report, assets: &PageAssets) -> String {
    let mut h = String::new();
    page_header(&mut h, report);
    if let Some((tune, plots)) = &assets.tune {
        tune_section(&mut h, tune, plots);
    }
    let images = |i: usize| {
        let (technique, error) = assets.run_figures.get(i)?.as_ref()?;
        let reference = assets.run_references.get(i)?.as_ref()?;
        Some((reference.as_str(), technique.as_str(), error.as_str()))
    };
    answer_section(&mut h, report, &images);
    viewer_section(&mut h);
    filters_section(&mut h, report);
    runs_table(&mut h, report, &images);
    scenes_table(&mut h, report);
    path_section(&mut h, report, &assets.path);
    cascades_section(&mut h, report);
    point_map_section(&mut h, report);
    figures_section(&mut h, assets);
    plots_section(&mut h, assets);
    let _ = writeln!(h, "<script>{SCRIPT}</script></body></html>");
    h
}

fn page_header(h: &mut String, report: &Report) {
    let _ = write!(
        h,
        "<!doctype html><html lang=\"en\"><head><meta charset=\"utf-8\"><title>shadowtruth report</title>\
         <style>{STYLE}</style></head><body><h1>shadowtruth report</h1>\
         <p>{} {} · created {} · {} ({} cores) · schema <code>{}</code></p><p id=\"status\">images loading…</p>",
        escape(&report.tool.name),
        escape(&report.tool.version),
        escape(&report.created),
        escape(&report.machine.cpu),
        report.machine.cores,
        escape(&report.schema)
    );
}

/// Selects that keep the runs of one scene, camera, light, technique or resolution.
fn filters_section(h: &mut String, report: &Report) {
    h.push_str("<div id=\"filters\">Show: ");
    let field = |name: &str, values: Vec<String>| {
        let mut unique: Vec<String> = Vec::new();
        for v in values {
            if !unique.contains(&v) {
                unique.push(v);
            }
        }
        let options: String =
            unique.iter().map(|v| format!("<option value=\"{0}\">{0}</option>", escape(v))).collect();
        format!(
            "<label>{name} <select name=\"{name}\"><option value=\"\">all</option>{options}</select></label>"
        )
    };
    let runs = &report.runs;
    h.push_str(&field("scene", runs.iter().map(|r| r.scene.clone()).collect()));
    h.push_str(&field("camera", runs.iter().map(|r| r.camera.clone()).collect()));
    h.push_str(&field("light", runs.iter().map(|r| r.light.clone()).collect()));
    h.push_str(&field("technique", runs.iter().map(|r| r.technique.clone()).collect()));
    h.push_str(&field("resolution", runs.iter().map(|r| r.resolution.to_string()).collect()));
    h.push_str("<span id=\"shown\"></span></div>");
}

/// The viewer, filled by a run's "view" button or a chart's point: run A's shadows and error map
/// against B, the reference or a run pinned as B; flipped (buttons or keys 1–3) or slid over each
/// other with a divider (4), with zoom, and the pixel under the cursor read from both.
fn viewer_section(h: &mut String) {
    h.push_str(
        "<section id=\"viewer\" hidden><h2>Viewer</h2><p id=\"view-caption\"></p><div id=\"view-modes\">\
         <button data-mode=\"reference\">1 reference</button><button data-mode=\"technique\">2 technique</button>\
         <button data-mode=\"error\">3 error map</button><button data-mode=\"slide\">4 slide</button> \
         <input id=\"view-slider\" type=\"range\" min=\"0\" max=\"100\" value=\"50\" hidden \
         aria-label=\"technique shown left of\"> <label>zoom <select id=\"view-zoom\"><option value=\"1\">1×</option>\
         <option value=\"2\">2×</option><option value=\"4\">4×</option><option value=\"8\">8×</option></select></label> \
         <button id=\"view-pin\"></button></div><p>",
    );
    h.push_str(&super::palette::colour_code_legend());
    h.push_str(
        " over the scene. In slide mode run A's shadows are left of the divider, B's (the reference, or \
         a run pinned as B) right; the zoom and the scrolling are the same for both.</p>\
         <p id=\"view-pixel\"></p><div id=\"view-stage\"><img id=\"view-base\" alt=\"\">\
         <img id=\"view-over\" alt=\"\" hidden><div id=\"view-divider\" hidden></div></div></section>",
    );
}

fn scenes_table(h: &mut String, report: &Report) {
    h.push_str("<h2>Scenes</h2><table><thead><tr><th class=\"l\">scene</th><th class=\"l\">file</th><th>triangles</th><th>degenerate dropped</th><th>BVH build ms</th></tr></thead><tbody>");
    for s in &report.scenes {
        let _ = write!(
            h,
            "<tr><td class=\"l\">{}</td><td class=\"l\">{}</td><td>{}</td><td>{}</td><td>{:.1}</td></tr>",
            escape(&s.name),
            escape(&s.file),
            s.triangles,
            s.dropped_degenerate,
            s.bvh_build_ms
        );
    }
    h.push_str("</tbody></table>");
}

/// The columns of the runs table: name, and whether it reads left-aligned.
const RUN_COLUMNS: [(&str, bool); 18] = [
    ("view", true),
    ("technique", true),
    ("res.", false),
    ("format", true),
    ("evaluated", false),
    ("false shadow", false),
    ("false lit", false),
    ("uncertain", false),
    ("aliasing", false),
    ("seam", false),
    ("acne", false),
    ("leak", false),
    ("bleed", false),
    ("error %", false),
    ("prepare ms", false),
    ("shade ms", false),
    ("ns/pixel", false),
    ("", true),
];

/// The runs table: its header here, its rows as data that page.js draws a page at a time, so
/// that a report of ten thousand runs stays a light page.
fn runs_table(h: &mut String, report: &Report, images: &super::answer_section::RunImages) {
    h.push_str("<h2>Runs</h2><p>Counts of pixels; click a header to sort. False shadow: lit in truth, shadowed by the technique; false lit: the reverse. Aliasing: within one shadow-map texel of a true shadow boundary. Uncertain: pixels the reference cannot decide beyond doubt, left out of every score (not among the evaluated). Error %: false shadow and false lit over the evaluated pixels.</p>");
    h.push_str("<div class=\"table-wrap\"><table id=\"runs\"><thead><tr>");
    for (name, left) in RUN_COLUMNS {
        let _ = write!(h, "<th{}>{name}</th>", if left { " class=\"l\"" } else { "" });
    }
    h.push_str(
        "</tr></thead><tbody></tbody></table></div><div id=\"pager\"><button id=\"page-prev\">‹ previous</button> \
         <span id=\"page-at\"></span> <button id=\"page-next\">next ›</button></div>",
    );
    let rows: Vec<serde_json::Value> =
        report.runs.iter().enumerate().map(|(i, r)| run_row(r, images(i))).collect();
    // `<` written as its JSON escape, so that no text in the data can close the script element.
    let data = serde_json::Value::Array(rows).to_string().replace('<', "\\u003c");
    let _ = write!(h, "<script type=\"application/json\" id=\"runs-data\">{data}</script>");
}

/// One run as page.js draws it: the values it filters on, each cell's text (with the exact
/// value it sorts by, where the text rounds), and its figures for the viewer.
fn run_row(r: &shadowtruth::record::RunRecord, images: Option<(&str, &str, &str)>) -> serde_json::Value {
    let c = &r.counts;
    let figures = images.map(|(reference, technique, error)| {
        serde_json::json!({
            "reference": reference,
            "technique": technique,
            "error": error,
            "caption": format!(
                "{}/{}/{}: {} at {}² {}",
                r.scene, r.camera, r.light, r.label, r.resolution, r.depth_format
            ),
        })
    });
    serde_json::json!({
        "scene": r.scene, "camera": r.camera, "light": r.light, "technique": r.technique,
        "resolution": r.resolution.to_string(),
        "cells": [
            format!("{}/{}/{}", r.scene, r.camera, r.light), r.label, r.resolution, r.depth_format,
            c.evaluated, c.false_shadow, c.false_lit, c.uncertain, c.aliasing, c.seam, c.acne, c.leak,
            c.light_bleeding, [format!("{:.3}", 100.0 * r.rates.error), r.rates.error],
            format!("{:.2}", r.timings.prepare), format!("{:.2}", r.timings.shade),
            [format!("{:.1}", r.timings.ns_per_pixel), r.timings.ns_per_pixel],
        ],
        "figures": figures,
    })
}

fn figures_section(h: &mut String, assets: &PageAssets) {
    if assets.figures.is_empty() {
        return;
    }
    open_list(h, "Figures", assets.figures.len());
    if assets.figures.len() <= OPEN_UP_TO {
        h.push_str("<div class=\"figs\">");
        for (path, caption) in &assets.figures {
            let _ = write!(
                h,
                "<figure><a href=\"{0}\"><img loading=\"lazy\" src=\"{0}\" alt=\"{1}\"></a>\
                 <figcaption>{1}</figcaption></figure>",
                escape(path),
                escape(caption)
            );
        }
        h.push_str("</div>");
    } else {
        h.push_str("<ul class=\"plot-links\">");
        for (path, caption) in &assets.figures {
            let _ = write!(h, "<li><a href=\"{0}\">{1}</a></li>", escape(path), escape(caption));
        }
        h.push_str("</ul>");
    }
    h.push_str("</details>");
}

/// Lists longer than this start folded and are links, not images, so that a report of many
/// views stays a light page.
const OPEN_UP_TO: usize = 60;

/// A section's heading, as the summary of a list that is open when short.
fn open_list(h: &mut String, title: &str, items: usize) {
    let open = if items <= OPEN_UP_TO { " open" } else { "" };
    let _ =
        write!(h, "<details{open}><summary><h2 style=\"display:inline\">{title}</h2> ({items})</summary>");
}

fn plots_section(h: &mut String, assets: &PageAssets) {
    if assets.plots.is_empty() {
        return;
    }
    open_list(h, "Plots", assets.plots.len());
    if assets.plots.len() <= OPEN_UP_TO {
        h.push_str("<div class=\"plots\">");
        for stem in &assets.plots {
            let _ = write!(
                h,
                "<p><a href=\"plots/{0}.svg\"><img loading=\"lazy\" src=\"plots/{0}.png\" alt=\"{0}\"></a></p>",
                escape(stem)
            );
        }
        h.push_str("</div>");
    } else {
        // Many plots: their names, each a link, rather than a thousand images to lay out.
        h.push_str("<ul class=\"plot-links\">");
        for stem in &assets.plots {
            let _ = write!(
                h,
                "<li><a href=\"plots/{0}.png\">{0}</a> (<a href=\"plots/{0}.svg\">svg</a>)</li>",
                escape(stem)
            );
        }
        h.push_str("</ul>");
    }
    h.push_str("</details>");
}

/// `index.html`, linking the figures already written under `figures/` and the report's plots.
pub struct PageExport;

impl crate::export::Export for PageExport {
    fn write(&self, dir: &Path, report: &Report) -> std::io::Result<()> {
        write_page(dir, report)
    }
}

/// Writes the report folder's `index.html` from what the folder holds.
pub fn write_page(dir: &Path, report: &Report) -> std::io::Result<()> {
    let assets = page_assets(dir, report);
    shadowtruth::atomic_file::write_atomic(&dir.join("index.html"), index_html(report, &assets).as_bytes())
}

/// What the page of the report folder `dir` shows: its grids and reference figures, each run's
/// figures where both were written, and the report's plots.
fn page_assets(dir: &Path, report: &Report) -> PageAssets {
    let mut figures: Vec<(String, String)> = std::fs::read_dir(dir.join("figures"))
        .map(|entries| {
            entries
                .filter_map(|e| e.ok())
                .filter_map(|e| e.file_name().into_string().ok())
                .filter(|n| n.ends_with(".grid.png") || n.ends_with(".reference.png"))
                .map(|n| (format!("figures/{n}"), n.trim_end_matches(".png").replace('.', " ")))
                .collect()
        })
        .unwrap_or_default();
    figures.sort();
    let run_figures = report
        .runs
        .iter()
        .map(|r| {
            let stem = run_stem(r);
            let (t, e) = (format!("figures/{stem}.technique.png"), format!("figures/{stem}.error.png"));
            (dir.join(&t).is_file() && dir.join(&e).is_file()).then_some((t, e))
        })
        .collect();
    let run_references = report
        .runs
        .iter()
        .map(|r| {
            let path =
                format!("figures/{}.reference.png", view_stem(ViewKey::new(&r.scene, &r.camera, &r.light)));
            dir.join(&path).is_file().then_some(path)
        })
        .collect();
    let plots = charts(report).into_iter().map(|c| c.stem).collect();
    PageAssets {
        plots,
        figures,
        run_figures,
        run_references,
        tune: tune_assets(dir),
        path: path_assets(dir, report),
    }
}

/// tune.json and the tune plots of a `tune` folder, when it is one.
fn tune_assets(dir: &Path) -> Option<(serde_json::Value, Vec<String>)> {
    let tune: serde_json::Value = serde_json::from_slice(&std::fs::read(dir.join("tune.json")).ok()?).ok()?;
    let mut plots: Vec<String> = std::fs::read_dir(dir.join("plots"))
        .ok()?
        .filter_map(|e| e.ok()?.file_name().into_string().ok())
        .filter(|n| n.starts_with("tune_") && n.ends_with(".png"))
        .map(|n| n.trim_end_matches(".png").to_string())
        .collect();
    plots.sort();
    Some((tune, plots))
}

/// What `tune` found: per scene and for the suite, the best setting, its objective and the
/// safe range of each parameter; then the plots of the search.
fn tune_section(h: &mut String, tune: &serde_json::Value, plots: &[String]) {
    h.push_str("<h2>Tuning</h2><p>The setting that minimises the objective, and the range of each parameter over \
                which the objective stays within 10 % of it (<a href=\"tune.json\">tune.json</a>).</p><table id=\"tune\">\
                <thead><tr><th class=\"l\">scene</th><th class=\"l\">best setting</th><th>objective %</th>\
                <th class=\"l\">safe range</th></tr></thead><tbody>");
    let suite = std::iter::once(("suite", &tune["suite"]));
    let scenes =
        tune["per_scene"].as_array().into_iter().flatten().map(|s| (s["scene"].as_str().unwrap_or("?"), s));
    for (scene, t) in suite.chain(scenes) {
        let ranges: Vec<String> = t["safe_range"]
            .as_object()
            .into_iter()
            .flatten()
            .map(|(name, r)| format!("{name} {} … {}", r["lo"], r["hi"]))
            .collect();
        let objective = 100.0 * t["best"]["objective"].as_f64().unwrap_or(f64::NAN);
        let (objective, ranges) = if t["best"]["feasible"] == false {
            (
                "—".to_string(),
                format!("no setting meets the bound (least false shadow {:.4} %)", objective - 100.0),
            )
        } else {
            (format!("{objective:.4}"), ranges.join(", "))
        };
        let _ = write!(
            h,
            "<tr><td class=\"l\">{}</td><td class=\"l\">{}</td><td>{objective}</td><td class=\"l\">{}</td></tr>",
            escape(scene),
            escape(t["best"]["label"].as_str().unwrap_or("")),
            escape(&ranges)
        );
    }
    h.push_str("</tbody></table><div class=\"plots\">");
    for stem in plots {
        let _ = write!(
            h,
            "<p><a href=\"plots/{0}.svg\"><img src=\"plots/{0}.png\" alt=\"{0}\"></a></p>",
            escape(stem)
        );
    }
    h.push_str("</div>");
}
