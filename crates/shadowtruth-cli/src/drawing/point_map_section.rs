//! The page's "Point lights" section (`html.rs`): for each run under a point light, a small table
//! of its map's faces (a cube's six, or two paraboloids) — the evaluated pixels each shaded and
//! their error, in all and within 3 texels of the face's edge — collapsed under the run's name.

use super::cascades_section::counts_cells;
use crate::escape::escape_html as escape;
use shadowtruth::record::{PointMapRecord, Report, RunRecord};
use std::fmt::Write as _;

/// The section, when the report has runs under point lights.
pub fn point_map_section(h: &mut String, report: &Report) {
    let runs: Vec<(&RunRecord, &PointMapRecord)> =
        report.runs.iter().filter_map(|r| Some((r, r.point_map.as_ref()?))).collect();
    if runs.is_empty() {
        return;
    }
    h.push_str(
        "<h2>Point lights</h2><p>Runs under point lights: per face of the light's map (a cube's six faces, or \
         two paraboloids), the evaluated pixels it shaded and their error, in all and within 3 texels of the \
         face's edge (a paraboloid's rim), where a filter reaches past the seam.</p>",
    );
    for (run, map) in runs {
        run_faces(h, run, map);
    }
}

/// One run's faces, collapsed under its name.
fn run_faces(h: &mut String, run: &RunRecord, map: &PointMapRecord) {
    let guard = match map.layout.as_str() {
        "cube" => format!(", guard band {} texels", map.guard_texels),
        _ => String::new(),
    };
    let _ = write!(
        h,
        "<details><summary>{}/{}/{}: {} at {}² ({}) — {}{guard}, faces of {}²</summary>\
         <table class=\"cascades\"><thead><tr><th>face</th><th>evaluated</th><th>error %</th>\
         <th>near the seam</th><th>error % near the seam</th></tr></thead><tbody>",
        escape(&run.scene),
        escape(&run.camera),
        escape(&run.light),
        escape(&run.label),
        run.resolution,
        escape(&run.depth_format),
        escape(&map.layout),
        map.face_texels,
    );
    for face in &map.faces {
        let _ = write!(
            h,
            "<tr><td>{}</td>{}{}</tr>",
            escape(&face.face),
            counts_cells(&face.counts),
            counts_cells(&face.near_seam)
        );
    }
    h.push_str("</tbody></table></details>");
}

#[cfg(test)]
mod tests {
    use super::*;
    use shadowtruth::metrics::Counts;
    use shadowtruth::record::{CascadeCounts, PointFaceRecord};

    #[test]
    fn a_table_per_point_light_run_with_each_face() {
        let mut report = Report::new();
        let counts = Counts { pixels: 100, evaluated: 100, ..Counts::default() };
        let mut run = crate::gate::test_run("room", "none", serde_json::json!({}), "none", counts);
        let face = |name: &str, evaluated, false_lit| PointFaceRecord {
            face: name.into(),
            near_seam: CascadeCounts { evaluated: 10, false_shadow: 1, false_lit: 0 },
            counts: CascadeCounts { evaluated, false_shadow: 0, false_lit },
        };
        run.point_map = Some(PointMapRecord {
            layout: "cube".into(),
            guard_texels: 8,
            face_texels: 528,
            faces: vec![face("+x", 200, 2), face("-y", 0, 0)],
        });
        report.runs.push(run);
        let mut h = String::new();
        point_map_section(&mut h, &report);
        assert!(h.contains("cube, guard band 8 texels, faces of 528²"), "{h}");
        assert!(h.contains("<td>+x</td><td>200</td><td>1.000</td><td>10</td><td>10.000</td>"), "{h}");
        // A face that shaded nothing has no error, not a division by zero.
        assert!(h.contains("<td>-y</td><td>0</td><td>0.000</td>"), "{h}");
        let mut empty = String::new();
        point_map_section(&mut empty, &Report::new());
        assert!(empty.is_empty());
    }
}
