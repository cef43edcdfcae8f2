//! `index.html`: one offline page per report folder — the runs table (sortable), runs over a path
//! (`path_section.rs`), on cascaded shadow maps (`cascades_section.rs`) and under point lights
//! (`point_map_section.rs`), the plots, the
//! figures, the settings and the tool version. Only relative links; no network.

use super::cascades_section::cascades_section;
use super::figures::{run_stem, view_stem};
use super::path_section::{PathAssets, path_assets, path_section};
use super::plots::charts;
use super::point_map_section::point_map_section;
use super::summary::{GroupSummary, per_scene, summaries};
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
#view-modes button[aria-pressed=true]{font-weight:bold;background:#dde}button.view{font-size:12px}";

/// Sorting, filters, the viewer and the images-loaded status line (read by tests).
const SCRIPT: &str = include_str!("page.js");

pub fn index_html(report: &Report, assets: &PageAssets) -> String {
    let mut h = String::new();
    page_header(&mut h, report);
    if let Some((tune, plots)) = &assets.tune {
        tune_section(&mut h, tune, plots);
    }
    summary_section(&mut h, report);
    scenes_table(&mut h, report);
    viewer_section(&mut h);
    filters_section(&mut h, report);
    runs_table(&mut h, report, assets);
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

/// Per scene, at each resolution: the best setting of each technique family with its error
/// and cost, and whether it is in the Pareto set (no setting both cheaper and better).
fn summary_section(h: &mut String, report: &Report) {
    let groups = summaries(report, per_scene);
    if groups.is_empty() {
        return;
    }
    h.push_str("<h2>Summary</h2><p>Per scene, summed over its views: the best setting of each technique at each \
                resolution, its error and shading cost; ✓ marks the Pareto set (no other setting is both cheaper \
                and better).</p>");
    for g in &groups {
        scene_summary(h, g);
    }
}

fn scene_summary(h: &mut String, g: &GroupSummary) {
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

/// The viewer, filled by a run's "view" button: the reference, the run's shadows and its error
/// map, flipped (buttons or keys 1–3) or slid over each other (4), with zoom.
fn viewer_section(h: &mut String) {
    h.push_str(
        "<section id=\"viewer\" hidden><h2>Viewer</h2><p id=\"view-caption\"></p><div id=\"view-modes\">\
         <button data-mode=\"reference\">1 reference</button><button data-mode=\"technique\">2 technique</button>\
         <button data-mode=\"error\">3 error map</button><button data-mode=\"slide\">4 slide</button> \
         <input id=\"view-slider\" type=\"range\" min=\"0\" max=\"100\" value=\"50\" hidden \
         aria-label=\"technique shown left of\"> <label>zoom <select id=\"view-zoom\"><option value=\"1\">1×</option>\
         <option value=\"2\">2×</option><option value=\"4\">4×</option><option value=\"8\">8×</option></select></label>\
         </div><p>",
    );
    h.push_str(&colour_code_legend());
    h.push_str(
        " over the scene; in slide mode the technique's shadows are left of the slider, the \
         reference's right.</p><div id=\"view-stage\">\
         <img id=\"view-base\" alt=\"\"><img id=\"view-over\" alt=\"\" hidden></div></section>",
    );
}

/// The error map's colours in words and swatches, from the one colour code (palette.rs).
fn colour_code_legend() -> String {
    use super::palette::{FALSE_LIT, FALSE_SHADOW, UNCERTAIN};
    let swatch = |[r, g, b]: [u8; 3], what: &str| {
        format!("<span style=\"color:#{r:02X}{g:02X}{b:02X}\">&#9632;</span> {what}")
    };
    format!(
        "The error map shows {}, {} and {} (pixels the reference cannot decide)",
        swatch(FALSE_SHADOW, "false shadow"),
        swatch(FALSE_LIT, "false lit"),
        swatch(UNCERTAIN, "uncertain")
    )
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

fn runs_table(h: &mut String, report: &Report, assets: &PageAssets) {
    h.push_str("<h2>Runs</h2><p>Rates are fractions of the evaluated pixels; click a header to sort. False shadow: lit in truth, shadowed by the technique; false lit: the reverse. Aliasing: within one shadow-map texel of a true shadow boundary. Uncertain: pixels the reference cannot decide beyond doubt, left out of every score (not among the evaluated).</p>");
    h.push_str("<table id=\"runs\"><thead><tr>");
    for (name, left) in [
        ("scene", true),
        ("camera", true),
        ("light", true),
        ("technique", true),
        ("resolution", false),
        ("format", true),
        ("evaluated", false),
        ("false shadow", false),
        ("false lit", false),
        ("uncertain", false),
        ("aliasing", false),
        ("seam", false),
        ("acne", false),
        ("leak", false),
        ("bleeding", false),
        ("error %", false),
        ("prepare ms", false),
        ("shade ms", false),
        ("ns/pixel", false),
        ("figures", true),
    ] {
        let _ = write!(h, "<th{}>{name}</th>", if left { " class=\"l\"" } else { "" });
    }
    h.push_str("</tr></thead><tbody>");
    for (i, r) in report.runs.iter().enumerate() {
        let c = &r.counts;
        let figs = run_figure_links(r, assets.run_figures.get(i), assets.run_references.get(i));
        let _ = write!(
            h,
            "<tr data-scene=\"{}\" data-camera=\"{}\" data-light=\"{}\" data-technique=\"{}\" data-resolution=\"{}\">\
             <td class=\"l\">{}</td><td class=\"l\">{}</td><td class=\"l\">{}</td><td class=\"l\">{}</td>\
             <td>{}</td><td class=\"l\">{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td>\
             <td data-v=\"{}\">{:.3}</td><td>{:.2}</td><td>{:.2}</td><td>{:.1}</td><td class=\"l\">{figs}</td></tr>",
            escape(&r.scene),
            escape(&r.camera),
            escape(&r.light),
            escape(&r.technique),
            r.resolution,
            escape(&r.scene),
            escape(&r.camera),
            escape(&r.light),
            escape(&r.label),
            r.resolution,
            escape(&r.depth_format),
            c.evaluated,
            c.false_shadow,
            c.false_lit,
            c.uncertain,
            c.aliasing,
            c.seam,
            c.acne,
            c.leak,
            c.light_bleeding,
            r.rates.error,
            100.0 * r.rates.error,
            r.timings.prepare,
            r.timings.shade,
            r.timings.ns_per_pixel
        );
    }
    h.push_str("</tbody></table>");
}

/// A run's figure links, and its viewer button when the reference figure is there too.
fn run_figure_links(
    r: &shadowtruth::record::RunRecord,
    figures: Option<&Option<(String, String)>>,
    reference: Option<&Option<String>>,
) -> String {
    let Some(Some((t, e))) = figures else { return String::new() };
    let links = format!("<a href=\"{}\">visibility</a> <a href=\"{}\">errors</a>", escape(t), escape(e));
    match reference {
        Some(Some(reference)) => format!(
            "<button class=\"view\" data-reference=\"{}\" data-technique=\"{}\" data-error=\"{}\" \
             data-caption=\"{}\">view</button> {links}",
            escape(reference),
            escape(t),
            escape(e),
            escape(&format!(
                "{}/{}/{}: {} at {}² {}",
                r.scene, r.camera, r.light, r.label, r.resolution, r.depth_format
            ))
        ),
        _ => links,
    }
}

fn figures_section(h: &mut String, assets: &PageAssets) {
    if !assets.figures.is_empty() {
        h.push_str("<h2>Figures</h2><div class=\"figs\">");
        for (path, caption) in &assets.figures {
            let _ = write!(
                h,
                "<figure><a href=\"{0}\"><img src=\"{0}\" alt=\"{1}\"></a><figcaption>{1}</figcaption></figure>",
                escape(path),
                escape(caption)
            );
        }
        h.push_str("</div>");
    }
}

fn plots_section(h: &mut String, assets: &PageAssets) {
    if !assets.plots.is_empty() {
        h.push_str("<h2>Plots</h2><div class=\"plots\">");
        for stem in &assets.plots {
            let _ = write!(
                h,
                "<p><a href=\"plots/{0}.svg\"><img src=\"plots/{0}.png\" alt=\"{0}\"></a></p>",
                escape(stem)
            );
        }
        h.push_str("</div>");
    }
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
