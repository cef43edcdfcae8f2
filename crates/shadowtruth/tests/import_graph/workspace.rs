//! Every crate of the workspace (`crates/*/src`) as a file graph.

use std::path::{Path, PathBuf};

use crate::graph::FileGraph;
use crate::modules::load_crate;
use crate::resolve::{Arrows, crate_arrows, crate_files};
use crate::summary::short;

pub struct CrateGraph {
    pub name: String,
    pub graph: FileGraph,
    /// Line count of each file of `graph.files`.
    pub lines: Vec<usize>,
    pub arrows: Arrows,
    pub unresolved: Vec<String>,
}

impl CrateGraph {
    /// `a.rs → b.rs (Name, Other)`.
    pub fn arrow_text(&self, from: usize, to: usize) -> String {
        let key = (self.graph.files[from].clone(), self.graph.files[to].clone());
        let names: Vec<&str> = self.arrows.get(&key).into_iter().flatten().map(String::as_str).collect();
        format!("{} → {} ({})", short(&self.graph, from), short(&self.graph, to), names.join(", "))
    }
}

pub fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..").canonicalize().expect("the workspace root")
}

pub fn crate_graphs() -> Vec<CrateGraph> {
    let root = workspace_root();
    let mut crate_dirs: Vec<PathBuf> = std::fs::read_dir(root.join("crates"))
        .expect("crates/")
        .map(|entry| entry.expect("an entry of crates/").path())
        .filter(|dir| dir.join("src").is_dir())
        .collect();
    crate_dirs.sort();
    let trees = crate_dirs.iter().filter_map(|dir| load_crate(&root, dir));
    trees
        .map(|tree| {
            let files = crate_files(&tree);
            let found = crate_arrows(&tree);
            let lines =
                files.iter().map(|f| tree.modules.values().find(|m| &m.file == f).unwrap().lines).collect();
            let graph = FileGraph::new(&files, &found.arrows);
            CrateGraph { name: tree.name, graph, lines, arrows: found.arrows, unresolved: found.unresolved }
        })
        .collect()
}
