//! Names are data, never paths: whatever a scene calls itself, its cameras and its lights
//! (`..`, `/`, an absolute path, a name that filters to nothing, 300 characters, NUL, a newline),
//! every file a run writes stays inside its report and cache folders and the run writes its
//! page; views whose names join to the same text (`a__b` + `c`, `a` + `b__c`) keep their own
//! cached references; and a cached mask edited into another valid PNG is traced again.

#[path = "../../shadowtruth/tests/common/mod.rs"]
mod common;

use serde_json::{Value, json};
use shadowtruth::scene::ViewKey;
use shadowtruth::trace::ReferenceCache;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

/// Runs `shadowtruth` in `dir` and checks that it succeeded.
fn shadowtruth(args: &[&str], dir: &Path) {
    let out = Command::new(env!("CARGO_BIN_EXE_shadowtruth")).args(args).current_dir(dir).output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "shadowtruth {args:?} failed: {stderr}");
}

/// A plane and a box seen by `cameras` (all at one place) under directional `lights` of 3°
/// (name, direction), as the scene `name`.
fn scene_json(name: &str, cameras: &[&str], lights: &[(&str, [f64; 3])]) -> Value {
    let cameras: Vec<Value> = cameras
        .iter()
        .map(|c| {
            json!({ "name": c, "position": [-6, 4, 6.5], "look_at": [0, 0.7, 0], "fov_y_deg": 45,
                    "width": 48, "height": 36 })
        })
        .collect();
    let lights: Vec<Value> = lights
        .iter()
        .map(|(l, direction)| {
            json!({ "name": l, "type": "directional", "direction": direction, "angular_diameter_deg": 3.0 })
        })
        .collect();
    json!({
        "format": "shadowtruth/scene/v1", "name": name,
        "objects": [
            { "name": "ground", "shape": { "type": "plane", "size": [10, 10] } },
            { "name": "box", "shape": { "type": "box", "size": [1, 1, 1] }, "closed": true,
              "transform": { "rotate_deg": [0, 30, 0], "translate": [0, 1.5, 0] } }
        ],
        "cameras": cameras,
        "lights": lights
    })
}

fn write_json(path: &Path, value: &Value) {
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    std::fs::write(path, value.to_string()).unwrap();
}

/// A plan of `techniques` at 16² and 32², one repeat, 2×2 soft grids.
fn write_plan(path: &Path, techniques: Value) {
    let plan = json!({
        "format": "shadowtruth/plan/v1", "techniques": techniques, "resolutions": [16, 32],
        "repeats": 1, "coverage_grid": 2, "area_light_grid": 2
    });
    write_json(path, &plan);
}

/// Every file under `dir` (links not followed), as paths relative to it.
fn files_under(dir: &Path) -> Vec<PathBuf> {
    let mut found = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for entry in std::fs::read_dir(&d).unwrap() {
            let entry = entry.unwrap();
            if entry.file_type().unwrap().is_dir() {
                stack.push(entry.path());
            } else {
                found.push(entry.path().strip_prefix(dir).unwrap().to_path_buf());
            }
        }
    }
    found.sort();
    found
}

/// (camera, light, label, resolution) → (false shadow, false lit) of every run of a report.
fn counts(report_dir: &Path) -> BTreeMap<(String, String, String, u64), (u64, u64)> {
    let report: Value =
        serde_json::from_slice(&std::fs::read(report_dir.join("report.json")).unwrap()).unwrap();
    let text = |r: &Value, field: &str| r[field].as_str().unwrap().to_string();
    report["runs"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| {
            let key =
                (text(r, "camera"), text(r, "light"), text(r, "label"), r["resolution"].as_u64().unwrap());
            let c = &r["counts"];
            (key, (c["false_shadow"].as_u64().unwrap(), c["false_lit"].as_u64().unwrap()))
        })
        .collect()
}

/// The hard masks a cache folder holds.
fn cached_masks(cache: &Path) -> Vec<PathBuf> {
    files_under(cache).into_iter().filter(|p| p.extension().is_some_and(|x| x == "png")).collect()
}

#[test]
fn hostile_names_write_only_inside_the_report_and_cache_folders() {
    let root = tempfile::tempdir().unwrap();
    // Deep enough that `../../x` from any folder the run writes still lands inside `root`,
    // where the walk below sees it.
    let work = root.path().join("a/b/c");
    let absolute = root.path().join("escaped").to_string_lossy().into_owned();
    let long = "n".repeat(300);
    // `)` and `//` filter to nothing; an empty name is refused (tests/bad_inputs).
    let names = [
        "../../x",
        "/tmp-abs",
        &absolute,
        ")",
        "//",
        &long,
        "nul\0byte",
        "new\nline",
        "..\\..\\back",
        "Ébène",
    ];
    let tmp_abs_existed = Path::new("/tmp-abs").exists();
    let mut scenes = Vec::new();
    for (i, name) in names.iter().enumerate() {
        let file = format!("scenes/s{i}.json");
        let lights = [(*name, [-0.3, -1.0, -0.45]), ("other", [0.2, -1.0, -0.1])];
        write_json(&work.join(&file), &scene_json(name, &[name], &lights));
        scenes.push(file);
    }
    write_plan(
        &work.join("plan.json"),
        json!([{ "technique": "constant", "bias_depth": [0.001, 0.01] }, { "technique": "pcf" }, { "technique": "pcss" }]),
    );
    let scene_args: Vec<&str> = scenes.iter().map(String::as_str).collect();
    let common = ["--plan", "plan.json", "--references", "refs", "--quiet"];
    shadowtruth(&[&["run"], &scene_args[..], &common, &["-o", "out"]].concat(), &work);
    // Read back from the cache, resumed, and over frames (movies, flicker maps, frame plots).
    shadowtruth(&[&["run"], &scene_args[..], &common, &["-o", "out", "--resume"]].concat(), &work);
    shadowtruth(&[&["run"], &scene_args[..], &common, &["-o", "frames", "--frames", "2"]].concat(), &work);

    for out in ["out", "frames"] {
        assert!(work.join(out).join("index.html").is_file(), "{out}: no page");
    }
    let allowed = ["a/b/c/scenes/", "a/b/c/plan.json", "a/b/c/out/", "a/b/c/frames/", "a/b/c/refs/"];
    let files = files_under(root.path());
    let stray: Vec<&PathBuf> =
        files.iter().filter(|f| !allowed.iter().any(|a| f.to_string_lossy().starts_with(a))).collect();
    assert!(stray.is_empty(), "written outside the tool's folders: {stray:?}");
    assert!(tmp_abs_existed || !Path::new("/tmp-abs").exists(), "a run wrote /tmp-abs");
    // Every view's hard mask is in the cache (one per view), named by the tool, not the scene.
    assert_eq!(cached_masks(&work.join("refs")).len(), 2 * names.len());
    for file in &files {
        let name = file.file_name().unwrap().to_string_lossy();
        assert!(name.len() <= 200, "{name}: a file name that long is the names' length, unbounded");
    }
}

#[test]
fn views_whose_names_join_alike_keep_their_own_references() {
    let dir = tempfile::tempdir().unwrap();
    // One camera twice, two slightly different suns: the pixel classes (what the cache checks a
    // mask against) agree, the shadows do not.
    let lights = [("c", [-0.3, -1.0, -0.45]), ("b__c", [-0.45, -1.0, -0.3])];
    write_json(&dir.path().join("s.json"), &scene_json("s", &["a__b", "a"], &lights));
    write_plan(&dir.path().join("plan.json"), json!([{ "technique": "constant", "bias_depth": 0.0005 }]));
    let run = |out: &str, cache: &[&str]| {
        shadowtruth(
            &[&["run", "s.json", "--plan", "plan.json", "--quiet", "-o", out], cache].concat(),
            dir.path(),
        )
    };
    run("truth", &["--no-cache"]);
    run("first", &["--references", "refs"]);
    run("second", &["--references", "refs"]);
    let truth = counts(&dir.path().join("truth"));
    let of_view = |camera: &str, light: &str| -> Vec<(u64, u64)> {
        truth.iter().filter(|(k, _)| k.0 == camera && k.1 == light).map(|(_, v)| *v).collect()
    };
    assert_ne!(
        of_view("a__b", "c"),
        of_view("a", "b__c"),
        "the two views must differ for the test to mean anything"
    );
    assert_eq!(counts(&dir.path().join("first")), truth);
    assert_eq!(counts(&dir.path().join("second")), truth, "the second run read another view's reference");
    assert_eq!(cached_masks(&dir.path().join("refs")).len(), 4, "one mask per view");
}

#[test]
fn names_holding_the_key_separators_keep_their_own_cache_entries() {
    let dir = tempfile::tempdir().unwrap();
    let cache = ReferenceCache::new(dir.path());
    // Pairs whose names join alike under `/` (manifest keys) or `__` (file names).
    let views = [
        (ViewKey::new("s", "a/b", "c"), [0u8, 255]),
        (ViewKey::new("s", "a", "b/c"), [255, 0]),
        (ViewKey::new("s", "a__b", "c"), [0, 0]),
        (ViewKey::new("s", "a", "b__c"), [255, 255]),
        (ViewKey::new("s%2Fa", "b", "c"), [128, 0]),
        (ViewKey::new("s/a", "b", "c"), [0, 128]),
    ];
    for (i, (view, codes)) in views.iter().enumerate() {
        cache.store(*view, &format!("digest {i}"), 2, 1, codes).unwrap();
    }
    for (i, (view, codes)) in views.iter().enumerate() {
        let mask =
            cache.load(*view, &format!("digest {i}")).unwrap_or_else(|| panic!("{view:?}: entry lost"));
        assert_eq!(mask.codes, codes, "{view:?} reads another view's mask");
    }
    assert_eq!(cached_masks(dir.path()).len(), views.len());
}

#[test]
fn a_cached_mask_edited_into_another_valid_png_is_traced_again() {
    let dir = tempfile::tempdir().unwrap();
    write_json(&dir.path().join("s.json"), &scene_json("s", &["main"], &[("sun", [-0.3, -1.0, -0.45])]));
    write_plan(&dir.path().join("plan.json"), json!([{ "technique": "none" }, { "technique": "pcf" }]));
    let run = |out: &str| {
        let args = ["run", "s.json", "--plan", "plan.json", "--quiet", "--references", "refs", "-o", out];
        shadowtruth(&args, dir.path())
    };
    run("first");
    let masks = cached_masks(&dir.path().join("refs"));
    assert_eq!(masks.len(), 1);
    let path = dir.path().join("refs").join(&masks[0]);
    // Every lit pixel shadowed: the same size, the same pixel classes, another truth.
    let mut img = image::open(&path).unwrap().into_luma8();
    let lit = img.pixels().filter(|p| p.0[0] == 255).count();
    assert!(lit > 100, "{lit} lit pixels");
    img.pixels_mut().filter(|p| p.0[0] == 255).for_each(|p| p.0[0] = 0);
    img.save_with_format(&path, image::ImageFormat::Png).unwrap();
    run("second");
    assert_eq!(counts(&dir.path().join("second")), counts(&dir.path().join("first")));
    // Traced again and stored again: the mask is the truth once more.
    assert_eq!(image::open(&path).unwrap().into_luma8().pixels().filter(|p| p.0[0] == 255).count(), lit);
}
