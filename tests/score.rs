//! Scoring another renderer's buffers (`shadowtruth score`, plan technique `external`,
//! `score_imported`): a buffer written from our own technique scores exactly that technique's
//! counts in every file format, a buffer from a moved camera shows surface mismatches, and the
//! command, the plan entry and the built-in technique agree record for record.

mod common;

use exr::prelude::*;
use shadowtruth::import::DEFAULT_DEPTH_TOLERANCE;
use shadowtruth::metrics::Counts;
use shadowtruth::scene::Scene;
use shadowtruth::trace::PixelClass;
use shadowtruth::{
    DepthFormat, GBuffer, HardReference, ReadOptions, SceneBvh, TechniqueSpec, read_depth, read_visibility,
    score_imported, trace_hard_reference,
};
use std::path::{Path, PathBuf};
use std::process::Command;

const WIDTH: u32 = 160;
const HEIGHT: u32 = 120;
/// A low resolution, so that the technique below is wrong on both sides.
const RESOLUTION: u32 = 96;
const TECHNIQUE: &str = r#"{"technique": "constant", "bias_depth": 0.0004}"#;

/// A box on a plane under the sun, the camera at `eye`; written into `dir` as scene.json.
fn scene_file(dir: &Path, eye: [f32; 3]) -> PathBuf {
    let json = serde_json::json!({
        "format": "shadowtruth/scene/v1", "name": "boxes",
        "objects": [
            { "name": "ground", "shape": { "type": "plane", "size": [8, 8] } },
            { "name": "box", "shape": { "type": "box", "size": [1, 1, 1] }, "closed": true,
              "transform": { "translate": [0, 0.5, 0], "rotate_deg": [0, 30, 0] } }
        ],
        "cameras": [{ "name": "c", "position": eye, "look_at": [0, 0.4, 0], "fov_y_deg": 45,
                      "width": WIDTH, "height": HEIGHT }],
        "lights": [{ "name": "sun", "type": "directional", "direction": [-0.4, -1, -0.3] }]
    });
    let path = dir.join("scene.json");
    std::fs::write(&path, serde_json::to_string_pretty(&json).unwrap()).unwrap();
    path
}

const EYE: [f32; 3] = [-4.0, 3.0, 4.0];

struct View {
    scene: Scene,
    gbuffer: GBuffer,
    reference: HardReference,
}

fn trace(path: &Path) -> View {
    let scene = shadowtruth::load_scene(path).unwrap();
    let bvh = SceneBvh::build(&scene);
    let gbuffer = GBuffer::trace(&scene, &bvh, &scene.cameras[0], &scene.lights[0]);
    let reference = trace_hard_reference(&scene, &bvh, &gbuffer, &scene.lights[0]);
    View { scene, gbuffer, reference }
}

/// Our technique's visibility of every camera pixel (row 0 at the top), and its counts.
fn technique_output(v: &View) -> (Vec<f32>, Counts) {
    let spec: TechniqueSpec = serde_json::from_str(TECHNIQUE).unwrap();
    let view = shadowtruth::light_view(&v.scene, &v.scene.lights[0], RESOLUTION).unwrap();
    let layers = shadowtruth::rasterize_layers(&v.scene, &view, DepthFormat::F32, &spec).unwrap();
    let visibility = shadowtruth::shade_technique(&spec, &v.scene, &v.gbuffer, &view, &layers).unwrap();
    let counts = shadowtruth::score_visibility(&v.gbuffer, &v.reference, &visibility).unwrap();
    assert!(counts.false_shadow > 0 && counts.false_lit > 0, "the technique errs both ways: {counts:?}");
    (visibility, counts)
}

fn write_exr(path: &Path, name: &str, values: &[f32], half: bool) {
    let samples = if half {
        FlatSamples::F16(values.iter().map(|&v| f16::from_f32(v)).collect())
    } else {
        FlatSamples::F32(values.to_vec())
    };
    let channel = AnyChannel::new(name, samples);
    let image = Image::from_layer(Layer::new(
        (WIDTH as usize, HEIGHT as usize),
        LayerAttributes::named("render"),
        Encoding::FAST_LOSSLESS,
        AnyChannels::sort(SmallVec::from_vec(vec![channel])),
    ));
    image.write().to_file(path).unwrap();
}

fn write_png16(path: &Path, values: &[f32]) {
    let file = std::io::BufWriter::new(std::fs::File::create(path).unwrap());
    let mut encoder = png::Encoder::new(file, WIDTH, HEIGHT);
    encoder.set_color(png::ColorType::Grayscale);
    encoder.set_depth(png::BitDepth::Sixteen);
    let bytes: Vec<u8> = values.iter().flat_map(|&v| ((v * 65535.0).round() as u16).to_be_bytes()).collect();
    encoder.write_header().unwrap().write_image_data(&bytes).unwrap();
}

fn flipped(values: &[f32]) -> Vec<f32> {
    values.chunks(WIDTH as usize).rev().flatten().copied().collect()
}

#[test]
fn our_own_output_scores_its_own_counts_in_every_format() {
    let dir = tempfile::tempdir().unwrap();
    let v = trace(&scene_file(dir.path(), EYE));
    let (visibility, counts) = technique_output(&v);
    let camera = &v.scene.cameras[0];
    let files = [("f32.exr", 0), ("f16.exr", 1), ("u16.png", 2), ("flipped.exr", 3)];
    for (name, kind) in files {
        let path = dir.path().join(name);
        match kind {
            0 => write_exr(&path, "V", &visibility, false),
            1 => write_exr(&path, "V", &visibility, true),
            2 => write_png16(&path, &visibility),
            _ => write_exr(&path, "V", &flipped(&visibility), false),
        }
        let options = ReadOptions { channel: None, flip_y: kind == 3 };
        let image = read_visibility(&path, &options).unwrap();
        assert_eq!(image.values, visibility, "{name}: the values read back");
        let imported =
            score_imported(&v.gbuffer, camera, &v.reference, &image, None, DEFAULT_DEPTH_TOLERANCE).unwrap();
        assert_eq!(imported, counts, "{name}");
        assert_eq!(imported.surface_mismatch, 0);
    }
}

/// The distance from `eye` to every pixel's surface, +inf for background.
fn camera_depth(v: &View, eye: [f32; 3]) -> Vec<f32> {
    let eye = glam::Vec3::from(eye).as_dvec3();
    (0..v.gbuffer.pixel_count())
        .map(|i| match v.gbuffer.class[i] {
            PixelClass::Background => f32::INFINITY,
            _ => (v.gbuffer.position[i].as_dvec3() - eye).length() as f32,
        })
        .collect()
}

/// The reference of a view as a renderer would write it: NaN where it drew background.
fn rendered_visibility(v: &View) -> Vec<f32> {
    (0..v.gbuffer.pixel_count())
        .map(|i| match v.gbuffer.class[i] {
            PixelClass::Background => f32::NAN,
            _ => v.reference.lit[i] as f32,
        })
        .collect()
}

#[test]
fn a_moved_camera_gives_surface_mismatches_and_the_same_camera_none() {
    let dir = tempfile::tempdir().unwrap();
    let original = trace(&scene_file(dir.path(), EYE));
    let camera = &original.scene.cameras[0];
    let score = |render: &View, eye: [f32; 3], half: bool| {
        let (vis_path, depth_path) = (dir.path().join("v.exr"), dir.path().join("d.exr"));
        write_exr(&vis_path, "V", &rendered_visibility(render), false);
        write_exr(&depth_path, "Z", &camera_depth(render, eye), half);
        let options = ReadOptions::default();
        let visibility = read_visibility(&vis_path, &options).unwrap();
        let depth = read_depth(&depth_path, &options).unwrap();
        let with_depth = score_imported(
            &original.gbuffer,
            camera,
            &original.reference,
            &visibility,
            Some(&depth),
            DEFAULT_DEPTH_TOLERANCE,
        )
        .unwrap();
        let without = score_imported(
            &original.gbuffer,
            camera,
            &original.reference,
            &visibility,
            None,
            DEFAULT_DEPTH_TOLERANCE,
        )
        .unwrap();
        (with_depth, without)
    };
    // The same camera, its depth exact or rounded to f16: every pixel matches, nothing is wrong.
    for half in [false, true] {
        let (with_depth, without) = score(&original, EYE, half);
        assert_eq!((with_depth.surface_mismatch, with_depth.false_shadow, with_depth.false_lit), (0, 0, 0));
        assert_eq!(with_depth, without);
    }
    // Moved back by 30 cm: the plane's far edge moves (background where the reference sees a
    // surface), and the distances change by more than the tolerance.
    let moved_eye = [EYE[0], EYE[1], EYE[2] + 0.3];
    let dir2 = tempfile::tempdir().unwrap();
    let moved = trace(&scene_file(dir2.path(), moved_eye));
    let (with_depth, without) = score(&moved, moved_eye, false);
    assert!(without.surface_mismatch > 0, "background drawn over the reference's surface: {without:?}");
    assert!(with_depth.surface_mismatch > without.surface_mismatch, "{with_depth:?} vs {without:?}");
    for c in [with_depth, without] {
        assert_eq!(c.evaluated, original.gbuffer.evaluated.len() as u64);
        assert!(c.false_shadow + c.false_lit <= c.scored());
        let rates = c.rates();
        assert_eq!(rates.error, (c.false_shadow + c.false_lit) as f64 / c.scored().max(1) as f64);
    }
}

fn shadowtruth(args: &[&str]) -> std::process::Output {
    let out = Command::new(env!("CARGO_BIN_EXE_shadowtruth")).args(args).output().unwrap();
    assert!(out.status.success(), "{args:?}: {}", String::from_utf8_lossy(&out.stderr));
    out
}

/// `shadowtruth run --plan PLAN -o OUT`, without cache or figures.
fn run_plan(plan: &Path, out: &Path) {
    let (plan, out) = (plan.to_str().unwrap(), out.to_str().unwrap());
    shadowtruth(&["run", "--plan", plan, "--no-cache", "--no-figures", "--quiet", "-o", out]);
}

fn runs(report_dir: &Path) -> Vec<serde_json::Value> {
    let text = std::fs::read_to_string(report_dir.join("report.json")).unwrap();
    let report: serde_json::Value = serde_json::from_str(&text).unwrap();
    report["runs"].as_array().unwrap().clone()
}

/// A record without what differs between two runs of the same thing: timings, memory.
fn comparable(run: &serde_json::Value) -> serde_json::Value {
    let mut run = run.clone();
    let map = run.as_object_mut().unwrap();
    map.remove("timings");
    map.remove("layer_memory_bytes");
    run
}

#[test]
fn score_the_plan_entry_and_the_built_in_technique_agree() {
    let dir = tempfile::tempdir().unwrap();
    let scene_path = scene_file(dir.path(), EYE);
    let v = trace(&scene_path);
    let (visibility, _) = technique_output(&v);
    std::fs::create_dir(dir.path().join("renders")).unwrap();
    write_png16(&dir.path().join("renders/boxes.c.sun.png"), &visibility);
    let (s, render) = (scene_path.to_str().unwrap(), dir.path().join("renders/boxes.c.sun.png"));
    let res = RESOLUTION.to_string();
    let out = dir.path().join("score");
    shadowtruth(&[
        "score",
        s,
        "--camera",
        "c",
        "--light",
        "sun",
        "--visibility",
        render.to_str().unwrap(),
        "--name",
        "ours",
        "--resolution",
        &res,
        "--no-cache",
        "--quiet",
        "-o",
        out.to_str().unwrap(),
    ]);
    let scored = runs(&out);
    assert_eq!(scored.len(), 1);
    assert!(out.join("report.csv").is_file() && out.join("index.html").is_file());
    assert!(std::fs::read_dir(out.join("figures")).unwrap().count() > 0, "figures written");

    let plan = serde_json::json!({
        "format": "shadowtruth/plan/v1",
        "scenes": ["scene.json"],
        "techniques": [
            serde_json::from_str::<serde_json::Value>(TECHNIQUE).unwrap(),
            { "technique": "external", "name": "ours", "visibility": "renders/{scene}.{camera}.{light}.png" }
        ],
        "resolutions": [RESOLUTION],
        "repeats": 1
    });
    std::fs::write(dir.path().join("plan.json"), plan.to_string()).unwrap();
    let out_plan = dir.path().join("plan_out");
    let plan_path = dir.path().join("plan.json");
    run_plan(&plan_path, &out_plan);
    let planned = runs(&out_plan);
    assert_eq!(planned.len(), 2);
    // The plan's file, relative to the plan, names the same file as the command's.
    let from_plan = Path::new(planned[1]["parameters"]["visibility"].as_str().unwrap());
    assert_eq!(std::fs::canonicalize(from_plan).unwrap(), std::fs::canonicalize(&render).unwrap());
    let mut expected = comparable(&scored[0]);
    expected["parameters"]["visibility"] = planned[1]["parameters"]["visibility"].clone();
    expected["label"] = planned[1]["label"].clone();
    assert_eq!(comparable(&planned[1]), expected, "the plan's external run is score's");
    // The built-in technique at the same resolution: the same counts, attribution included.
    let (built_in, external) = (&planned[0]["counts"], &planned[1]["counts"]);
    assert_eq!(built_in, external);
    assert!(external["aliasing"].as_u64().unwrap() > 0, "{external}");
    assert!(external.get("surface_mismatch").is_none(), "written only when not 0");
}

#[test]
fn a_shadow_map_written_by_depth_map_scores_the_technique_on_our_own_map() {
    let dir = tempfile::tempdir().unwrap();
    let scene_path = scene_file(dir.path(), EYE);
    let s = scene_path.to_str().unwrap();
    let (map, res) = (dir.path().join("map.exr"), RESOLUTION.to_string());
    shadowtruth(&["depth-map", s, "--light", "sun", "--resolution", &res, "-o", map.to_str().unwrap()]);
    let out = dir.path().join("score");
    shadowtruth(&[
        "score",
        s,
        "--camera",
        "c",
        "--light",
        "sun",
        "--shadow-map",
        map.to_str().unwrap(),
        "--technique",
        TECHNIQUE,
        "--no-cache",
        "--no-figures",
        "--quiet",
        "-o",
        out.to_str().unwrap(),
    ]);
    let out_run = dir.path().join("run");
    let plan = serde_json::json!({
        "format": "shadowtruth/plan/v1", "scenes": ["scene.json"],
        "techniques": [serde_json::from_str::<serde_json::Value>(TECHNIQUE).unwrap()],
        "resolutions": [RESOLUTION], "repeats": 1
    });
    let plan_path = dir.path().join("plan.json");
    std::fs::write(&plan_path, plan.to_string()).unwrap();
    run_plan(&plan_path, &out_run);
    let (imported, ours) = (runs(&out), runs(&out_run));
    assert_eq!((imported.len(), ours.len()), (1, 1));
    assert_eq!(
        comparable(&imported[0]),
        comparable(&ours[0]),
        "the same record, counts and attribution included"
    );
    let counts: Counts = serde_json::from_value(imported[0]["counts"].clone()).unwrap();
    assert!(counts.false_shadow > 0 && counts.false_lit > 0 && counts.aliasing > 0, "{counts:?}");
}
