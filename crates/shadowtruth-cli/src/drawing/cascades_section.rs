//! The page's "Cascades" section (`html.rs`): for each run on cascaded shadow maps, a small table
//! of its cascades — the view depths each serves, its texel in world units and in camera pixels
//! at its far split, and the error of the pixels it shaded — collapsed under the run's name, so
//! that many runs stay one line each.

use crate::escape::escape_html as escape;
use shadowtruth::record::Report;
use shadowtruth::record::{CascadeCounts, CascadesRecord, RunRecord};
use std::fmt::Write as _;

/// The section, when the report has runs on cascaded shadow maps.
pub fn cascades_section(h: &mut String, report: &Report) {
    let runs: Vec<(&RunRecord, &CascadesRecord)> =
        report.runs.iter().filter_map(|r| Some((r, r.cascades.as_ref()?))).collect();
    if runs.is_empty() {
        return;
    }
    h.push_str(
        "<h2>Cascades</h2><p>Runs on cascaded shadow maps: per cascade, the view depths it serves, the world \
         size of one texel and how many camera pixels it spans at the cascade's far end (more is blockier), and \
         the error of the evaluated pixels it shaded (the nearer cascade's, in a blend band). For a run over a \
         path, its last frame.</p>",
    );
    for (run, cascades) in runs {
        run_cascades(h, run, cascades);
    }
}

/// One run's cascades, collapsed under its name.
fn run_cascades(h: &mut String, run: &RunRecord, c: &CascadesRecord) {
    let _ = write!(
        h,
        "<details><summary>{}/{}/{}: {} at {}² ({}) — {} cascades, {} split, {} fit{}</summary>\
         <table class=\"cascades\"><thead><tr><th>cascade</th><th>near – far</th><th>texel (world)</th>\
         <th>texel pixels at far</th><th>evaluated</th><th>error %</th></tr></thead><tbody>",
        escape(&run.scene),
        escape(&run.camera),
        escape(&run.light),
        escape(&run.label),
        run.resolution,
        escape(&run.depth_format),
        c.cascades.len(),
        escape(&c.split),
        escape(&c.fit),
        if c.stabilize { ", stabilized" } else { "" }
    );
    for (k, cascade) in c.cascades.iter().enumerate() {
        let _ = write!(
            h,
            "<tr><td>{k}</td><td>{:.3} – {:.3}</td><td>{:.4}</td><td>{:.2}</td>{}</tr>",
            cascade.near,
            cascade.far,
            cascade.texel_world,
            cascade.texel_pixels_at_far,
            counts_cells(&cascade.counts)
        );
    }
    let _ = write!(
        h,
        "<tr><td class=\"l\" colspan=\"4\">beyond the last cascade (lit)</td>{}</tr></tbody></table></details>",
        counts_cells(&c.beyond)
    );
}

/// The evaluated pixels and their error in %, as two cells (the point-light section's too).
pub(super) fn counts_cells(c: &CascadeCounts) -> String {
    let wrong = c.false_shadow + c.false_lit;
    let error = if c.evaluated == 0 { 0.0 } else { 100.0 * wrong as f64 / c.evaluated as f64 };
    format!("<td>{}</td><td>{error:.3}</td>", c.evaluated)
}

#[cfg(test)]
mod tests {
    use super::*;
    use shadowtruth::metrics::Counts;
    use shadowtruth::record::CascadeRecord;

    #[test]
    fn a_table_per_cascaded_run() {
        let counts = Counts { pixels: 100, evaluated: 100, ..Counts::default() };
        let plain = crate::gate::test_run("s", "none", serde_json::json!({}), "none", counts);
        let mut cascaded = plain.clone();
        let cascade = |near: f64, far: f64, evaluated: u64, false_lit: u64| CascadeRecord {
            near,
            far,
            texel_world: 0.02,
            texel_pixels_at_far: 1.25,
            counts: CascadeCounts { evaluated, false_shadow: 0, false_lit },
        };
        cascaded.cascades = Some(CascadesRecord {
            split: "practical(λ=0.5)".into(),
            fit: "sphere".into(),
            stabilize: true,
            blend_band: 0.1,
            cascades: vec![cascade(0.1, 8.0, 60, 3), cascade(8.0, 40.0, 30, 0)],
            beyond: CascadeCounts { evaluated: 10, false_shadow: 0, false_lit: 0 },
        });
        let mut h = String::new();
        cascades_section(&mut h, &Report { runs: vec![plain.clone(), cascaded], ..Report::new() });
        assert_eq!(h.matches("<details>").count(), 1);
        assert!(h.contains("2 cascades, practical(λ=0.5) split, sphere fit, stabilized"), "{h}");
        assert!(h.contains(
            "<td>0</td><td>0.100 – 8.000</td><td>0.0200</td><td>1.25</td><td>60</td><td>5.000</td>"
        ));
        assert!(h.contains("beyond the last cascade (lit)</td><td>10</td><td>0.000</td>"), "{h}");
        let mut none = String::new();
        cascades_section(&mut none, &Report { runs: vec![plain], ..Report::new() });
        assert!(none.is_empty());
    }
}
