//! Scoring another renderer's buffers (`shadowtruth score`, plan technique `external`,
//! `score_imported`): a buffer written from our own technique scores exactly that technique's
//! counts in every file format, a buffer from a moved camera shows surface mismatches, and the
//! command, the plan entry and the built-in technique agree record for record.

#[path = "../../shadowtruth/tests/common/mod.rs"]
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
    let gbuffer = GBuffer::trace(&bvh, &scene.cameras[0], &scene.lights[0]);
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

/// A box on a plane under two suns and a spot light, written into `dir` as lights.json.
fn scene_of_three_lights(dir: &Path) -> PathBuf {
    let json = serde_json::json!({
        "format": "shadowtruth/scene/v1", "name": "lights",
        "objects": [
            { "name": "ground", "shape": { "type": "plane", "size": [8, 8] } },
            { "name": "box", "shape": { "type": "box", "size": [1, 1, 1] }, "closed": true,
              "transform": { "translate": [0, 0.5, 0] } }
        ],
        "cameras": [{ "name": "c", "position": EYE, "look_at": [0, 0.4, 0], "fov_y_deg": 45,
                      "width": 40, "height": 30 }],
        "lights": [
            { "name": "sun", "type": "directional", "direction": [-0.4, -1, -0.3] },
            { "name": "sun2", "type": "directional", "direction": [0.5, -1, 0.2] },
            { "name": "lamp", "type": "spot", "position": [1, 5, 1], "direction": [-0.2, -1, 0.1],
              "cone_deg": 70, "near": 0.5, "far": 20 }
        ]
    });
    let path = dir.join("lights.json");
    std::fs::write(&path, serde_json::to_string_pretty(&json).unwrap()).unwrap();
    path
}

/// The sidecar of `light`'s shadow map as view-export writes it: D3D's `clip_from_world` (the
/// project's own clip space), with `near` and `far`, into `dir/<light>.json`.
fn sidecar_from_view_export(scene: &Path, light: &str, dir: &Path) -> PathBuf {
    let out = dir.join(format!("export_{light}"));
    let (s, o) = (scene.to_str().unwrap(), out.to_str().unwrap());
    shadowtruth(&["view-export", s, "--light", light, "--resolution", "16", "--quiet", "-o", o]);
    let view: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("view.json")).unwrap()).unwrap();
    let map = &view["light"]["shadow_map"];
    let cells = map["d3d"]["clip_from_world_row_major"].as_array().unwrap();
    let rows: Vec<&[serde_json::Value]> = cells.chunks(4).collect();
    let sidecar = serde_json::json!({ "clip_from_world": rows, "near": map["near"], "far": map["far"] });
    let path = dir.join(format!("{light}.json"));
    std::fs::write(&path, sidecar.to_string()).unwrap();
    path
}

/// `score --shadow-map` of a 16² map with `sidecar` for `light`.
fn score_map(scene: &Path, map: &Path, sidecar: &Path, light: &str, out: &Path) -> std::process::Output {
    let args = [
        "score",
        scene.to_str().unwrap(),
        "--camera",
        "c",
        "--light",
        light,
        "--shadow-map",
        map.to_str().unwrap(),
        "--clip-from-world",
        sidecar.to_str().unwrap(),
        "--technique",
        TECHNIQUE,
        "--no-cache",
        "--no-figures",
        "--quiet",
        "-o",
        out.to_str().unwrap(),
    ];
    Command::new(env!("CARGO_BIN_EXE_shadowtruth")).args(args).output().unwrap()
}

#[test]
fn a_view_exports_own_sidecar_passes_the_light_check_and_another_lights_fails() {
    let dir = tempfile::tempdir().unwrap();
    let scene = scene_of_three_lights(dir.path());
    let map = dir.path().join("map.exr");
    let empty = vec![1.0f32; 16 * 16];
    let channel = AnyChannel::new("Z", FlatSamples::F32(empty));
    let layer = Layer::new(
        (16, 16),
        LayerAttributes::named("depth"),
        Encoding::FAST_LOSSLESS,
        AnyChannels::sort(SmallVec::from_vec(vec![channel])),
    );
    Image::from_layer(layer).write().to_file(&map).unwrap();
    let sidecars: Vec<(&str, PathBuf)> = ["sun", "sun2", "lamp"]
        .into_iter()
        .map(|l| (l, sidecar_from_view_export(&scene, l, dir.path())))
        .collect();
    for (light, sidecar) in &sidecars {
        let out = score_map(&scene, &map, sidecar, light, &dir.path().join(format!("own_{light}")));
        assert!(out.status.success(), "{light}: {}", String::from_utf8_lossy(&out.stderr));
    }
    let refused = |sidecar: &Path, light: &str| {
        let out = score_map(&scene, &map, sidecar, light, &dir.path().join("other"));
        assert_eq!(out.status.code(), Some(2), "{light}");
        let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
        assert!(stderr.contains(&format!("{}: clip_from_world: ", sidecar.display())), "{stderr}");
        stderr
    };
    // The angle between the two suns' directions, computed here.
    let (a, b) =
        (glam::DVec3::new(-0.4, -1.0, -0.3).normalize(), glam::DVec3::new(0.5, -1.0, 0.2).normalize());
    let degrees = a.dot(b).acos().to_degrees();
    let stderr = refused(&sidecars[1].1, "sun");
    let shown: f64 = stderr.split("(row 2) is ").nth(1).unwrap().split('°').next().unwrap().parse().unwrap();
    assert!((shown - degrees).abs() < 1e-3, "{shown}° against {degrees}°: {stderr}");
    assert!(refused(&sidecars[2].1, "sun").contains("a perspective projection"));
    assert!(refused(&sidecars[0].1, "lamp").contains("an orthographic projection"));
}

/// Counts the bytes allocated on each thread, and the most held at once since the last reset.
mod allocations {
    use std::alloc::{GlobalAlloc, Layout, System};
    use std::cell::Cell;

    thread_local! {
        static HELD: Cell<isize> = const { Cell::new(0) };
        static PEAK: Cell<isize> = const { Cell::new(0) };
    }

    pub struct Counting;

    unsafe impl GlobalAlloc for Counting {
        unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
            let _ = HELD.try_with(|held| {
                held.set(held.get() + layout.size() as isize);
                let _ = PEAK.try_with(|peak| peak.set(peak.get().max(held.get())));
            });
            unsafe { System.alloc(layout) }
        }

        unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
            let _ = HELD.try_with(|held| held.set(held.get() - layout.size() as isize));
            unsafe { System.dealloc(ptr, layout) }
        }
    }

    /// The most bytes `f` held at once on this thread, beyond what was held before it.
    pub fn peak_of<T>(f: impl FnOnce() -> T) -> (T, usize) {
        let before = HELD.with(Cell::get);
        PEAK.with(|peak| peak.set(before));
        let out = f();
        (out, (PEAK.with(Cell::get) - before).max(0) as usize)
    }
}

#[global_allocator]
static COUNTING: allocations::Counting = allocations::Counting;

#[test]
fn a_wrong_size_image_is_refused_before_its_pixels_are_allocated() {
    use shadowtruth::import::{ExpectedSize, ImageSource, read_visibility_from};
    let dir = tempfile::tempdir().unwrap();
    // 64 megapixels of zeros: 64 MB as grey PNG, 128 MB as f16 EXR, a few hundred KB on disk.
    let (side, view) = (8192u32, ExpectedSize::View { width: WIDTH, height: HEIGHT });
    let png_path = dir.path().join("big.png");
    let mut encoder = png::Encoder::new(std::fs::File::create(&png_path).unwrap(), side, side);
    encoder.set_color(png::ColorType::Grayscale);
    encoder.write_header().unwrap().write_image_data(&vec![0u8; (side * side) as usize]).unwrap();
    let exr_path = dir.path().join("big.exr");
    let zeros = FlatSamples::F16(vec![f16::ZERO; (side * side) as usize]);
    let channel = AnyChannel::new("V", zeros);
    let encoding = Encoding { compression: Compression::ZIP16, ..Encoding::FAST_LOSSLESS };
    let layer = Layer::new(
        (side as usize, side as usize),
        LayerAttributes::named("v"),
        encoding,
        AnyChannels::sort(SmallVec::from_vec(vec![channel])),
    );
    Image::from_layer(layer).write().to_file(&exr_path).unwrap();
    for path in [&png_path, &exr_path] {
        let (result, peak) = allocations::peak_of(|| {
            read_visibility_from(ImageSource::File(path), &ReadOptions::default(), view)
        });
        let e = result.unwrap_err().to_string();
        assert!(
            e.contains(&format!("declares {side}×{side}, expected the camera's {WIDTH}×{HEIGHT}")),
            "{e}"
        );
        assert!(peak < 1 << 20, "{}: {peak} bytes held before the size was refused", path.display());
    }
    // The right size is read, holding little more than its final image (4 bytes a pixel).
    let (image, peak) = allocations::peak_of(|| {
        read_visibility_from(ImageSource::File(&png_path), &ReadOptions::default(), ExpectedSize::ANY_CAMERA)
    });
    let pixels = image.unwrap().values.len();
    assert_eq!(pixels, (side * side) as usize);
    assert!((pixels * 4..pixels * 4 + (20 << 20)).contains(&peak), "{peak} bytes held for {pixels} pixels");
}

#[test]
fn an_upside_down_buffer_scores_as_written_with_a_hint_to_flip_it() {
    let dir = tempfile::tempdir().unwrap();
    let scene = scene_file(dir.path(), EYE);
    let v = trace(&scene);
    // The exact answer, background marked: upright it has no wrong pixel.
    let visibility: Vec<f32> = (v.reference.lit.iter().zip(&v.gbuffer.class))
        .map(|(&lit, &class)| if class == PixelClass::Background { f32::NAN } else { lit as f32 })
        .collect();
    let (upright, upside_down) = (dir.path().join("upright.exr"), dir.path().join("upside_down.exr"));
    write_exr(&upright, "V", &visibility, false);
    write_exr(&upside_down, "V", &flipped(&visibility), false);
    let score = |file: &Path, extra: &[&str]| {
        let out_dir =
            dir.path().join(format!("out-{}-{}", file.file_stem().unwrap().to_str().unwrap(), extra.len()));
        let mut args = vec!["score", scene.to_str().unwrap(), "--camera", "c", "--light", "sun"];
        args.extend([
            "--visibility",
            file.to_str().unwrap(),
            "--resolution",
            "96",
            "--no-cache",
            "--no-figures",
        ]);
        args.extend(extra);
        args.extend(["-o", out_dir.to_str().unwrap()]);
        let out = shadowtruth(&args);
        (String::from_utf8_lossy(&out.stderr).into_owned(), runs(&out_dir)[0]["counts"].clone())
    };
    let (hint, as_written) = score(&upside_down, &[]);
    assert!(hint.contains("hint: read with --flip-y, 0.000% of the pixels are wrong"), "{hint} {as_written}");
    assert!(as_written["false_shadow"].as_u64().unwrap() > 100, "scored as written: {as_written}");
    let (quiet, flipped_back) = score(&upside_down, &["--flip-y"]);
    assert!(!quiet.contains("hint"), "{quiet}");
    assert_eq!(
        (flipped_back["false_shadow"].as_u64(), flipped_back["false_lit"].as_u64()),
        (Some(0), Some(0))
    );
    let (none, _) = score(&upright, &[]);
    assert!(!none.contains("hint"), "an upright buffer gets no hint: {none}");
}
