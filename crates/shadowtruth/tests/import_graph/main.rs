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

/// Arrows of known circles in files this check does not yet hold to it, as (importer, imported)
/// pairs of paths below `crates/`. Each one removed here is still printed by the summary; a
/// circle through any other arrow fails. Remove a pair once its circle is opened.
const KNOWN_CIRCLE_ARROWS: &[(&str, &str)] = &[];

/// The library's files that may import `error.rs`: the API that returns `Error`, and the root
/// that re-exports it.
const ERROR_IMPORTERS: [&str; 2] = ["crates/shadowtruth/src/api.rs", "crates/shadowtruth/src/lib.rs"];
const ERROR_FILE: &str = "crates/shadowtruth/src/error.rs";

#[test]
fn no_file_imports_a_file_that_imports_it() {
    let mut failures = String::new();
    for crate_graph in crate_graphs() {
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
