//! A view whose reference cannot decide one pixel: the pixel is left out of every score, counted
//! in `counts.uncertain` and shown in every report form (report.json, report.csv, index.html, the
//! error map), and the view's pixels still add up.

use super::common::repo;

use crate::drawing::figures::{FALSE_LIT_INDEX, UNCERTAIN_INDEX, ViewCanvas, error_map};
use crate::outputs::write_report_outputs;
use crate::plan::{Plan, execute};
use crate::sinks::ReportWriter;
use shadowtruth::metrics::Counts;
use shadowtruth::record::Report;
use shadowtruth::scene::{Scene, ViewKey, load_scene};
use shadowtruth::technique::{NoneParams, TechniqueSpec};
use shadowtruth::trace::{
    GBuffer, HardReference, MaskCode, PixelClass, ReferenceCache, SceneBvh, reference_digest,
    trace_hard_reference,
};
use std::path::Path;

/// plane_box's view and its reference, which decides every pixel; and a shadowed evaluated
/// pixel (one that `none`, which draws everything lit, gets wrong).
fn plane_box() -> (Scene, GBuffer, HardReference, u32) {
    let scene = load_scene(&repo().join("scenes/plane_box.json")).unwrap();
    let bvh = SceneBvh::build(&scene);
    let (camera, light) = (&scene.cameras[0], &scene.lights[0]);
    let g = GBuffer::trace(&bvh, camera, light);
    let hard = trace_hard_reference(&scene, &bvh, &g, light);
    assert!(hard.uncertain.is_empty() && g.count(PixelClass::Uncertain) == 0, "plane_box is decided");
    let shadowed = *g.evaluated.iter().find(|&&i| hard.lit[i as usize] == 0).expect("a shadowed pixel");
    (scene, g, hard, shadowed)
}

/// plane_box under `none` at 256², its references read from `cache` when given; the report
/// with its outputs written to `dir`.
fn run_none(dir: &Path, cache: Option<&ReferenceCache>) -> Report {
    let plan = Plan {
        repeats: 1,
        figures: false,
        ..Plan::new(
            vec![repo().join("scenes/plane_box.json")],
            vec![TechniqueSpec::None(NoneParams {})],
            vec![256],
        )
    };
    let mut writer = ReportWriter::new(dir);
    execute(&plan, cache, &mut [&mut writer]).unwrap();
    let report = writer.into_report();
    write_report_outputs(dir, &report).unwrap();
    report
}

#[test]
fn an_uncertain_pixel_is_counted_and_scored_neither_way_in_every_report_form() {
    let (scene, g, hard, doubtful) = plane_box();
    let (camera, light) = (&scene.cameras[0], &scene.lights[0]);
    // The cache holds the reference with that pixel marked uncertain, as the tracer would have
    // written it had it been unable to decide it.
    let cache_dir = tempfile::tempdir().unwrap();
    let cache = ReferenceCache::new(cache_dir.path());
    let mut codes = hard.mask_codes(&g);
    codes[doubtful as usize] = MaskCode::Uncertain as u8;
    let view = ViewKey::from_view(&scene, camera, light);
    cache.store(view, &reference_digest(&scene, camera, light), g.width, g.height, &codes).unwrap();

    let (plain_dir, flagged_dir) = (tempfile::tempdir().unwrap(), tempfile::tempdir().unwrap());
    let plain = run_none(plain_dir.path(), None).runs[0].counts;
    let report = run_none(flagged_dir.path(), Some(&cache));
    let flagged = report.runs[0].counts;
    assert_eq!((plain.uncertain, flagged.uncertain), (0, 1));
    // Left out of the evaluated pixels, and of the false lits it would have been one of.
    assert_eq!(flagged.evaluated, plain.evaluated - 1);
    assert_eq!((flagged.false_shadow, flagged.false_lit), (plain.false_shadow, plain.false_lit - 1));
    assert_eq!(
        flagged.aliasing + flagged.seam + flagged.acne + flagged.leak + flagged.light_bleeding,
        flagged.false_shadow + flagged.false_lit
    );
    // The pixels the reference was asked about are the same, and the classes add up.
    assert_eq!(flagged.evaluated + flagged.uncertain, plain.evaluated);
    let classes = |c: &Counts| c.background + c.facing_away + c.outside_light + c.evaluated + c.uncertain;
    assert_eq!((classes(&plain), classes(&flagged)), (plain.pixels, flagged.pixels));
    assert_eq!(report.runs[0].rates, flagged.rates());

    // report.json carries it.
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(flagged_dir.path().join("report.json")).unwrap()).unwrap();
    assert_eq!(json["runs"][0]["counts"]["uncertain"], 1);
    // report.csv, in its own column.
    let mut csv = csv::Reader::from_path(flagged_dir.path().join("report.csv")).unwrap();
    let column = csv.headers().unwrap().iter().position(|h| h == "counts.uncertain").expect("a column");
    let row = csv.records().next().unwrap().unwrap();
    assert_eq!(&row[column], "1");
    // index.html: a column beside false lit, its cell in the same place in the row.
    let html = std::fs::read_to_string(flagged_dir.path().join("index.html")).unwrap();
    let table = &html[html.find("<table id=\"runs\">").expect("the runs table")..];
    let header = &table[table.find("<thead><tr>").unwrap() + 11..table.find("</thead>").unwrap()];
    let headers: Vec<&str> =
        header.split("<th").skip(1).map(|h| &h[h.find('>').unwrap() + 1..h.find("</th>").unwrap()]).collect();
    let at = headers.iter().position(|&h| h == "uncertain").expect("an uncertain column");
    assert_eq!(headers[at - 1], "false lit");
    // The rows are the page's data (page.js draws them): one cell per column but the last
    // (the figures').
    let open = "<script type=\"application/json\" id=\"runs-data\">";
    let data = &html[html.find(open).unwrap() + open.len()..];
    let rows: serde_json::Value = serde_json::from_str(&data[..data.find("</script>").unwrap()]).unwrap();
    let cells = rows[0]["cells"].as_array().unwrap();
    assert_eq!(cells.len() + 1, headers.len());
    assert_eq!((&cells[at], &cells[at - 1]), (&1.into(), &flagged.false_lit.into()));
}

#[test]
fn the_error_map_draws_uncertain_pixels_in_their_own_colour() {
    let (scene, mut g, hard, doubtful) = plane_box();
    let reference = HardReference { uncertain: vec![doubtful], ..hard };
    g.leave_out(&reference.uncertain);
    let canvas = ViewCanvas::new(&g, &reference, &scene.lights[0]);
    assert_eq!(canvas.uncertain(), 1);
    // `none`: every evaluated pixel lit, so every shadowed one is false lit.
    let all_lit = vec![1.0; g.evaluated.len()];
    let map = error_map(&g, &reference, &all_lit, &canvas);
    let area = &map.pixels[..(g.width * g.height) as usize];
    assert_eq!(area[doubtful as usize], UNCERTAIN_INDEX);
    assert_eq!(area.iter().filter(|&&p| p == UNCERTAIN_INDEX).count(), 1);
    let shadowed = g.evaluated.iter().filter(|&&i| reference.lit[i as usize] == 0).count();
    assert_eq!(area.iter().filter(|&&p| p == FALSE_LIT_INDEX).count(), shadowed);
    // The legend strip below has a swatch of the colour.
    assert!(map.pixels[area.len()..].contains(&UNCERTAIN_INDEX), "no legend entry");
}
