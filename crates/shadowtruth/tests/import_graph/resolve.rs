//! Each path a file writes, resolved to the file that defines the name: through modules,
//! through `use` bindings and `pub use` re-exports (globs included) to where the item is
//! written. A name another crate defines resolves to the file of this crate that brings it in.

use std::collections::{BTreeMap, BTreeSet};

use crate::modules::{CrateTree, ModulePath};

/// How deep a chain of bindings may go before it is taken for a loop.
const MAX_HOPS: usize = 32;

pub enum Target {
    Module(ModulePath),
    Item { file: String, name: String },
}

/// File → file arrows, each with the names that make it.
pub type Arrows = BTreeMap<(String, String), BTreeSet<String>>;

pub struct CrateArrows {
    pub arrows: Arrows,
    /// `file: a::b::C` for each path into the crate that names nothing found.
    pub unresolved: Vec<String>,
}

pub fn crate_arrows(tree: &CrateTree) -> CrateArrows {
    let mut out = CrateArrows { arrows: Arrows::new(), unresolved: Vec::new() };
    for (module_path, module) in &tree.modules {
        let uses = module.items.uses.iter().filter(|u| !(u.public && module.is_facade));
        let written =
            uses.map(|u| (&u.segments, u.glob)).chain(module.items.paths.iter().map(|p| (p, false)));
        for (segments, glob) in written {
            let Some(absolute) = absolute_path(tree, module_path, segments, 0) else { continue };
            let arrow = match resolve(tree, &absolute, 0) {
                Some(Target::Item { file, name }) => (file, name),
                Some(Target::Module(target)) if glob => (tree.modules[&target].file.clone(), "*".to_string()),
                Some(Target::Module(_)) => continue,
                None => {
                    out.unresolved.push(format!("{}: {}", module.file, absolute.join("::")));
                    continue;
                }
            };
            if arrow.0 != module.file {
                out.arrows.entry((module.file.clone(), arrow.0)).or_default().insert(arrow.1);
            }
        }
    }
    out
}

/// The path from the crate root that `segments`, written in `module`, names; `None` for a
/// path into another crate (or a local name such as a variable's type).
fn absolute_path(
    tree: &CrateTree,
    module: &ModulePath,
    segments: &[String],
    hops: usize,
) -> Option<ModulePath> {
    let first = segments.first()?.as_str();
    let rest = &segments[1..];
    if first == "crate" || tree.self_alias.as_deref() == Some(first) {
        return Some(rest.to_vec());
    }
    if first == "self" {
        return Some([module.as_slice(), rest].concat());
    }
    if first == "super" {
        let ups = segments.iter().take_while(|s| *s == "super").count();
        let base = module.get(..module.len().checked_sub(ups)?)?;
        return Some([base, &segments[ups..]].concat());
    }
    let child = [module.as_slice(), &segments[..1]].concat();
    if tree.modules.contains_key(&child) {
        return Some([module.as_slice(), segments].concat());
    }
    if hops >= MAX_HOPS {
        return None;
    }
    let items = &tree.modules.get(module)?.items;
    let bound = items.uses.iter().find(|u| !u.glob && u.binding.as_deref() == Some(first))?;
    let base = absolute_path(tree, module, &bound.segments, hops + 1)?;
    Some([base.as_slice(), rest].concat())
}

/// What an absolute path names; `None` when nothing in the crate answers to it.
fn resolve(tree: &CrateTree, path: &[String], hops: usize) -> Option<Target> {
    let mut module_path: ModulePath = Vec::new();
    for (i, segment) in path.iter().enumerate() {
        let child = [module_path.as_slice(), std::slice::from_ref(segment)].concat();
        if tree.modules.contains_key(&child) {
            module_path = child;
            continue;
        }
        if hops >= MAX_HOPS {
            return None;
        }
        let module = &tree.modules[&module_path];
        if module.items.defined.contains(segment) {
            return Some(Target::Item { file: module.file.clone(), name: segment.clone() });
        }
        let bound = module.items.uses.iter().find(|u| !u.glob && u.binding.as_ref() == Some(segment));
        if let Some(binding) = bound {
            let Some(base) = absolute_path(tree, &module_path, &binding.segments, 0) else {
                // Brought in from another crate: this file is where the crate gets it.
                return Some(Target::Item { file: module.file.clone(), name: segment.clone() });
            };
            let target_path = [base.as_slice(), &path[i + 1..]].concat();
            // Re-exported from a file that defines the name out of this parser's sight (inside a
            // macro's expansion): that file still is where it comes from.
            let unseen = || Target::Item { file: deepest_module_file(tree, &base), name: segment.clone() };
            return Some(resolve(tree, &target_path, hops + 1).unwrap_or_else(unseen));
        }
        let globs = module.items.uses.iter().filter(|u| u.glob);
        let through_globs = globs.filter_map(|glob| {
            let base = absolute_path(tree, &module_path, &glob.segments, 0)?;
            resolve(tree, &[base.as_slice(), &path[i..]].concat(), hops + 1)
        });
        return through_globs.into_iter().next();
    }
    Some(Target::Module(module_path))
}

/// The file of the longest module prefix of an absolute path.
fn deepest_module_file(tree: &CrateTree, path: &[String]) -> String {
    let prefixes = (0..=path.len()).rev().map(|n| path[..n].to_vec());
    let module = prefixes.filter_map(|prefix| tree.modules.get(&prefix)).next();
    module.expect("the crate root").file.clone()
}

/// All the files a crate's arrows touch, with every module file even when it has no arrow.
pub fn crate_files(tree: &CrateTree) -> BTreeSet<String> {
    tree.modules.values().map(|m| m.file.clone()).collect()
}
