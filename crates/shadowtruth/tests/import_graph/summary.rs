//! The graph of a crate in words: its floors, its circles with the names that make each arrow,
//! its back-arrows and its longest files.

use std::fmt::Write;

use crate::graph::FileGraph;
use crate::workspace::CrateGraph;

const LONGEST_FILES_SHOWN: usize = 10;

pub fn summary(crate_graph: &CrateGraph) -> String {
    let graph = &crate_graph.graph;
    let floors = graph.floors();
    let circles = graph.circles();
    let back_arrows = graph.back_arrows();
    let arrow_count: usize = graph.successors.iter().map(|s| s.len()).sum();
    let floor_count = floors.iter().max().map_or(0, |top| top + 1);
    let mut out = String::new();
    let _ = writeln!(
        out,
        "crate {}: {} files, {arrow_count} arrows, {floor_count} floors, {} circles, {} back-arrows, {} unresolved paths",
        crate_graph.name,
        graph.files.len(),
        circles.len(),
        back_arrows.len(),
        crate_graph.unresolved.len(),
    );
    for floor in (0..floor_count).rev() {
        let files: Vec<&str> =
            (0..graph.files.len()).filter(|&f| floors[f] == floor).map(|f| short(graph, f)).collect();
        let _ = writeln!(out, "  floor {floor} ({}): {}", files.len(), files.join(", "));
    }
    for (n, circle) in circles.iter().enumerate() {
        let _ = writeln!(out, "  circle {} ({} files):", n + 1, circle.len());
        for &from in circle {
            for &to in graph.successors[from].iter().filter(|to| circle.contains(to)) {
                let _ = writeln!(out, "    {}", crate_graph.arrow_text(from, to));
            }
        }
    }
    for &(from, to) in &back_arrows {
        let _ = writeln!(out, "  back-arrow: {}", crate_graph.arrow_text(from, to));
    }
    for line in &crate_graph.unresolved {
        let _ = writeln!(out, "  unresolved: {line}");
    }
    let _ = writeln!(out, "  longest files: {}", longest_files(crate_graph).join(", "));
    out
}

fn longest_files(crate_graph: &CrateGraph) -> Vec<String> {
    let mut by_length: Vec<(usize, &str)> = crate_graph
        .lines
        .iter()
        .enumerate()
        .map(|(f, &lines)| (lines, short(&crate_graph.graph, f)))
        .collect();
    by_length.sort_by(|a, b| b.0.cmp(&a.0).then(a.1.cmp(b.1)));
    by_length.iter().take(LONGEST_FILES_SHOWN).map(|(lines, file)| format!("{file} {lines}")).collect()
}

/// A file's path below its crate's `src/`.
pub fn short(graph: &FileGraph, file: usize) -> &str {
    let path = graph.files[file].as_str();
    path.split_once("/src/").map_or(path, |(_, below)| below)
}
