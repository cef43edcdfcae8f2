//! Runs that share folders lose nothing and leave nothing behind: concurrent runs on one
//! reference cache keep every manifest entry, temporary files of killed writers are removed by
//! the next run (those of live writers kept), a run into an earlier report folder leaves none of
//! the earlier run's outputs, and soft EXRs are the same bytes on every run and thread count.

#[path = "../../shadowtruth/tests/common/mod.rs"]
mod common;

use shadowtruth::scene::ViewKey;
use shadowtruth::trace::{ReferenceCache, SoftKind, SoftReference};
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};

fn shadowtruth_command<S: AsRef<std::ffi::OsStr>>(args: &[S], dir: &Path) -> Command {
    let mut command = Command::new(env!("CARGO_BIN_EXE_shadowtruth"));
    command.args(args).current_dir(dir).stdout(Stdio::null()).stderr(Stdio::piped());
    command
}

/// Waits for a `shadowtruth` process and checks that it succeeded.
fn succeeded<S: AsRef<std::ffi::OsStr> + std::fmt::Debug>(child: Child, args: &[S]) {
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "shadowtruth {args:?} failed: {stderr}");
}

fn shadowtruth(args: &[&str], dir: &Path) {
    succeeded(shadowtruth_command(args, dir).spawn().unwrap(), args);
}

/// Writes `NAME` as a plan of `techniques` at `resolutions`, with one repeat and 2×2 soft grids.
fn write_plan(dir: &Path, name: &str, techniques: serde_json::Value, resolutions: &[u32]) {
    write_plan_for_lights(dir, name, techniques, resolutions, None);
}

/// As `write_plan`, for the lights named in `lights` only (`None`: all).
fn write_plan_for_lights(
    dir: &Path,
    name: &str,
    techniques: serde_json::Value,
    resolutions: &[u32],
    lights: Option<&[&str]>,
) {
    let mut plan = serde_json::json!({
        "format": "shadowtruth/plan/v1", "techniques": techniques, "resolutions": resolutions,
        "repeats": 1, "coverage_grid": 2, "area_light_grid": 2
    });
    if let Some(lights) = lights {
        plan["lights"] = serde_json::json!(lights);
    }
    std::fs::write(dir.join(name), plan.to_string()).unwrap();
}

fn manifest_entries(cache: &Path) -> BTreeSet<String> {
    let text = std::fs::read(cache.join("manifest.json")).unwrap();
    let manifest: serde_json::Value = serde_json::from_slice(&text).unwrap();
    manifest["entries"].as_object().unwrap().keys().cloned().collect()
}

#[test]
fn two_runs_sharing_a_cache_keep_every_manifest_entry() {
    let dir = tempfile::tempdir().unwrap();
    let lights = 12;
    for scene in ["a", "b"] {
        common::write_plane_box_scene(&dir.path().join(format!("{scene}.json")), scene, lights, (32, 24));
    }
    // Each view stores a hard mask and a coverage reference: 2 entries.
    write_plan(
        dir.path(),
        "plan.json",
        serde_json::json!([{ "technique": "none" }, { "technique": "pcf" }]),
        &[16],
    );
    let args = |scene: &str| -> Vec<String> {
        let (file, out) = (format!("{scene}.json"), format!("out-{scene}"));
        let args = ["run", &file, "--plan", "plan.json", "-o", &out, "--references", "refs"];
        [&args[..], &["--no-figures", "--quiet", "--threads", "1"]]
            .concat()
            .into_iter()
            .map(String::from)
            .collect()
    };
    let (a, b) = (args("a"), args("b"));
    let children = [&a, &b].map(|args| shadowtruth_command(args, dir.path()).spawn().unwrap());
    for (child, args) in children.into_iter().zip([&a, &b]) {
        succeeded(child, args);
    }
    let entries = manifest_entries(&dir.path().join("refs"));
    let expected: BTreeSet<String> = ["a", "b"]
        .iter()
        .flat_map(|s| {
            (0..lights).flat_map(move |i| [format!("{s}/c/l{i}"), format!("{s}/c/l{i}/coverage-2x2")])
        })
        .collect();
    let missing: Vec<_> = expected.difference(&entries).collect();
    assert!(missing.is_empty(), "{} of {} entries lost: {missing:?}", missing.len(), expected.len());
    assert_eq!(entries.len(), expected.len());
}

#[test]
fn threads_storing_into_one_cache_keep_every_manifest_entry() {
    let dir = tempfile::tempdir().unwrap();
    let (threads, per_thread) = (8, 12);
    std::thread::scope(|s| {
        for t in 0..threads {
            let cache = ReferenceCache::new(dir.path());
            s.spawn(move || {
                for i in 0..per_thread {
                    let light = format!("l{i}");
                    let scene = format!("s{t}");
                    cache.store(ViewKey::new(&scene, "c", &light), "digest", 2, 1, &[0, 255]).unwrap();
                }
            });
        }
    });
    let entries = manifest_entries(dir.path());
    assert_eq!(entries.len(), threads * per_thread, "entries lost");
    let cache = ReferenceCache::new(dir.path());
    for t in 0..threads {
        for i in 0..per_thread {
            let light = format!("l{i}");
            let scene = format!("s{t}");
            let mask = cache.load(ViewKey::new(&scene, "c", &light), "digest").expect("stored mask loads");
            assert_eq!(mask.codes, [0, 255]);
        }
    }
}

/// How this tool names its temporary files (`src/atomic_file.rs`, `TEMP_PREFIX`).
const TEMP_PREFIX: &str = ".shadowtruth-tmp.";

/// The cache's file name of the hard mask of the view `a`/`c`/`l0`.
fn mask_file() -> String {
    ReferenceCache::mask_path(ViewKey::new("a", "c", "l0"))
}

/// A temporary file named as this tool names them, of a writer that died (no lock held).
fn dead_temp_file(dir: &Path, target: &str) -> PathBuf {
    std::fs::create_dir_all(dir).unwrap();
    // PID 0 is never a user process's.
    let path = dir.join(format!("{TEMP_PREFIX}0.{target}.AbC123"));
    std::fs::write(&path, b"half a file").unwrap();
    path
}

/// A temporary file that a live writer (this process, through its own handle) holds locked.
fn live_temp_file(dir: &Path, target: &str) -> (PathBuf, std::fs::File) {
    std::fs::create_dir_all(dir).unwrap();
    let path = dir.join(format!("{TEMP_PREFIX}0.{target}.XyZ789"));
    let file = std::fs::File::create(&path).unwrap();
    fs4::FileExt::lock(&file).unwrap();
    (path, file)
}

#[test]
fn the_next_run_removes_stray_temp_files_and_keeps_live_ones() {
    let dir = tempfile::tempdir().unwrap();
    common::write_plane_box_scene(&dir.path().join("a.json"), "a", 1, (32, 24));
    write_plan(
        dir.path(),
        "plan.json",
        serde_json::json!([{ "technique": "none" }, { "technique": "pcf" }]),
        &[16],
    );
    let (out, refs) = (dir.path().join("out"), dir.path().join("refs"));
    let dead = [
        dead_temp_file(&out, "report.json"),
        dead_temp_file(&out.join("figures"), "a.c.l0.reference.png"),
        dead_temp_file(&out.join("plots"), "resolution.svg"),
        dead_temp_file(&refs, "manifest.json"),
        dead_temp_file(&refs, &mask_file()),
    ];
    let live = [
        live_temp_file(&out, "index.html"),
        live_temp_file(&out.join("figures"), "a.c.l0.reference.png"),
        live_temp_file(&refs, "manifest.json"),
        live_temp_file(&refs, &mask_file()),
    ];
    shadowtruth(
        &["run", "a.json", "--plan", "plan.json", "-o", "out", "--references", "refs", "--quiet"],
        dir.path(),
    );
    for path in &dead {
        assert!(!path.exists(), "{} was left", path.display());
    }
    for (path, _) in &live {
        assert!(path.exists(), "{} was removed while its writer held it", path.display());
    }
    assert!(out.join("report.json").exists() && refs.join("manifest.json").exists());
}

/// Every file under `dir`, relative to it, without the user's files listed in `user`.
fn files_under(dir: &Path, user: &[&str]) -> BTreeSet<String> {
    let mut found = BTreeSet::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for entry in std::fs::read_dir(&d).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
            } else {
                found.insert(path.strip_prefix(dir).unwrap().to_string_lossy().into_owned());
            }
        }
    }
    found.retain(|f| !user.contains(&f.as_str()));
    found
}

fn csv_rows(dir: &Path) -> usize {
    csv::Reader::from_path(dir.join("report.csv")).unwrap().records().count()
}

#[test]
fn a_second_run_into_a_folder_leaves_nothing_of_the_first() {
    let dir = tempfile::tempdir().unwrap();
    common::write_plane_box_scene(&dir.path().join("a.json"), "a", 2, (32, 24));
    let both = serde_json::json!([{ "technique": "none" }, { "technique": "constant", "bias_depth": [0.001, 0.01] }]);
    write_plan(dir.path(), "big.json", both, &[16, 32, 64]);
    // One light, one technique, two resolutions (plots need two).
    let none = serde_json::json!([{ "technique": "none" }]);
    write_plan_for_lights(dir.path(), "small.json", none, &[16, 32], Some(&["l0"]));
    let run = |plan: &str, out: &str| {
        let args = ["run", "a.json", "--plan", plan, "-o", out, "--references", "refs", "--quiet"];
        shadowtruth(&args, dir.path())
    };
    run("big.json", "out");
    let out = dir.path().join("out");
    assert_eq!(csv_rows(&out), 2 * 3 * 3);
    // What the user keeps in the folder stays; claims of an earlier `papers` run do not.
    let user = ["notes.txt", "figures/keep.md"];
    for file in user {
        std::fs::write(out.join(file), "mine").unwrap();
    }
    std::fs::write(out.join("claims.json"), "{}").unwrap();
    // A run rejected before its first run leaves the earlier report whole.
    std::fs::write(dir.path().join("bad.json"), "{ not a scene").unwrap();
    let rejected =
        shadowtruth_command(&["run", "bad.json", "-o", "out", "--quiet"], dir.path()).output().unwrap();
    assert_eq!(rejected.status.code(), Some(2));
    assert_eq!(csv_rows(&out), 2 * 3 * 3, "a rejected run changed the earlier report");

    run("small.json", "out");
    run("small.json", "fresh");
    let fresh = files_under(&dir.path().join("fresh"), &[]);
    assert!(fresh.iter().any(|f| f.starts_with("figures/")) && fresh.iter().any(|f| f.starts_with("plots/")));
    assert_eq!(files_under(&out, &user), fresh, "outputs of the first run are left");
    assert_eq!(csv_rows(&out), 2);
    for file in user {
        assert_eq!(std::fs::read_to_string(out.join(file)).unwrap(), "mine", "{file}");
    }
}

/// A soft reference of `width`×`height` pixels with values that vary from tile to tile, so that
/// tiles take different times to compress.
fn patterned_reference(width: u32, height: u32) -> SoftReference {
    let n = (width * height) as usize;
    let value = |i: usize| ((i * 2_654_435_761) % 1000) as f32 / 1000.0 * ((i / 4096) % 3) as f32 / 2.0;
    let visibility: Vec<f32> = (0..n).map(value).collect();
    let std_error = visibility.iter().map(|v| v * (1.0 - v) / 8.0).collect();
    SoftReference { width, height, visibility, std_error, samples: 16 }
}

#[test]
fn soft_exr_bytes_do_not_depend_on_the_run() {
    let reference = patterned_reference(1024, 768);
    let first = reference.to_exr().unwrap();
    for _ in 0..8 {
        assert!(reference.to_exr().unwrap() == first, "the EXR bytes changed between two writes");
    }
    assert!(SoftReference::from_exr(&first).unwrap() == reference);
}

fn read(path: PathBuf) -> Vec<u8> {
    std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

#[test]
fn soft_exrs_are_byte_identical_across_runs_and_thread_counts() {
    let dir = tempfile::tempdir().unwrap();
    common::write_plane_box_scene(&dir.path().join("a.json"), "a", 1, (512, 384));
    for kind in ["coverage", "area"] {
        let files: Vec<Vec<u8>> = [("1", "one"), ("2", "two"), ("2", "again")]
            .iter()
            .map(|(threads, name)| {
                let out = format!("{kind}.{name}.exr");
                let args = [
                    "reference",
                    "a.json",
                    "--kind",
                    kind,
                    "--samples",
                    "2",
                    "-o",
                    &out,
                    "--threads",
                    threads,
                ];
                shadowtruth(&args, dir.path());
                read(dir.path().join(out))
            })
            .collect();
        assert!(files[0] == files[1], "{kind}: the EXR differs between 1 and 2 threads");
        assert!(files[1] == files[2], "{kind}: the EXR differs between two runs");
    }
    // The soft references that runs store in the cache.
    let techniques = serde_json::json!([{ "technique": "pcf" }, { "technique": "pcss" }]);
    write_plan(dir.path(), "plan.json", techniques, &[64]);
    for threads in ["1", "2"] {
        let refs = format!("refs{threads}");
        let args = ["run", "a.json", "--plan", "plan.json", "-o", "out", "--references", &refs];
        shadowtruth(&[&args[..], &["--no-figures", "--quiet", "--threads", threads]].concat(), dir.path());
    }
    let view = ViewKey::new("a", "c", "l0");
    let files =
        [SoftKind::Coverage, SoftKind::AreaLight].map(|kind| ReferenceCache::soft_path(view, kind, 2));
    for file in &files {
        let (one, two) =
            (read(dir.path().join("refs1").join(file)), read(dir.path().join("refs2").join(file)));
        assert!(one == two, "{file}: the cached EXR differs between 1 and 2 threads");
    }
}

#[test]
fn depth_map_exr_bytes_do_not_depend_on_the_run() {
    let dir = tempfile::tempdir().unwrap();
    common::write_plane_box_scene(&dir.path().join("a.json"), "a", 1, (32, 24));
    let files: Vec<Vec<u8>> = ["one", "two", "three", "four"]
        .iter()
        .map(|name| {
            let out = format!("{name}.exr");
            shadowtruth(&["depth-map", "a.json", "--resolution", "1024", "-o", &out], dir.path());
            read(dir.path().join(out))
        })
        .collect();
    assert!(files.windows(2).all(|w| w[0] == w[1]), "the depth map's EXR bytes changed");
}
