//! The import graph of the workspace's sources: every `use` and every `crate::…` / `super::…`
//! path resolved to the file that defines the name, one graph per crate.
//!
//! No file may import, through any chain, a file that imports it; only the library's API
//! imports its error type. `cargo test -p shadowtruth --test import_graph -- --nocapture`
//! prints each crate's floors, circles, back-arrows and longest files.

mod graph;
mod items;
mod modules;
mod resolve;
mod summary;
mod tokens;
mod workspace;

use workspace::{CrateGraph, crate_graphs};

/// Arrows of the circles still open in the command's `cli`, `plan` and `report` modules, as
/// (importer, imported) pairs of paths below `crates/`: the back-arrows of those circles, so that
/// without them the graph has none. The summary still prints them; a circle through any other
/// arrow fails. Remove a pair once its circle is opened (the check names pairs that no longer
/// match an arrow).
const KNOWN_CIRCLE_ARROWS: &[(&str, &str)] = &[
    // cli.rs ↔ cli/score.rs, cli/tune.rs (set_threads, write_plan_report, expand_scenes).
    ("shadowtruth-cli/src/cli/score.rs", "shadowtruth-cli/src/cli.rs"),
    ("shadowtruth-cli/src/cli/tune.rs", "shadowtruth-cli/src/cli.rs"),
    // plan/spec.rs ↔ plan/file.rs (parse_plan).
    ("shadowtruth-cli/src/plan/spec.rs", "shadowtruth-cli/src/plan/file.rs"),
    // plan/execute.rs ↔ events, select, map_setup, references (PlanError, MapSetting, Event).
    ("shadowtruth-cli/src/plan/execute.rs", "shadowtruth-cli/src/plan/events.rs"),
    ("shadowtruth-cli/src/plan/select.rs", "shadowtruth-cli/src/plan/execute.rs"),
    ("shadowtruth-cli/src/plan/map_setup.rs", "shadowtruth-cli/src/plan/execute.rs"),
    ("shadowtruth-cli/src/plan/references.rs", "shadowtruth-cli/src/plan/execute.rs"),
    // report/outputs.rs (Export) ↔ each output, report/html.rs (escape) ↔ its sections.
    ("shadowtruth-cli/src/report/csv_rows.rs", "shadowtruth-cli/src/report/outputs.rs"),
    ("shadowtruth-cli/src/report/frame_plots.rs", "shadowtruth-cli/src/report/outputs.rs"),
    ("shadowtruth-cli/src/report/frame_plots.rs", "shadowtruth-cli/src/report/plots.rs"),
    ("shadowtruth-cli/src/report/cascades_section.rs", "shadowtruth-cli/src/report/html.rs"),
    ("shadowtruth-cli/src/report/html.rs", "shadowtruth-cli/src/report/outputs.rs"),
    ("shadowtruth-cli/src/report/path_section.rs", "shadowtruth-cli/src/report/html.rs"),
    ("shadowtruth-cli/src/report/html.rs", "shadowtruth-cli/src/report/plots.rs"),
    ("shadowtruth-cli/src/report/html.rs", "shadowtruth-cli/src/report/summary.rs"),
    ("shadowtruth-cli/src/report/outputs.rs", "shadowtruth-cli/src/report/plots.rs"),
    // report/gate/: check.rs → rules.rs → render.rs → check.rs.
    ("shadowtruth-cli/src/report/gate/render.rs", "shadowtruth-cli/src/report/gate/check.rs"),
];

/// The library's files that may import `error.rs`: the API that returns `Error`, and the root
/// that re-exports it.
const ERROR_IMPORTERS: [&str; 2] = ["crates/shadowtruth/src/api.rs", "crates/shadowtruth/src/lib.rs"];
const ERROR_FILE: &str = "crates/shadowtruth/src/error.rs";

#[test]
fn no_file_imports_a_file_that_imports_it() {
    let mut failures = String::new();
    let graphs = crate_graphs();
    for (from, to) in KNOWN_CIRCLE_ARROWS {
        let present =
            graphs.iter().flat_map(|g| g.arrows.keys()).any(|(f, t)| f.ends_with(from) && t.ends_with(to));
        if !present {
            println!("KNOWN_CIRCLE_ARROWS: no arrow {from} → {to} any more: remove the pair");
        }
    }
    for crate_graph in graphs {
        let checked = crate_graph.without_arrows(KNOWN_CIRCLE_ARROWS);
        for circle in checked.graph.circles() {
            failures.push_str(&format!("{}: a circle of {} files:\n", checked.name, circle.len()));
            for &from in &circle {
                for &to in checked.graph.successors[from].iter().filter(|to| circle.contains(to)) {
                    failures.push_str(&format!("    {}\n", checked.arrow_text(from, to)));
                }
            }
        }
    }
    assert!(failures.is_empty(), "files that import, through a chain, a file that imports them:\n{failures}");
}

#[test]
fn only_the_api_imports_the_error_type() {
    let graphs = crate_graphs();
    let library = graphs.iter().find(|g| g.name == "shadowtruth").expect("the library crate");
    let importers: Vec<String> = library
        .arrows
        .iter()
        .filter(|((from, to), _)| {
            to.ends_with(ERROR_FILE) && !ERROR_IMPORTERS.iter().any(|ok| from.ends_with(ok))
        })
        .map(|((from, _), names)| {
            format!("{from} ({})", names.iter().cloned().collect::<Vec<_>>().join(", "))
        })
        .collect();
    assert!(importers.is_empty(), "below the API, files import the error type: {importers:#?}");
}

/// The parser finds the arrows it must: a check that reads nothing would pass the others.
#[test]
fn the_api_is_seen_importing_the_error_type() {
    let graphs = crate_graphs();
    let library = graphs.iter().find(|g| g.name == "shadowtruth").expect("the library crate");
    let api_to_error = library
        .arrows
        .iter()
        .find(|((from, to), _)| from.ends_with(ERROR_IMPORTERS[0]) && to.ends_with(ERROR_FILE));
    assert!(api_to_error.is_some_and(|(_, names)| names.contains("Error")));
}

#[test]
fn summary() {
    let graphs: Vec<CrateGraph> = crate_graphs();
    for crate_graph in &graphs {
        println!("{}", summary::summary(crate_graph));
    }
}
