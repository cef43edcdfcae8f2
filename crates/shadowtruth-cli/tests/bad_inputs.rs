//! The bad-input corpus (`tests/bad_inputs/cases.toml`): every case runs the `shadowtruth` binary
//! on a bad file or argument and must exit with its code, never panic, and name the file and
//! the field at fault. All failing cases are listed together;
//! `cases.toml` says what each file must produce.

use serde::Deserialize;
use std::collections::BTreeSet;
use std::path::Path;
use std::process::Command;

#[derive(Deserialize)]
struct Corpus {
    case: Vec<Case>,
}

#[derive(Deserialize)]
struct Case {
    name: String,
    args: Vec<String>,
    exit: i32,
    /// The file the message must name ("" when the problem is a command-line argument).
    file: String,
    /// The field, JSON path or argument the message must name.
    field: String,
}

/// Every command the binary has; each must have bad-input cases.
const COMMANDS: [&str; 14] = [
    "run",
    "reference",
    "verify",
    "export-obj",
    "depth-map",
    "report",
    "gate",
    "papers",
    "island",
    "generate",
    "view-export",
    "score",
    "merge",
    "tune",
];

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for entry in std::fs::read_dir(from).unwrap() {
        let entry = entry.unwrap();
        let target = to.join(entry.file_name());
        if entry.file_type().unwrap().is_dir() {
            copy_dir(&entry.path(), &target);
        } else {
            std::fs::copy(entry.path(), target).unwrap();
        }
    }
}

/// What is wrong with the outcome of `case`, if anything.
fn check(case: &Case, dir: &Path) -> Option<String> {
    let out =
        Command::new(env!("CARGO_BIN_EXE_shadowtruth")).args(&case.args).current_dir(dir).output().unwrap();
    // Errors go to stderr; a gate's verdict (missing runs, violations) to stdout.
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned() + &String::from_utf8_lossy(&out.stdout);
    let code = out.status.code().unwrap_or(-1);
    let mut wrong = Vec::new();
    if stderr.contains("panicked") || code == 101 {
        wrong.push("panicked".to_string());
    }
    if code != case.exit {
        wrong.push(format!("exit {code}, expected {}", case.exit));
    }
    for (what, needle) in [("file", &case.file), ("field", &case.field)] {
        if !stderr.contains(needle.as_str()) {
            wrong.push(format!("message does not name the {what} `{needle}`"));
        }
    }
    (!wrong.is_empty()).then(|| format!("{}: {}\n    stderr: {}", case.name, wrong.join("; "), stderr.trim()))
}

#[test]
fn every_bad_input_exits_with_its_code_naming_the_file_and_field() {
    let source = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/bad_inputs");
    let text = std::fs::read_to_string(source.join("cases.toml")).unwrap();
    let corpus: Corpus = toml::from_str(&text).unwrap();
    assert!(corpus.case.len() >= 60, "only {} cases", corpus.case.len());
    let names: BTreeSet<&str> = corpus.case.iter().map(|c| c.name.as_str()).collect();
    assert_eq!(names.len(), corpus.case.len(), "case names must be unique");

    let work = tempfile::tempdir().unwrap();
    copy_dir(&source, work.path());
    let failures: Vec<String> = corpus.case.iter().filter_map(|c| check(c, work.path())).collect();
    assert!(
        failures.is_empty(),
        "{} of {} cases failed:\n{}",
        failures.len(),
        corpus.case.len(),
        failures.join("\n")
    );
    let commands: BTreeSet<&str> = corpus.case.iter().map(|c| c.args[0].as_str()).collect();
    for command in COMMANDS {
        assert!(commands.contains(command), "no case for `{command}`");
    }
}
