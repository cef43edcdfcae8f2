//! Scene files named on the command line: files as given (a glTF file is a scene of its own),
//! folders expanded to their `*.json` files in name order (a glTF in a folder is usually a
//! scene file's mesh, so it is not a scene there).

use anyhow::{Context, Result, bail};
use std::path::PathBuf;

/// The scene files of `paths`, files and folders in the order given.
pub(super) fn expand_scenes(paths: &[PathBuf]) -> Result<Vec<PathBuf>> {
    let mut out = Vec::new();
    for p in paths {
        if p.is_dir() {
            let mut found: Vec<PathBuf> = std::fs::read_dir(p)
                .with_context(|| format!("reading folder {}", p.display()))?
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|f| f.is_file() && f.extension().is_some_and(|x| x == "json"))
                .collect();
            found.sort();
            if found.is_empty() {
                bail!("{}: no scene files (*.json) in this folder", p.display());
            }
            out.extend(found);
        } else if p.is_file() {
            out.push(p.clone());
        } else {
            bail!("{}: no such scene file or folder", p.display());
        }
    }
    Ok(out)
}

/// The scene files of `paths`, or of `scenes/` when none is given.
pub(super) fn expand_scenes_or_default(paths: &[PathBuf]) -> Result<Vec<PathBuf>> {
    if paths.is_empty() { expand_scenes(&[PathBuf::from("scenes")]) } else { expand_scenes(paths) }
}
