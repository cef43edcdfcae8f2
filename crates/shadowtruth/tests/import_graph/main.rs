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

use graph::FileGraph;
use workspace::{CrateGraph, crate_graphs};

/// The library's files that may import `error.rs`: the API that returns `Error`, and the root
/// that re-exports it.
const ERROR_IMPORTERS: [&str; 2] = ["crates/shadowtruth/src/api.rs", "crates/shadowtruth/src/lib.rs"];
const ERROR_FILE: &str = "crates/shadowtruth/src/error.rs";

#[test]
fn no_file_imports_a_file_that_imports_it() {
    let mut failures = String::new();
    let graphs = crate_graphs();
    for checked in graphs {
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

/// The circle finder finds a circle of three files and none once an arrow is reversed: a check
/// that cannot see a circle would pass the one above.
#[test]
fn a_circle_of_three_files_is_found() {
    let files: std::collections::BTreeSet<String> = ["a.rs", "b.rs", "c.rs"].map(String::from).into();
    let arrows = |pairs: &[(&str, &str)]| -> resolve::Arrows {
        pairs.iter().map(|(f, t)| ((f.to_string(), t.to_string()), ["Name".to_string()].into())).collect()
    };
    let circle = FileGraph::new(&files, &arrows(&[("a.rs", "b.rs"), ("b.rs", "c.rs"), ("c.rs", "a.rs")]));
    assert_eq!(circle.circles().len(), 1);
    assert_eq!(circle.circles()[0].len(), 3);
    let chain = FileGraph::new(&files, &arrows(&[("a.rs", "b.rs"), ("b.rs", "c.rs"), ("a.rs", "c.rs")]));
    assert!(chain.circles().is_empty());
}
