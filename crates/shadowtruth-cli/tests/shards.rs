//! `run --shard K/N`, `merge` and `run --resume` through the binary: a merged or resumed folder
//! equals the whole run's apart from timings (report.json without `created`, `timings` and
//! `bvh_build_ms`, report.csv without the timing columns, the figures byte for byte, the plots
//! other than cost against error, and index.html once timings are set equal), resuming keeps the
//! finished runs as they were, and bad shards, merges and resumes are refused naming the file.

#[path = "../../shadowtruth/tests/common/mod.rs"]
mod common;

use serde_json::Value;
use std::collections::BTreeMap;
use std::path::Path;
use std::process::{Command, Output};

fn shadowtruth(args: &[&str], dir: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_shadowtruth")).args(args).current_dir(dir).output().unwrap()
}

/// Runs `shadowtruth args` in `dir`, checks that it succeeded and returns its stdout.
fn succeed(args: &[&str], dir: &Path) -> String {
    let out = shadowtruth(args, dir);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "shadowtruth {args:?} failed: {stderr}");
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// Runs `shadowtruth args` in `dir`, checks that it exits 2 and returns its stderr.
fn refused(args: &[&str], dir: &Path) -> String {
    let out = shadowtruth(args, dir);
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(out.status.code(), Some(2), "shadowtruth {args:?}: {stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    stderr
}

/// Writes scenes `a` (three lights) and `b` (two): five views of a plane and a box, 32×24
/// pixels each, and `plan.json`: three techniques at 16² and 32² (30 runs, six per view).
fn write_suite(dir: &Path) {
    for (name, lights) in [("a", 3), ("b", 2)] {
        common::write_plane_box_scene(&dir.join(format!("scenes/{name}.json")), name, lights, (32, 24));
    }
    write_plan(dir, "plan.json", 0.01);
}

fn write_plan(dir: &Path, name: &str, bias_depth: f64) {
    let plan = serde_json::json!({
        "format": "shadowtruth/plan/v1",
        "techniques": [{ "technique": "none" }, { "technique": "constant", "bias_depth": [0.001, bias_depth] }],
        "resolutions": [16, 32], "depth_formats": ["f32"], "repeats": 1
    });
    std::fs::write(dir.join(name), plan.to_string()).unwrap();
}

const RUNS: usize = 30;

/// `run` of the suite into `out` with `extra` arguments.
fn run(dir: &Path, out: &str, extra: &[&str]) -> String {
    let args =
        [&["run", "scenes", "--plan", "plan.json", "--references", "refs", "-o", out][..], extra].concat();
    succeed(&args, dir)
}

fn report(dir: &Path) -> Value {
    serde_json::from_slice(&std::fs::read(dir.join("report.json")).unwrap()).unwrap()
}

/// report.json without what timing decides.
fn without_timings(mut report: Value) -> Value {
    report.as_object_mut().unwrap().remove("created");
    for scene in report["scenes"].as_array_mut().unwrap() {
        scene.as_object_mut().unwrap().remove("bvh_build_ms");
    }
    for run in report["runs"].as_array_mut().unwrap() {
        run.as_object_mut().unwrap().remove("timings");
    }
    report
}

/// report.csv without its timing columns.
fn csv_without_timings(dir: &Path) -> Vec<Vec<String>> {
    let text = std::fs::read_to_string(dir.join("report.csv")).unwrap();
    let rows: Vec<Vec<String>> = text.lines().map(|l| l.split(',').map(String::from).collect()).collect();
    let keep: Vec<usize> = (0..rows[0].len()).filter(|&i| !rows[0][i].starts_with("timings.")).collect();
    rows.iter().map(|row| keep.iter().map(|&i| row[i].clone()).collect()).collect()
}

/// The files of `dir` (name → bytes); none when it does not exist.
fn files(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    let Ok(entries) = std::fs::read_dir(dir) else { return BTreeMap::new() };
    entries
        .map(|e| e.unwrap().path())
        .map(|p| (p.file_name().unwrap().to_string_lossy().into_owned(), std::fs::read(&p).unwrap()))
        .collect()
}

/// index.html as `shadowtruth report` renders it from a copy of `dir` whose report.json has
/// timings set to zero and one `created`.
fn page_with_equal_timings(dir: &Path, scratch: &Path) -> Vec<u8> {
    let copy = scratch.join(format!("page-{}", dir.file_name().unwrap().to_string_lossy()));
    std::fs::create_dir_all(copy.join("figures")).unwrap();
    for (name, bytes) in files(&dir.join("figures")) {
        std::fs::write(copy.join("figures").join(name), bytes).unwrap();
    }
    let mut report = report(dir);
    report["created"] = Value::from("2026-01-01T00:00:00Z");
    for scene in report["scenes"].as_array_mut().unwrap() {
        scene["bvh_build_ms"] = Value::from(0.0);
    }
    for run in report["runs"].as_array_mut().unwrap() {
        run["timings"] = serde_json::json!({ "prepare": 0.0, "shade": 0.0, "ns_per_pixel": 0.0 });
    }
    std::fs::write(copy.join("report.json"), report.to_string()).unwrap();
    succeed(&["report", copy.to_str().unwrap()], scratch);
    std::fs::read(copy.join("index.html")).unwrap()
}

/// Asserts that the report folder `got` equals `want` apart from timings.
fn assert_same_folder(want: &Path, got: &Path, scratch: &Path) {
    let what = got.display();
    assert_eq!(without_timings(report(got)), without_timings(report(want)), "{what}: report.json");
    assert_eq!(csv_without_timings(got), csv_without_timings(want), "{what}: report.csv");
    let (want_figures, got_figures) = (files(&want.join("figures")), files(&got.join("figures")));
    assert_eq!(
        got_figures.keys().collect::<Vec<_>>(),
        want_figures.keys().collect::<Vec<_>>(),
        "{what}: figures"
    );
    for (name, bytes) in &want_figures {
        assert!(got_figures[name] == *bytes, "{what}: figures/{name} differs");
    }
    let (want_plots, got_plots) = (files(&want.join("plots")), files(&got.join("plots")));
    assert_eq!(got_plots.keys().collect::<Vec<_>>(), want_plots.keys().collect::<Vec<_>>(), "{what}: plots");
    for (name, bytes) in want_plots.iter().filter(|(name, _)| !name.starts_with("cost_")) {
        assert!(got_plots[name] == *bytes, "{what}: plots/{name} differs");
    }
    // The page is the merged report's, and the whole run's once timings are equal.
    let page = std::fs::read(got.join("index.html")).unwrap();
    let copy = scratch.join("rendered");
    let _ = std::fs::remove_dir_all(&copy);
    std::fs::create_dir_all(&copy).unwrap();
    std::fs::copy(got.join("report.json"), copy.join("report.json")).unwrap();
    std::fs::create_dir_all(copy.join("figures")).unwrap();
    for (name, bytes) in &got_figures {
        std::fs::write(copy.join("figures").join(name), bytes).unwrap();
    }
    succeed(&["report", copy.to_str().unwrap()], scratch);
    assert!(
        std::fs::read(copy.join("index.html")).unwrap() == page,
        "{what}: index.html is not its report's page"
    );
    assert!(
        page_with_equal_timings(got, scratch) == page_with_equal_timings(want, scratch),
        "{what}: index.html"
    );
}

#[test]
fn shard_1_of_1_equals_the_whole_run() {
    let dir = tempfile::tempdir().unwrap();
    write_suite(dir.path());
    run(dir.path(), "whole", &["--quiet"]);
    run(dir.path(), "one", &["--quiet", "--shard", "1/1"]);
    assert_eq!(report(&dir.path().join("one"))["shard"], serde_json::json!({ "index": 1, "count": 1 }));
    succeed(&["merge", "one", "-o", "merged"], dir.path());
    assert_same_folder(&dir.path().join("whole"), &dir.path().join("merged"), dir.path());
    // The shard's own folder is the whole run's plus its `shard`.
    let mut shard = report(&dir.path().join("one"));
    shard.as_object_mut().unwrap().remove("shard");
    assert_eq!(without_timings(shard), without_timings(report(&dir.path().join("whole"))));
}

#[test]
fn shards_merged_equal_the_whole_run() {
    let dir = tempfile::tempdir().unwrap();
    write_suite(dir.path());
    run(dir.path(), "whole", &["--quiet"]);
    assert_eq!(report(&dir.path().join("whole"))["runs"].as_array().unwrap().len(), RUNS);
    // Six shards of five views: the last has none and still writes a folder.
    for count in [2, 3, 4, 6] {
        let mut folders = Vec::new();
        for index in (1..=count).rev() {
            let out = format!("s{count}-{index}");
            run(dir.path(), &out, &["--quiet", "--shard", &format!("{index}/{count}")]);
            let runs = report(&dir.path().join(&out))["runs"].as_array().unwrap().len();
            let views = (0..5).filter(|v| v % count + 1 == index).count();
            assert_eq!(runs, 6 * views, "shard {index}/{count}: views are dealt round-robin");
            folders.push(out);
        }
        let merged = format!("merged{count}");
        let args: Vec<&str> = ["merge"].into_iter().chain(folders.iter().map(String::as_str)).collect();
        succeed(&[&args[..], &["-o", &merged]].concat(), dir.path());
        assert_same_folder(&dir.path().join("whole"), &dir.path().join(&merged), dir.path());
    }
}

/// Cuts `dir/report.json` to its first `runs` runs and removes what is written at the end, as a
/// run killed after its run `runs` leaves the folder.
fn interrupt(dir: &Path, runs: usize) {
    let mut r = report(dir);
    r["runs"].as_array_mut().unwrap().truncate(runs);
    std::fs::write(dir.join("report.json"), serde_json::to_string_pretty(&r).unwrap()).unwrap();
    for file in ["report.csv", "index.html"] {
        std::fs::remove_file(dir.join(file)).unwrap();
    }
    std::fs::remove_dir_all(dir.join("plots")).unwrap();
}

#[test]
fn resume_equals_a_fresh_run_and_keeps_finished_runs() {
    let dir = tempfile::tempdir().unwrap();
    write_suite(dir.path());
    run(dir.path(), "whole", &["--quiet"]);
    let resumed = dir.path().join("resumed");
    run(dir.path(), "resumed", &["--quiet"]);
    // Killed during the third map (runs 7 to 9), and the second map's grid not yet written:
    // the first map's three runs are kept, the second's and third's run again.
    interrupt(&resumed, 7);
    let key = |r: &Value| format!("{}/{}/{}", r["scene"], r["camera"], r["light"]);
    let first = report(&resumed)["runs"][3].clone();
    let grid = std::fs::read_dir(resumed.join("figures"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| {
            let name = p.file_name().unwrap().to_string_lossy().into_owned();
            name.ends_with(".r32.f32.grid.png")
                && name.starts_with(&format!("a.c.{}", first["light"].as_str().unwrap()))
        })
        .expect("the second map's grid");
    assert_eq!(key(&first), key(&report(&resumed)["runs"][0]));
    std::fs::remove_file(grid).unwrap();
    let kept = report(&resumed)["runs"].as_array().unwrap()[..3].to_vec();
    let stdout = run(dir.path(), "resumed", &["--resume"]);
    assert!(stdout.contains("3 finished runs kept, 4 runs of unfinished maps run again"), "{stdout}");
    assert!(
        stdout.contains(&format!("{RUNS} runs in"))
            && stdout.contains(&format!("({} of them run now)", RUNS - 3)),
        "{stdout}"
    );
    // Kept runs are not run again: their timings are the interrupted run's, to the bit.
    assert_eq!(report(&resumed)["runs"].as_array().unwrap()[..3], kept[..]);
    assert_same_folder(&dir.path().join("whole"), &resumed, dir.path());
    // A finished folder resumed runs nothing.
    let stdout = run(dir.path(), "resumed", &["--resume"]);
    assert!(stdout.contains("(0 of them run now)"), "{stdout}");
    assert_same_folder(&dir.path().join("whole"), &resumed, dir.path());
}

#[test]
fn an_interrupted_shard_is_refused_by_merge_then_resumed() {
    let dir = tempfile::tempdir().unwrap();
    write_suite(dir.path());
    run(dir.path(), "whole", &["--quiet"]);
    run(dir.path(), "s1", &["--quiet", "--shard", "1/2"]);
    run(dir.path(), "s2", &["--quiet", "--shard", "2/2"]);
    interrupt(&dir.path().join("s2"), 8);
    let stderr = refused(&["merge", "s1", "s2", "-o", "merged"], dir.path());
    assert!(stderr.contains("s2/report.json: runs: view") && stderr.contains("did not finish"), "{stderr}");
    assert!(!dir.path().join("merged").exists(), "nothing is written for a refused merge");
    let stderr = refused(
        &["run", "scenes", "--plan", "plan.json", "--references", "refs", "-o", "s2", "--resume"],
        dir.path(),
    );
    assert!(stderr.contains("s2/report.json: shard: the folder holds shard 2/2"), "{stderr}");
    run(dir.path(), "s2", &["--quiet", "--shard", "2/2", "--resume"]);
    succeed(&["merge", "s2", "s1", "-o", "merged"], dir.path());
    assert_same_folder(&dir.path().join("whole"), &dir.path().join("merged"), dir.path());
}

#[test]
fn resume_refuses_a_folder_of_another_plan() {
    let dir = tempfile::tempdir().unwrap();
    write_suite(dir.path());
    run(dir.path(), "out", &["--quiet", "--no-figures"]);
    let before = std::fs::read(dir.path().join("out/report.json")).unwrap();
    write_plan(dir.path(), "plan.json", 0.02);
    let stderr = refused(
        &[
            "run",
            "scenes",
            "--plan",
            "plan.json",
            "--references",
            "refs",
            "-o",
            "out",
            "--resume",
            "--no-figures",
        ],
        dir.path(),
    );
    assert!(
        stderr.contains("out/report.json: schedule.identity: the folder holds a run of another plan"),
        "{stderr}"
    );
    // Figures are an option that changes the folder: resuming with them is refused too.
    write_plan(dir.path(), "plan.json", 0.01);
    let stderr = refused(
        &["run", "scenes", "--plan", "plan.json", "--references", "refs", "-o", "out", "--resume"],
        dir.path(),
    );
    assert!(stderr.contains("schedule.identity"), "{stderr}");
    assert!(
        std::fs::read(dir.path().join("out/report.json")).unwrap() == before,
        "the folder is left as it was"
    );
}

#[test]
fn merge_refuses_shards_that_do_not_make_one_run() {
    let dir = tempfile::tempdir().unwrap();
    write_suite(dir.path());
    for (out, shard) in [("s1", "1/3"), ("s2", "2/3"), ("s3", "3/3")] {
        run(dir.path(), out, &["--quiet", "--no-figures", "--shard", shard]);
    }
    run(dir.path(), "whole", &["--quiet", "--no-figures"]);
    write_plan(dir.path(), "other.json", 0.02);
    let args = ["run", "scenes", "--plan", "other.json", "--references", "refs", "--quiet", "--no-figures"];
    succeed(&[&args[..], &["-o", "other3", "--shard", "3/3"]].concat(), dir.path());
    succeed(&[&args[..], &["-o", "s2of2", "--shard", "2/2"]].concat(), dir.path());
    let cases: [(&[&str], &str); 6] = [
        (&["s1", "s2"], "shard: shard 3/3 is missing"),
        (&["s1", "s2", "s2", "s3"], "s2/report.json: shard: shard 2/3 given twice"),
        (&["s1", "s2", "whole"], "whole/report.json: shard: missing: not a shard folder"),
        (&["s1", "s2", "other3"], "other3/report.json: schedule.identity: a shard of another plan"),
        (&["s1", "s2", "s2of2"], "s2of2/report.json: schedule.identity"),
        (&["s1", "s2", "nowhere"], "nowhere: no such report"),
    ];
    for (dirs, message) in cases {
        let stderr = refused(&[&["merge"][..], dirs, &["-o", "merged"]].concat(), dir.path());
        assert!(stderr.contains(message), "merge {dirs:?}: {stderr}");
    }
    // A run moved into another shard's report: the shards overlap.
    let (mut s1, mut s2) = (report(&dir.path().join("s1")), report(&dir.path().join("s2")));
    let moved = s2["runs"].as_array_mut().unwrap().remove(0);
    s1["runs"].as_array_mut().unwrap().push(moved);
    std::fs::write(dir.path().join("s1/report.json"), s1.to_string()).unwrap();
    std::fs::write(dir.path().join("s2/report.json"), s2.to_string()).unwrap();
    let stderr = refused(&["merge", "s1", "s2", "s3", "-o", "merged"], dir.path());
    assert!(
        stderr.contains("s1/report.json: runs[12]: view") && stderr.contains("the shards overlap"),
        "{stderr}"
    );
    let stderr = refused(&["merge", "s1", "s2", "s3", "-o", "s1"], dir.path());
    assert!(!stderr.is_empty());
    assert!(!dir.path().join("merged").exists());
}

#[test]
fn bad_shard_values_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    write_suite(dir.path());
    for (value, message) in [
        ("0/4", "K must be between 1 and N (4)"),
        ("5/4", "K must be between 1 and N (4)"),
        ("1/0", "N must be at least 1"),
        ("x", "'x' is not K/N"),
        ("2", "'2' is not K/N"),
    ] {
        let stderr =
            refused(&["run", "scenes", "--plan", "plan.json", "-o", "out", "--shard", value], dir.path());
        assert!(stderr.contains("--shard") && stderr.contains(message), "--shard {value}: {stderr}");
    }
    assert!(!dir.path().join("out").exists());
}

#[test]
fn a_killed_run_resumes_to_the_fresh_run() {
    let dir = tempfile::tempdir().unwrap();
    write_suite(dir.path());
    run(dir.path(), "whole", &["--quiet"]);
    let args = ["run", "scenes", "--plan", "plan.json", "--references", "refs", "-o", "killed", "--quiet"];
    let mut child = Command::new(env!("CARGO_BIN_EXE_shadowtruth"))
        .args([&args[..], &["--threads", "1"]].concat())
        .current_dir(dir.path())
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    // Killed (SIGKILL) as soon as a run is on disk: in the journal beside report.json.
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(60);
    let runs_journaled = || {
        let bytes = std::fs::read(dir.path().join("killed/report.journal")).unwrap_or_default();
        String::from_utf8_lossy(&bytes).lines().filter(|l| l.starts_with("{\"run\":")).count()
    };
    while runs_journaled() == 0 && child.try_wait().unwrap().is_none() {
        assert!(std::time::Instant::now() < deadline, "the run journaled no run in 60 s");
        std::thread::sleep(std::time::Duration::from_millis(2));
    }
    child.kill().unwrap();
    child.wait().unwrap();
    assert_eq!(report(&dir.path().join("killed"))["schema"], "shadowtruth/report/v1", "a whole report");
    let stdout = run(dir.path(), "killed", &["--resume"]);
    assert!(stdout.contains("resuming killed:"), "{stdout}");
    assert_same_folder(&dir.path().join("whole"), &dir.path().join("killed"), dir.path());
}
