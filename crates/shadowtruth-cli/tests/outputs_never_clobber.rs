//! Outputs never clobber, through the binary: a second process writing into a folder that a live
//! one is writing is refused before it touches anything, and the first one's report and figures
//! stay whole; a killed writer leaves no lock behind; an output path that holds a symbolic link or
//! a folder is refused and left as it is, while a FIFO, `/dev/stdout`, `/dev/null` and `/dev/full`
//! are written into in place and stay what they are; CSV cells that a spreadsheet would run as
//! formulas are neutralised.
//!
//! Only `/dev/null` and `/dev/full` among the real devices are written to (the tests run as root
//! in CI, where replacing a device would break the machine), and both are checked to still be
//! character devices afterwards.

#[path = "../../shadowtruth/tests/common/mod.rs"]
mod common;

use std::os::unix::fs::FileTypeExt;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};

/// The lock file that the reference cache's writers take to record a reference
/// (`src/trace/reference/cache.rs`, `MANIFEST_LOCK_FILE`): held here, it keeps a run from finishing.
const MANIFEST_LOCK_FILE: &str = ".manifest.lock";

/// The lock file of a folder being written (`src/output_lock.rs`, `LOCK_FILE_NAME`).
const FOLDER_LOCK_FILE: &str = ".shadowtruth.lock";

fn binary() -> Command {
    Command::new(env!("CARGO_BIN_EXE_shadowtruth"))
}

fn shadowtruth(args: &[&str], dir: &Path) -> Output {
    binary().args(args).current_dir(dir).output().unwrap()
}

/// Runs `shadowtruth args` in `dir` and checks that it exits 2 without a panic; returns stderr.
fn refused(args: &[&str], dir: &Path) -> String {
    let out = shadowtruth(args, dir);
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(out.status.code(), Some(2), "shadowtruth {args:?}: {stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    stderr
}

/// A scene of one view (`a.json`) and a plan of two techniques at one resolution: a report of two
/// runs and six figures (the reference, each run's technique and error maps, the grid).
fn write_one_view_suite(dir: &Path) {
    common::write_plane_box_scene(&dir.join("a.json"), "a", 1, (32, 24));
    let plan = serde_json::json!({
        "format": "shadowtruth/plan/v1",
        "techniques": [{ "technique": "none" }, { "technique": "constant", "bias_depth": 0.001 }],
        "resolutions": [16], "depth_formats": ["f32"], "repeats": 1
    });
    std::fs::write(dir.join("plan.json"), plan.to_string()).unwrap();
}

const RUN_INTO_OUT: [&str; 7] = ["run", "a.json", "--plan", "plan.json", "-o", "out", "--quiet"];

/// The reference cache's manifest lock in `dir/refs`, taken by this process.
fn hold_cache_manifest(dir: &Path) -> std::fs::File {
    std::fs::create_dir_all(dir.join("refs")).unwrap();
    let file = std::fs::File::create(dir.join("refs").join(MANIFEST_LOCK_FILE)).unwrap();
    fs4::FileExt::lock(&file).unwrap();
    file
}

/// `run` into `dir/out` through the cache `dir/refs`, started, and waited on until its journal
/// holds its scene: it then holds the folder, and cannot end while the cache's manifest is held
/// (it records its reference there before its runs).
fn start_blocked_run(dir: &Path) -> Child {
    let mut child = binary()
        .args([&RUN_INTO_OUT[..], &["--references", "refs"]].concat())
        .current_dir(dir)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // report.json is written when the plan is known, then the built scene is appended to the
    // journal beside it; the next write waits for the cache's manifest.
    let scene_recorded = || {
        let journal = std::fs::read(dir.join("out/report.journal")).unwrap_or_default();
        String::from_utf8_lossy(&journal).lines().any(|l| l.starts_with("{\"scene\":"))
    };
    while !scene_recorded() {
        if let Some(status) = child.try_wait().unwrap() {
            let mut stderr = String::new();
            std::io::Read::read_to_string(&mut child.stderr.take().unwrap(), &mut stderr).unwrap();
            panic!("the first run ended ({status}) before it could be blocked: {stderr}");
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    child
}

fn png_files(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .map(|entries| entries.map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect())
        .unwrap_or_default();
    names.retain(|n| n.ends_with(".png"));
    names.sort();
    names
}

#[test]
fn a_second_writer_of_a_folder_is_refused_and_the_first_stays_whole() {
    let dir = tempfile::tempdir().unwrap();
    write_one_view_suite(dir.path());
    let manifest = hold_cache_manifest(dir.path());
    let mut first = start_blocked_run(dir.path());
    let report_before = std::fs::read(dir.path().join("out/report.json")).unwrap();

    // The second run needs no cache, so nothing but the folder's lock can stop it.
    let stderr = refused(&[&RUN_INTO_OUT[..], &["--no-cache"]].concat(), dir.path());
    assert!(stderr.contains("out: another shadowtruth process"), "{stderr}");
    assert!(stderr.contains(&format!("PID {}", first.id())), "{stderr}");
    assert_eq!(std::fs::read(dir.path().join("out/report.json")).unwrap(), report_before, "untouched");

    drop(manifest);
    let status = first.wait().unwrap();
    assert!(status.success(), "the first run: {status}");
    let report: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.path().join("out/report.json")).unwrap()).unwrap();
    assert_eq!(report["runs"].as_array().unwrap().len(), 2, "the first run's report is whole");
    let figures = png_files(&dir.path().join("out/figures"));
    assert_eq!(figures.len(), 6, "the reference, 2 × (technique, error), the grid: {figures:?}");
    assert!(dir.path().join("out/report.csv").is_file() && dir.path().join("out/index.html").is_file());
    assert!(!dir.path().join("out").join(FOLDER_LOCK_FILE).exists(), "the lock file goes with its lock");
}

#[test]
fn a_killed_writer_leaves_no_lock_behind() {
    let dir = tempfile::tempdir().unwrap();
    write_one_view_suite(dir.path());
    let manifest = hold_cache_manifest(dir.path());
    let mut first = start_blocked_run(dir.path());
    first.kill().unwrap();
    first.wait().unwrap();
    drop(manifest);
    let out = shadowtruth(&[&RUN_INTO_OUT[..], &["--no-cache"]].concat(), dir.path());
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert_eq!(png_files(&dir.path().join("out/figures")).len(), 6);
}

#[test]
fn a_refused_command_leaves_no_folder() {
    let dir = tempfile::tempdir().unwrap();
    refused(&["run", "missing.json", "--no-cache", "-o", "new/out"], dir.path());
    assert!(!dir.path().join("new").exists(), "the folders made to lock the output are removed");
}

/// `gate` of a passing report with `extra` output options, in `dir`.
fn gate(dir: &Path, extra: &[&str]) -> Output {
    let fixtures = common::repo().join("crates/shadowtruth-cli/tests/bad_inputs");
    let report = fixtures.join("reports/good.json");
    let rules = fixtures.join("rules/good.toml");
    let args = [&["gate", report.to_str().unwrap(), "--rules", rules.to_str().unwrap()][..], extra].concat();
    shadowtruth(&args, dir)
}

fn assert_gate_refuses(dir: &Path, option: &str, path: &Path, what: &str) {
    let out = gate(dir, &[option, path.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{option} {}: {stderr}", path.display());
    assert!(stderr.contains(&path.display().to_string()) && stderr.contains(what), "{stderr}");
}

#[test]
fn an_output_that_is_a_link_or_a_folder_is_refused_and_left_as_it_is() {
    let dir = tempfile::tempdir().unwrap();
    let victim = dir.path().join("victim.txt");
    std::fs::write(&victim, "not the tool's").unwrap();
    let link = dir.path().join("junit.xml");
    std::os::unix::fs::symlink(&victim, &link).unwrap();
    assert_gate_refuses(dir.path(), "--junit", &link, "a symbolic link (to a regular file)");
    assert!(std::fs::symlink_metadata(&link).unwrap().file_type().is_symlink(), "still a link");
    assert_eq!(std::fs::read_to_string(&victim).unwrap(), "not the tool's");

    let dangling = dir.path().join("summary.md");
    std::os::unix::fs::symlink(dir.path().join("nowhere"), &dangling).unwrap();
    assert_gate_refuses(dir.path(), "--summary", &dangling, "a symbolic link (to nothing)");
    assert!(!dir.path().join("nowhere").exists());

    let folder = dir.path().join("folder.md");
    std::fs::create_dir(&folder).unwrap();
    assert_gate_refuses(dir.path(), "--summary", &folder, "a folder");
    assert!(folder.is_dir());
}

fn make_fifo(path: &Path) {
    let c_path = std::ffi::CString::new(path.to_str().unwrap()).unwrap();
    // SAFETY: a valid NUL-terminated path; mkfifo only creates the node.
    assert_eq!(unsafe { libc::mkfifo(c_path.as_ptr(), 0o600) }, 0, "mkfifo {}", path.display());
}

fn is_fifo(path: &Path) -> bool {
    std::fs::symlink_metadata(path).unwrap().file_type().is_fifo()
}

fn is_char_device(path: &str) -> bool {
    std::fs::metadata(path).unwrap().file_type().is_char_device()
}

#[test]
fn a_fifo_is_written_into_in_place_and_stays_a_fifo() {
    let dir = tempfile::tempdir().unwrap();
    let fifo: PathBuf = dir.path().join("junit.fifo");
    make_fifo(&fifo);
    let reader = {
        let fifo = fifo.clone();
        std::thread::spawn(move || std::fs::read_to_string(fifo).unwrap())
    };
    let out = gate(dir.path(), &["--junit", fifo.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    let xml = reader.join().unwrap();
    assert!(xml.starts_with("<?xml") && xml.contains("<testsuite"), "{xml}");
    assert!(is_fifo(&fifo), "still a FIFO");
}

#[test]
fn dev_stdout_and_dev_null_are_written_into_and_dev_full_says_no_space() {
    let dir = tempfile::tempdir().unwrap();
    // Here /dev/stdout is the pipe this test reads.
    let out = gate(dir.path(), &["--junit", "/dev/stdout"]);
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(String::from_utf8_lossy(&out.stdout).contains("<testsuite"));

    let out = gate(dir.path(), &["--junit", "/dev/null", "--summary", "/dev/null"]);
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(is_char_device("/dev/null"));

    let out = gate(dir.path(), &["--summary", "/dev/full"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("/dev/full") && stderr.to_lowercase().contains("no space"), "{stderr}");
    assert!(is_char_device("/dev/full"), "/dev/full is still a device");
}

/// A report whose names start as spreadsheet formulas, and one parameter a negative number.
fn formula_report() -> serde_json::Value {
    let text = std::fs::read_to_string(
        common::repo().join("crates/shadowtruth-cli/tests/bad_inputs/reports/good.json"),
    )
    .unwrap();
    let mut report: serde_json::Value = serde_json::from_str(&text).unwrap();
    let run = &mut report["runs"][1];
    run["scene"] = "=HYPERLINK(\"http://x\",\"y\")".into();
    run["camera"] = "+cmd".into();
    run["light"] = "@SUM(A1:A2)".into();
    run["label"] = "-2+3".into();
    run["technique"] = "\tconstant".into();
    run["parameters"]["note"] = "\rtext".into();
    run["parameters"]["bias_depth"] = serde_json::json!(-0.001);
    report
}

#[test]
fn csv_cells_that_start_as_formulas_are_neutralised_and_numbers_stay_numbers() {
    let dir = tempfile::tempdir().unwrap();
    let folder = dir.path().join("r");
    std::fs::create_dir(&folder).unwrap();
    std::fs::write(folder.join("report.json"), formula_report().to_string()).unwrap();
    let out = shadowtruth(&["report", "r"], dir.path());
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = std::fs::read_to_string(folder.join("report.csv")).unwrap();
    let mut reader = csv::Reader::from_reader(text.as_bytes());
    let header = reader.headers().unwrap().clone();
    let rows: Vec<csv::StringRecord> = reader.records().map(Result::unwrap).collect();
    let cell = |column: &str| rows[1][header.iter().position(|c| c == column).unwrap()].to_string();
    assert_eq!(cell("scene"), "'=HYPERLINK(\"http://x\",\"y\")");
    assert_eq!(cell("camera"), "'+cmd");
    assert_eq!(cell("light"), "'@SUM(A1:A2)");
    assert_eq!(cell("label"), "'-2+3");
    assert_eq!(cell("technique"), "'\tconstant");
    assert_eq!(cell("parameters.note"), "'\rtext");
    assert_eq!(cell("parameters.bias_depth"), "-0.001", "a negative number stays a number");
    assert_eq!(cell("counts.false_shadow"), "191");
    // The untouched run keeps its names as they are.
    assert_eq!(rows[0][header.iter().position(|c| c == "scene").unwrap()].to_string(), "good");
}

/// A report folder whose `figures/` links elsewhere is refused before anything is written or
/// removed: the run would otherwise write its figures there, and remove the earlier ones.
#[cfg(unix)]
#[test]
fn a_report_folder_whose_figures_link_elsewhere_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    write_one_view_suite(dir.path());
    let theirs = dir.path().join("pictures");
    std::fs::create_dir(&theirs).unwrap();
    std::fs::write(theirs.join("holiday.png"), b"not ours").unwrap();
    std::fs::create_dir(dir.path().join("out")).unwrap();
    std::os::unix::fs::symlink(&theirs, dir.path().join("out/figures")).unwrap();
    let stderr = refused(&[&RUN_INTO_OUT[..], &["--no-cache"]].concat(), dir.path());
    assert!(stderr.contains("figures is a symbolic link"), "{stderr}");
    assert_eq!(std::fs::read_dir(&theirs).unwrap().count(), 1, "nothing written there");
    assert_eq!(std::fs::read(theirs.join("holiday.png")).unwrap(), b"not ours");
}
