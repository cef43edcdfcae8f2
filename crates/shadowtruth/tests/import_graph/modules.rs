//! A crate's module tree, from its root file through every `mod x;` declaration, each module
//! with the items its file holds.

use std::collections::BTreeMap;
use std::path::Path;

use crate::items::{FileItems, read_items};
use crate::tokens::tokenize;

pub type ModulePath = Vec<String>;

pub struct Module {
    /// Relative to the workspace root, with `/` separators.
    pub file: String,
    pub lines: usize,
    /// `lib.rs`, `main.rs` or `mod.rs`: its `pub use` lines are the module's face, not imports.
    pub is_facade: bool,
    pub items: FileItems,
}

pub struct CrateTree {
    pub name: String,
    pub modules: BTreeMap<ModulePath, Module>,
    /// The name the crate calls itself by (`extern crate self as NAME;`), besides `crate`.
    pub self_alias: Option<String>,
}

/// The tree of `crates/NAME/src`, from `lib.rs` (or `main.rs` when there is no library).
pub fn load_crate(workspace: &Path, crate_dir: &Path) -> Option<CrateTree> {
    let src = crate_dir.join("src");
    let root = ["lib.rs", "main.rs"].into_iter().map(|name| src.join(name)).find(|file| file.is_file())?;
    let name = crate_dir.file_name()?.to_string_lossy().into_owned();
    let mut tree = CrateTree { name, modules: BTreeMap::new(), self_alias: None };
    add_module(workspace, &mut tree, Vec::new(), &root);
    tree.self_alias = tree.modules.get(&Vec::new()).and_then(|root| root.items.self_alias.clone());
    Some(tree)
}

fn add_module(workspace: &Path, tree: &mut CrateTree, path: ModulePath, file: &Path) {
    let source = std::fs::read_to_string(file).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
    let items = read_items(&tokenize(&source));
    let file_name = file.file_name().unwrap_or_default().to_string_lossy();
    let is_facade = matches!(&*file_name, "lib.rs" | "main.rs" | "mod.rs");
    // Children of `a/b.rs` live in `a/b/`; children of `a/mod.rs` or `lib.rs` beside it.
    let children_dir = match is_facade {
        true => file.parent().unwrap().to_path_buf(),
        false => file.with_extension(""),
    };
    for child in &items.modules {
        let flat = children_dir.join(format!("{child}.rs"));
        let nested = children_dir.join(child).join("mod.rs");
        let Some(child_file) = [flat, nested].into_iter().find(|f| f.is_file()) else {
            panic!("{}: `mod {child};` has no file", file.display())
        };
        let mut child_path = path.clone();
        child_path.push(child.clone());
        add_module(workspace, tree, child_path, &child_file);
    }
    let relative = file.strip_prefix(workspace).unwrap_or(file).to_string_lossy().replace('\\', "/");
    let module = Module { file: relative, lines: source.lines().count(), is_facade, items };
    tree.modules.insert(path, module);
}
